#pragma once
// The viewer's side of a frame on the GPU: the progressive-refinement sum of HDR frames, the display image of
// the current view mode (internal resolution, linear display values) and its blit to the window. Screenshots
// read the display image, so they hold exactly what the view shows, without the panel.
#include "app/viewer/viewer_settings.h"
#include "renderer/core/aabb.h"
#include "renderer/core/image_io.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"
#include "renderer/render/frame_targets.h"

namespace chcrt::app {

class ViewDisplay {
public:
    ViewDisplay(); // requires a current GL context; compiles the display programs

    // (Re)creates the targets for an internal resolution; clears the accumulation.
    void resize(int width, int height);
    void resetAccumulation();
    // Adds the renderer's HDR output to the sum.
    void accumulate(const FrameTargets& frame);
    // Shows the renderer's frame as it is, without the sum (refinement off: saves a full-screen pass).
    void showSingleFrame() { accumulatedFrames_ = 1; }
    int accumulatedFrames() const { return accumulatedFrames_; }

    // Renders the display image of `settings.viewMode` from the frame's targets; `costHits` is the hit set
    // holding the traversal cost of the traced rays (cost view). `cullingCost`, when not 0, is a CHC+RT cost debug
    // image (R32UI of the display's size, ChcrtDebugImage::Cost) that the cost view shows instead, on the same heat
    // map and `costScale`, so that CHC+RT and pure BVH methods compare.
    void visualize(const FrameTargets& frame, const ViewerSettings& settings, const Aabb& sceneBounds,
                   const HitTargets& costHits, GLuint cullingCost = 0);
    // Shows a CPU image (RGB in [0, 1], rows top to bottom, width × height of the display) as the display image:
    // CHC+RT's colourised debug images.
    void showImage(const std::vector<float>& rgb);
    // Draws the display image over the whole default framebuffer.
    void blitToWindow(int framebufferWidth, int framebufferHeight) const;
    ImageRgba32f readImage() const; // rows top to bottom

    int width() const { return width_; }
    int height() const { return height_; }

private:
    int width_ = 0, height_ = 0;
    int accumulatedFrames_ = 0;
    GlTexture accumHdr_, display_;
    GlFramebuffer accumFbo_, displayFbo_;
    ShaderProgram visualizeProgram_, accumulateProgram_, blitProgram_;
};

} // namespace chcrt::app
