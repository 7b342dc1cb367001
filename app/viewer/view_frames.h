#pragma once
// What the viewer's view modes draw beyond the renderer's shaded frame (view_modes.h): the single shaded frame
// the CPU-coloured views (shafts, residency) start from, the chosen ray set of the cost and CHC+RT debug views, and
// the display image of the G-buffer, cost and debug views.
#include "app/viewer/view_display.h"
#include "app/viewer/viewer_settings.h"
#include "culling/chcrt_tracer.h"
#include "culling/outofcore/out_of_core_tracer.h"
#include "renderer/render/renderer.h"

#include <cstdint>
#include <vector>

namespace chcrt::app {

// The CHC+RT debug image a view mode shows: its own for the debug views; for `cost` the traversal steps summed
// over CHC+RT's subtree passes (CHC+RT writes no per-ray cost target); none otherwise.
ChcrtDebugImage chcrtDebugImageOf(ViewMode mode);

// One shaded frame shown without refinement: the base image of the views drawn over it (residency, shafts).
void showShadedFrame(Renderer& renderer, ViewDisplay& display, const ViewerSettings& settings, const Aabb& sceneBounds,
                     const Camera& camera, FrameStats& stats);
// The displayed image as RGB in [0, 1], rows top to bottom, for the views that colour it on the CPU.
std::vector<float> displayedRgb(const ViewDisplay& display);
// Subtrees resident in the GPU cache now (by file subtree index).
std::vector<uint8_t> residentSubtrees(const outofcore::OutOfCoreTracer& tracer);
// Per subtree of the tracer's file, the level of detail a request is served at from the last frame's view (0 = the
// subtree itself; always 0 for exact methods).
std::vector<uint8_t> subtreeLevels(const outofcore::OutOfCoreTracer& tracer);

// The cost and CHC+RT debug views: the settings' cost ray set traced after the G-buffer (the debug image shows
// only it, not the G-buffer's traced primary rays). `outOfCore`: the tracer when it traces out of core.
void traceChosenRays(Renderer& renderer, ChcrtTracer* chcrt, outofcore::OutOfCoreTracer* outOfCore,
                     const ViewerSettings& settings, const Camera& camera, FrameStats& stats);
// The display image of a G-buffer, cost or CHC+RT debug view (w × h) from the renderer's targets.
void showTracedView(Renderer& renderer, ViewDisplay& display, ChcrtTracer* chcrt, const ViewerSettings& settings,
                    const Aabb& sceneBounds, int w, int h);

} // namespace chcrt::app
