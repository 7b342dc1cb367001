#include "app/viewer/view_modes.h"

#include "renderer/core/error.h"

namespace chcrt::app {

const std::vector<ViewMode>& allViewModes() {
    static const std::vector<ViewMode> modes = {ViewMode::Shaded, ViewMode::Position, ViewMode::Normal,
                                                ViewMode::Albedo, ViewMode::TriangleId, ViewMode::Depth,
                                                ViewMode::Cost, ViewMode::Overdraw, ViewMode::Subtrees,
                                                ViewMode::Batches, ViewMode::Bounds, ViewMode::Shafts,
                                                ViewMode::Residency, ViewMode::Lod};
    return modes;
}

const char* toString(ViewMode mode) {
    switch (mode) {
    case ViewMode::Shaded: return "shaded";
    case ViewMode::Position: return "position";
    case ViewMode::Normal: return "normal";
    case ViewMode::Albedo: return "albedo";
    case ViewMode::TriangleId: return "triangle";
    case ViewMode::Depth: return "depth";
    case ViewMode::Cost: return "cost";
    case ViewMode::Overdraw: return "overdraw";
    case ViewMode::Subtrees: return "subtrees";
    case ViewMode::Batches: return "batches";
    case ViewMode::Bounds: return "bounds";
    case ViewMode::Shafts: return "shafts";
    case ViewMode::Residency: return "residency";
    case ViewMode::Lod: return "lod";
    }
    return "?";
}

const char* describe(ViewMode mode) {
    switch (mode) {
    case ViewMode::Shaded: return "the composed, tone-mapped frame";
    case ViewMode::Position: return "G-buffer world position, scaled to the scene bounds";
    case ViewMode::Normal: return "G-buffer normal (facing the camera), 0.5 + 0.5 n";
    case ViewMode::Albedo: return "G-buffer base colour";
    case ViewMode::TriangleId: return "original triangle id, hashed to a colour";
    case ViewMode::Depth: return "linear view depth, log scale over the scene diagonal";
    case ViewMode::Cost:
        return "BVH traversal steps per ray (inner nodes + leaves + triangles; CHC+RT: summed over its subtree "
               "passes), heat map";
    case ViewMode::Overdraw: return "CHC+RT: occlusion-query fragments per pixel, heat map (paper Figure 4)";
    case ViewMode::Subtrees: return "CHC+RT: termination subtree that produced each hit, hashed colour (Figure 5)";
    case ViewMode::Batches: return "CHC+RT: subtrees traversed per pixel over all batches, heat map (Figure 5)";
    case ViewMode::Bounds:
        return "CHC+RT: the ray bounds grid's cells, coloured by the t extent of their rays' segments (their t_best "
               "once hits bound them), log heat map; magenta = unbounded";
    case ViewMode::Shafts:
        return "Line Space of the picked node (click): green = the pixel's ray lies in an empty shaft, red = filled";
    case ViewMode::Residency:
        return "out of core: primary hit's subtree resident in the GPU cache before the frame (green) or uploaded "
               "this frame (orange); one shade per subtree, dark subtree boundaries";
    case ViewMode::Lod:
        return "out of core, chcrt-lod: the level of detail of the primary hit's subtree, the subtree itself (grey-blue) "
               "or a proxy (levels 1-4, green to red as they coarsen); set --lod-pixels with its slider";
    }
    return "";
}

ViewMode parseViewMode(const std::string& name) {
    std::string names;
    for (ViewMode mode : allViewModes()) {
        if (name == toString(mode)) return mode;
        names += (names.empty() ? "" : ", ") + std::string(toString(mode));
    }
    throw InputError("unknown view mode '" + name + "' (available: " + names + ")");
}

bool isGBufferMode(ViewMode mode) {
    return mode != ViewMode::Shaded && mode != ViewMode::Cost && mode != ViewMode::Shafts &&
           mode != ViewMode::Residency && mode != ViewMode::Lod && !isChcrtDebugMode(mode);
}

bool isChcrtDebugMode(ViewMode mode) {
    return mode == ViewMode::Overdraw || mode == ViewMode::Subtrees || mode == ViewMode::Batches ||
           mode == ViewMode::Bounds;
}

} // namespace chcrt::app
