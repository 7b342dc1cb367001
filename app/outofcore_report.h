#pragma once
// JSON of the out-of-core statistics (CHC+RT Table 3: Mrays/s, queries, MB transferred BVH / geometry, cache
// hits/misses/evictions, resident MB) for `chcrt bench --json` rows and `--stats-json` (docs/outofcore.md).
#include "culling/outofcore/out_of_core_tracer.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/camera_path.h"

#include <nlohmann/json.hpp>

namespace chcrt::app {

// Counters divided by `frames` (per-frame means; 1 = the counters themselves); levels as they are.
nlohmann::json outOfCoreStatsJson(const outofcore::OutOfCoreStats& stats, double frames,
                                  const outofcore::OutOfCoreTracer& tracer);

// --prefetch-frames: once frame `frames[index]` of `path` is rendered, `tracer` reads ahead for the frames after it
// in `frames` (OutOfCoreTracer::prefetchAfterFrame; the last frame has none, so only its fronts are read ahead).
void prefetchAfterFrame(outofcore::OutOfCoreTracer& tracer, const CameraPath& path, const std::vector<int>& frames,
                        size_t index, int width, int height);

// A scene that is not in core (docs/outofcore.md): the renderer's traced G-buffer is resolved through
// `tracer`'s recorded subtrees (outofcore::PrimaryResolve) and secondary rays read per-pixel geometric normals.
// Switches the renderer to traced primary visibility; `tracer` must trace the G-buffer's primary rays (it must
// outlive the renderer's use of it).
void installOutOfCorePrimary(Renderer& renderer, outofcore::OutOfCoreTracer& tracer);
// Whether the renderer's G-buffer must come from `tracer` (installOutOfCorePrimary): a scene not in core, or a tracer
// of LOD proxies (chcrt-lod), whose secondary rays must start on the proxy surfaces its primary rays hit (an exact
// G-buffer under a proxy that lies above it would shadow itself).
bool needsOutOfCorePrimary(const outofcore::OutOfCoreTracer& tracer, bool sceneInCore);

} // namespace chcrt::app
