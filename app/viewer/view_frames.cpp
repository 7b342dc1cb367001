#include "app/viewer/view_frames.h"

#include "renderer/gl/gl.h"

#include <algorithm>

namespace chcrt::app {

ChcrtDebugImage chcrtDebugImageOf(ViewMode mode) {
    switch (mode) {
    case ViewMode::Overdraw: return ChcrtDebugImage::Overdraw;
    case ViewMode::Subtrees: return ChcrtDebugImage::Subtrees;
    case ViewMode::Batches: return ChcrtDebugImage::Batches;
    case ViewMode::Bounds: return ChcrtDebugImage::Bounds;
    case ViewMode::Cost: return ChcrtDebugImage::Cost;
    default: return ChcrtDebugImage::None;
    }
}

void showShadedFrame(Renderer& renderer, ViewDisplay& display, const ViewerSettings& settings, const Aabb& sceneBounds,
                     const Camera& camera, FrameStats& stats) {
    stats = renderer.renderFrame(camera);
    display.showSingleFrame();
    ViewerSettings shadedSettings = settings;
    shadedSettings.viewMode = ViewMode::Shaded;
    display.visualize(renderer.targets(), shadedSettings, sceneBounds, renderer.targets().hits[0]);
}

std::vector<float> displayedRgb(const ViewDisplay& display) {
    const ImageRgba32f image = display.readImage();
    const size_t pixels = size_t(image.width) * size_t(image.height);
    std::vector<float> rgb(pixels * 3);
    for (size_t i = 0; i < pixels; ++i) {
        for (int k = 0; k < 3; ++k) rgb[i * 3 + size_t(k)] = std::clamp(image.pixels[i * 4 + size_t(k)], 0.0f, 1.0f);
    }
    return rgb;
}

std::vector<uint8_t> residentSubtrees(const outofcore::OutOfCoreTracer& tracer) {
    std::vector<uint8_t> resident(tracer.file().subtrees().size(), 0);
    const outofcore::GpuSubtreeCache& cache = tracer.cache();
    for (uint32_t slot = 0; slot < cache.slotCount(); ++slot) {
        const uint32_t subtree = cache.slotSubtree(slot);
        if (subtree < resident.size()) resident[subtree] = 1;
    }
    return resident;
}

std::vector<uint8_t> subtreeLevels(const outofcore::OutOfCoreTracer& tracer) {
    const outofcore::GpuSubtreeCache& cache = tracer.cache();
    std::vector<uint8_t> levels(tracer.file().subtrees().size(), 0);
    for (uint32_t s = 0; s < levels.size(); ++s) levels[s] = uint8_t(cache.levelFor(s));
    return levels;
}

// Out of core the tracer records the primary rays' subtrees in the debug image for the G-buffer resolve: the
// chosen image (for `cost`, CHC+RT's cost image) is selected here and the recording paused for this one trace
// (each image's shader variants are compiled once and kept).
void traceChosenRays(Renderer& renderer, ChcrtTracer* chcrt, outofcore::OutOfCoreTracer* outOfCore,
                     const ViewerSettings& settings, const Camera& camera, FrameStats& stats) {
    const ChcrtDebugImage kind = chcrtDebugImageOf(settings.viewMode);
    if (chcrt && kind != ChcrtDebugImage::None) {
        if (outOfCore) chcrt->setDebugImage(kind);
        chcrt->clearDebugImage();
    }
    if (outOfCore) outOfCore->setRecordPrimarySubtrees(false);
    try {
        renderer.generateRayPass(camera, settings.costRayType, 0, stats);
        renderer.traceRayPass(camera, settings.costRayType, 0, stats);
    } catch (...) {
        if (outOfCore) outOfCore->setRecordPrimarySubtrees(true);
        throw;
    }
    if (outOfCore) outOfCore->setRecordPrimarySubtrees(true);
}

void showTracedView(Renderer& renderer, ViewDisplay& display, ChcrtTracer* chcrt, const ViewerSettings& settings,
                    const Aabb& sceneBounds, int w, int h) {
    const bool sized = chcrt && chcrt->debugTexture() != 0 && chcrt->debugWidth() == w && chcrt->debugHeight() == h;
    if (isChcrtDebugMode(settings.viewMode)) {
        display.showImage(sized ? colorizeChcrtDebugImage(chcrt->debugImageKind(), chcrt->readDebugImage(), w, h)
                                : std::vector<float>(size_t(w) * h * 3, 0.0f));
        return;
    }
    // CHC+RT's cost view: its cost debug image on the pure tracer's heat map and scale.
    const bool cullingCost =
        settings.viewMode == ViewMode::Cost && sized && chcrt->debugImageKind() == ChcrtDebugImage::Cost;
    if (cullingCost) glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT); // the image stores, read as a texture
    display.visualize(renderer.targets(), settings, sceneBounds, renderer.targets().hits[0],
                      cullingCost ? chcrt->debugTexture() : 0);
}

} // namespace chcrt::app
