#include "app/outofcore_report.h"

#include "culling/outofcore/primary_resolve.h"

#include <cstdio>
#include <cstdlib>

namespace chcrt::app {
namespace {

// Per-level counters (index 0 = subtrees, then the file's proxy levels) divided by `n`.
nlohmann::json perLevel(const uint64_t (&counts)[outofcore::kLodStatLevels], uint32_t levels, double n) {
    nlohmann::json list = nlohmann::json::array();
    for (uint32_t l = 0; l < levels && l < outofcore::kLodStatLevels; ++l) list.push_back(double(counts[l]) / n);
    return list;
}

} // namespace

nlohmann::json outOfCoreStatsJson(const outofcore::OutOfCoreStats& s, double frames,
                                  const outofcore::OutOfCoreTracer& tracer) {
    const double n = frames > 0 ? frames : 1.0;
    const double mb = 1.0 / double(1u << 20);
    const outofcore::OutOfCoreOptions& o = tracer.options();
    const uint32_t levels = tracer.file().lodLevels() + 1; // level 0 = the subtrees
    return {{"per_frames", frames},
            {"mrays_per_s", s.traceMs > 0 ? double(s.raysTraced) / (s.traceMs * 1000.0) : 0.0},
            {"trace_ms", s.traceMs / n},
            {"queries", double(s.queries) / n},
            {"mb_transferred_bvh", double(s.uploadedBvhBytes) * mb / n},
            {"mb_transferred_geometry", double(s.uploadedGeometryBytes) * mb / n},
            // chcrt-lod (issue #19): the uploads split into subtrees and LOD proxies, and requests per level
            {"mb_transferred_full", double(s.uploadedBvhBytes + s.uploadedGeometryBytes - s.proxyUploadedBytes) * mb / n},
            {"mb_transferred_proxy", double(s.proxyUploadedBytes) * mb / n},
            {"proxy_uploads", double(s.proxyUploads) / n},
            {"level_requests", perLevel(s.requestsPerLevel, levels, n)},
            {"level_uploads", perLevel(s.uploadsPerLevel, levels, n)},
            {"cache_hits", double(s.cacheHits) / n},
            {"cache_misses", double(s.cacheMisses) / n},
            {"cache_evictions", double(s.cacheEvictions) / n},
            {"cache_deferred", double(s.cacheDeferred) / n},
            {"cache_postponed", double(s.cachePostponed) / n},
            {"host_reads", double(s.hostReads) / n},
            {"mb_read_from_file", double(s.hostBytesRead) * mb / n},
            {"resident_mb", double(s.residentBytes) * mb},
            {"allocated_mb", double(s.allocatedBytes) * mb},
            {"host_resident_mb", double(s.hostResidentBytes) * mb},
            {"peak_resident_mb", double(s.peakResidentBytes) * mb},
            {"host_peak_resident_mb", double(s.hostPeakResidentBytes) * mb},
            {"prefetch_reads", double(s.prefetchReads) / n},
            {"prefetch_hits", double(s.prefetchHits) / n},
            {"prefetch_wasted_mb", double(s.prefetchWastedBytes) * mb / n},
            {"prefetch_skipped", double(s.prefetchSkipped) / n},
            {"prefetch_frames", o.prefetchFrames},
            {"prefetch_mb", double(o.prefetchBytesPerFrame) * mb},
            {"slots", s.slots},
            {"resident_subtrees", s.residentSubtrees},
            {"gpu_cache_mb", double(o.gpuCacheBytes) * mb},
            {"host_cache_mb", double(o.hostCacheBytes) * mb},
            {"policy", outofcore::toString(o.policy)},
            {"file_subtrees", tracer.file().subtrees().size()},
            {"lod_pixels", tracer.lodEnabled() ? nlohmann::json(o.lodPixels) : nlohmann::json(nullptr)},
            {"proxy_slots", tracer.cache().stats().proxySlots}};
}

bool needsOutOfCorePrimary(const outofcore::OutOfCoreTracer& tracer, bool sceneInCore) {
    return !sceneInCore || tracer.lodEnabled();
}

void prefetchAfterFrame(outofcore::OutOfCoreTracer& tracer, const CameraPath& path, const std::vector<int>& frames,
                        size_t index, int width, int height) {
    std::vector<Camera> next;
    for (size_t i = index + 1; i < frames.size() && next.size() < tracer.options().prefetchFrames; ++i) {
        next.push_back(path.cameraAtFrame(frames[i]));
    }
    tracer.prefetchAfterFrame(path.cameraAtFrame(frames[index]), next, width, height);
}

void installOutOfCorePrimary(Renderer& renderer, outofcore::OutOfCoreTracer& tracer) {
    if (renderer.settings().primaryVisibility != PrimaryVisibility::Traced) {
        RenderSettings traced = renderer.settings();
        traced.primaryVisibility = PrimaryVisibility::Traced;
        renderer.setSettings(traced);
    }
    outofcore::PrimaryResolve* resolve = &tracer.primaryResolve(); // now: turns on subtree recording
    renderer.setOutOfCorePrimary([resolve](const Camera& camera, const FrameTargets& targets, float nearPlane) {
        resolve->resolve(camera, targets, nearPlane);
        if (std::getenv("CHCRT_DEBUG_RESOLVE")) { // docs/outofcore.md: per-frame cost of the host lookup
            const outofcore::PrimaryResolveStats& r = resolve->lastStats();
            std::fprintf(stderr, "resolve: %llu hit pixels, %llu subtrees, %llu unresolved, %.1f ms on the host\n",
                         (unsigned long long)r.hitPixels, (unsigned long long)r.subtreesRead,
                         (unsigned long long)r.unresolvedPixels, r.hostMs);
        }
        return resolve->geometricNormalTexture();
    });
}

} // namespace chcrt::app
