#pragma once
// CHC+RT tracing of a prepared scene out of core (CHC+RT §5.4): the culling hierarchy comes from the file's
// upper part (chs_culling_hierarchy.h), the subtrees from a GpuSubtreeCache under --gpu-cache-mb fed by a
// SubtreeStore under --host-cache-mb. Nothing of the scene has to be in core for tracing; hits carry the
// original triangle ids stored in the file.
//
// Texture units: the cache binds its own node/triangle buffers on the BVH units (CHCRT_UNIT_BVH_*); this
// tracer restores whatever was bound there before, so callers that bound the in-core BVH once (tests, the
// pure-BVH oracle of `chcrt verify`) keep working after an out-of-core trace.
#include "culling/chcrt_tracer.h"
#include "culling/outofcore/gpu_subtree_cache.h"
#include "renderer/outofcore/chs_file.h"
#include "renderer/outofcore/subtree_store.h"

#include <filesystem>
#include <memory>

namespace chcrt::outofcore {

class PrimaryResolve;

struct OutOfCoreOptions {
    uint64_t gpuCacheBytes = 1024ull << 20; // --gpu-cache-mb
    uint64_t hostCacheBytes = 2048ull << 20; // --host-cache-mb
    CachePolicy policy = CachePolicy::Lru;   // --cache-policy
    uint32_t maxUploadsPerTrace = 0;         // viewer streaming (GpuCacheOptions); 0 = complete, exact traces
    // Read-ahead into the host store after each frame (prefetchAfterFrame, subtree_prefetch.h): the frustums of up
    // to this many next cameras and the fronts next to visible pairs; 0 = no prefetch. --prefetch-frames
    uint32_t prefetchFrames = 2;
    uint64_t prefetchBytesPerFrame = 256ull << 20; // at most this much queued per frame; --prefetch-mb
    // chcrt-lod (--lod-pixels): trace a subtree's LOD proxy where its error projects below this many pixels; 0 =
    // exact tracing, proxies never used. > 0 needs a file with proxies (InputError otherwise).
    float lodPixels = 0.0f;
};

// Counters in the shape of CHC+RT Table 3, for one frame or summed (difference of two snapshots).
struct OutOfCoreStats {
    uint64_t queries = 0; // occlusion tests of pairs: GL queries, or pairs tested by batched dispatches
    uint64_t raysTraced = 0;
    double traceMs = 0.0;  // CHC+RT tracing time (phases 1-3), ms
    uint64_t cacheHits = 0, cacheMisses = 0, cacheEvictions = 0, cacheDeferred = 0;
    uint64_t cachePostponed = 0; // requests left for a later trace by the per-trace upload limit (incomplete traces)
    uint64_t uploadedBvhBytes = 0, uploadedGeometryBytes = 0;
    uint64_t proxyUploads = 0, proxyUploadedBytes = 0; // chcrt-lod: of the uploads, LOD proxies (issue #19)
    uint64_t requestsPerLevel[kLodStatLevels] = {};    // subtree requests served per level (0 = the subtree)
    uint64_t uploadsPerLevel[kLodStatLevels] = {};
    uint64_t hostReads = 0, hostBytesRead = 0;
    uint64_t residentBytes = 0, allocatedBytes = 0; // GPU cache, at the snapshot
    uint64_t hostResidentBytes = 0;
    // Prefetch (SubtreeStoreStats): reads by the prefetch thread, first uses of what it read, bytes it read for
    // nothing, queued subtrees it left out for lack of room.
    uint64_t prefetchReads = 0, prefetchHits = 0, prefetchWastedBytes = 0, prefetchSkipped = 0;
    uint64_t peakResidentBytes = 0, hostPeakResidentBytes = 0; // GPU cache, host store: highest since construction
    uint32_t slots = 0, residentSubtrees = 0;
    // `later` minus `earlier` for counters; levels (resident, allocated, slots) from `later`.
    static OutOfCoreStats difference(const OutOfCoreStats& later, const OutOfCoreStats& earlier);
    // Sums the counters; levels from `o` (the later one).
    OutOfCoreStats& operator+=(const OutOfCoreStats& o);
};

class OutOfCoreTracer final : public Tracer {
public:
    // Opens the file, builds its culling hierarchy and the caches (needs a current GL context). `options.adaptive`
    // is ignored: there is no full-scene tracer out of core. Throws InputError for a bad file or a GPU budget
    // that cannot hold one subtree.
    // With options.lodPixels > 0 (chcrt-lod) the file must hold LOD proxies (InputError naming it otherwise).
    OutOfCoreTracer(const std::filesystem::path& file, const OutOfCoreOptions& options, ChcrtOptions chcrt,
                    std::string name = "chcrt");
    ~OutOfCoreTracer() override;

    std::string name() const override { return chcrt_->name(); }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override;

    const ChsFile& file() const { return *file_; }
    ChcrtTracer& chcrt() { return *chcrt_; }
    const GpuSubtreeCache& cache() const { return *cache_; }
    // Whether this tracer traces LOD proxies (chcrt-lod): approximate, and its primary hits must be resolved through
    // it (PrimaryResolve) even when the scene is in core, so that secondary rays start on the surfaces it traces.
    bool lodEnabled() const { return cache_->lodEnabled(); }
    const SubtreeStore& store() const { return *store_; }
    SubtreeStore& store() { return *store_; }
    // Primary rays (closest hit) are traced with ChcrtTracer's "subtrees" debug image, cleared first, so that
    // afterwards it holds 1 + the subtree of each pixel's final hit (PrimaryResolve, primary_resolve.h). Throws
    // InputError at the next trace when another debug image is selected.
    void setRecordPrimarySubtrees(bool record) { recordPrimarySubtrees_ = record; }
    // The G-buffer resolve of a scene that is not in core (primary_resolve.h), created on first use (turns on
    // the recording above).
    PrimaryResolve& primaryResolve();
    const OutOfCoreOptions& options() const { return options_; }
    // Read-ahead for the next frames, called once a frame is rendered (subtree_prefetch.h): queues for the host
    // store's background thread the subtrees of the fronts next to visible pairs (ranked from `current`'s eye) and
    // those entering the frustums of the first options().prefetchFrames of `next` (width × height frames) or in them
    // and asked for since the previous call, leaving out subtrees resident in the GPU cache, up to
    // prefetchBytesPerFrame. Starts the store's next frame. Nothing is queued when prefetchFrames is 0.
    void prefetchAfterFrame(const Camera& current, std::span<const Camera> next, int width, int height);
    // Cumulative counters since construction (take differences for a frame).
    OutOfCoreStats snapshot() const;

private:
    OutOfCoreOptions options_;
    std::unique_ptr<ChsFile> file_;
    std::unique_ptr<SubtreeStore> store_;
    std::unique_ptr<GpuSubtreeCache> cache_;
    std::unique_ptr<ChcrtTracer> chcrt_;
    bool recordPrimarySubtrees_ = false;
    uint64_t frameFirstAcquire_ = 0; // the cache's acquireCount() at the previous prefetchAfterFrame
    std::unique_ptr<PrimaryResolve> primaryResolve_; // last: destroyed first (it uses the tracer)
};

} // namespace chcrt::outofcore
