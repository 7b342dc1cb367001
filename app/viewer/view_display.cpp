#include "app/viewer/view_display.h"

#include "renderer/render/frame_targets.h"
#include "shaders/shared/render_layout.h"
#include "shaders/shared/viewer_layout.h"

#include <algorithm>

namespace chcrt::app {
namespace {

static_assert(int(ViewMode::Shaded) == CHCRT_VIEW_SHADED && int(ViewMode::Position) == CHCRT_VIEW_POSITION &&
              int(ViewMode::Normal) == CHCRT_VIEW_NORMAL && int(ViewMode::Albedo) == CHCRT_VIEW_ALBEDO &&
              int(ViewMode::TriangleId) == CHCRT_VIEW_TRIANGLE && int(ViewMode::Depth) == CHCRT_VIEW_DEPTH &&
              int(ViewMode::Cost) == CHCRT_VIEW_COST,
              "ViewMode must match shaders/shared/viewer_layout.h");

ShaderProgram makeFullscreenProgram(const char* fragment) {
    return ShaderProgram({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"}, {GL_FRAGMENT_SHADER, fragment}});
}

} // namespace

ViewDisplay::ViewDisplay()
    : visualizeProgram_(makeFullscreenProgram("viewer/visualize.frag.glsl")),
      accumulateProgram_(makeFullscreenProgram("viewer/accumulate_frame.frag.glsl")),
      blitProgram_(makeFullscreenProgram("viewer/blit.frag.glsl")) {}

void ViewDisplay::resize(int width, int height) {
    width_ = width;
    height_ = height;
    accumHdr_ = createTexture2D(width, height, GL_RGBA32F);
    GLuint id = accumHdr_.id();
    accumFbo_ = createFramebuffer(&id, 1);
    display_ = createTexture2D(width, height, GL_RGBA32F);
    // The window may be larger than the internal resolution: scale bilinearly.
    glTextureParameteri(display_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(display_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(display_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(display_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    id = display_.id();
    displayFbo_ = createFramebuffer(&id, 1);
    resetAccumulation();
}

void ViewDisplay::resetAccumulation() {
    const float zero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(accumFbo_.id(), GL_COLOR, 0, zero);
    accumulatedFrames_ = 0;
}

void ViewDisplay::accumulate(const FrameTargets& frame) {
    glBindFramebuffer(GL_FRAMEBUFFER, accumFbo_.id());
    glViewport(0, 0, width_, height_);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    accumulateProgram_.use();
    glBindTextureUnit(CHCRT_VIEWER_UNIT_SOURCE, frame.outputHdr.id());
    drawFullscreenTriangle();
    glDisable(GL_BLEND);
    ++accumulatedFrames_;
}

void ViewDisplay::showImage(const std::vector<float>& rgb) {
    std::vector<float> rgba(size_t(width_) * height_ * 4, 1.0f);
    for (int y = 0; y < height_ && rgb.size() >= size_t(width_) * height_ * 3; ++y) {
        const size_t source = size_t(height_ - 1 - y) * width_ * 3; // GL rows bottom to top
        for (int x = 0; x < width_; ++x) {
            for (int c = 0; c < 3; ++c) rgba[(size_t(y) * width_ + x) * 4 + c] = rgb[source + size_t(x) * 3 + c];
        }
    }
    glTextureSubImage2D(display_.id(), 0, 0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba.data());
}

void ViewDisplay::visualize(const FrameTargets& frame, const ViewerSettings& settings, const Aabb& bounds,
                            const HitTargets& costHits, GLuint cullingCost) {
    glBindFramebuffer(GL_FRAMEBUFFER, displayFbo_.id());
    glViewport(0, 0, width_, height_);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    const ShaderProgram& p = visualizeProgram_;
    p.use();
    p.set("viewMode", int(settings.viewMode));
    p.set("accumulatedFrames", accumulatedFrames_);
    p.set("exposure", settings.common.render.exposure);
    p.set("sceneLower", bounds.lower);
    p.set("sceneExtent", bounds.extent());
    p.set("sceneDiagonal", bounds.diagonal());
    p.set("costScale", settings.costScale);
    p.set("useCullingCost", int(cullingCost != 0));
    glBindTextureUnit(CHCRT_VIEWER_UNIT_DISPLAY, frame.outputDisplay.id());
    glBindTextureUnit(CHCRT_VIEWER_UNIT_ACCUM, accumHdr_.id());
    glBindTextureUnit(CHCRT_VIEWER_UNIT_COST, costHits.cost.id());
    // Binding 0 would unbind every target of the unit (its number is shared with renderer units).
    if (cullingCost != 0) glBindTextureUnit(CHCRT_VIEWER_UNIT_CULLING_COST, cullingCost);
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_POSITION, frame.gbufferPosition.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_NORMAL, frame.gbufferNormal.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_ALBEDO, frame.gbufferAlbedo.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_TRIANGLE, frame.gbufferTriangle.id());
    drawFullscreenTriangle();
}

void ViewDisplay::blitToWindow(int framebufferWidth, int framebufferHeight) const {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, framebufferWidth, framebufferHeight);
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_SCISSOR_TEST);
    blitProgram_.use();
    glBindTextureUnit(CHCRT_VIEWER_UNIT_SOURCE, display_.id());
    drawFullscreenTriangle();
}

ImageRgba32f ViewDisplay::readImage() const {
    ImageRgba32f image{width_, height_, std::vector<float>(size_t(width_) * height_ * 4)};
    glGetTextureImage(display_.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(image.pixels.size() * sizeof(float)),
                      image.pixels.data());
    const size_t row = size_t(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y) { // GL rows are bottom to top
        std::swap_ranges(image.pixels.begin() + y * row, image.pixels.begin() + (y + 1) * row,
                         image.pixels.end() - (y + 1) * row);
    }
    return image;
}

} // namespace chcrt::app
