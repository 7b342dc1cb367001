#pragma once
// The viewer's view modes. Only modes that work are listed: the shaded image, the G-buffer channels, the BVH
// traversal cost per pixel (heat map of the tracer's cost output, shaders/shared/render_layout.h) and CHC+RT's
// debug images (ChcrtTracer::setDebugImage; CHC+RT Figures 4 and 5) of the rays chosen for the cost view, and
// the binary Line Space shafts of a picked node (app/viewer/shaft_view.h), and out of core the GPU-cache
// residency of each pixel's primary hit and the level of detail it was traced at (app/viewer/residency_view.h).
#include <string>
#include <vector>

namespace chcrt::app {

enum class ViewMode { Shaded, Position, Normal, Albedo, TriangleId, Depth, Cost, Overdraw, Subtrees, Batches,
                      Bounds, Shafts, Residency, Lod };

const std::vector<ViewMode>& allViewModes();
const char* toString(ViewMode mode);            // "shaded", "position", ..., "cost"
const char* describe(ViewMode mode);            // one line for the panel
ViewMode parseViewMode(const std::string& name); // throws InputError listing the modes
// Modes that need only the G-buffer (no rays, no shading).
bool isGBufferMode(ViewMode mode);
// CHC+RT debug images (need a CHC+RT method; other methods show black).
bool isChcrtDebugMode(ViewMode mode);

} // namespace chcrt::app
