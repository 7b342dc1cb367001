#include "culling/outofcore/out_of_core_tracer.h"

#include "culling/outofcore/chs_culling_hierarchy.h"
#include "culling/outofcore/primary_resolve.h"
#include "culling/outofcore/subtree_prefetch.h"
#include "renderer/core/error.h"
#include "shaders/shared/render_layout.h"

#include <cmath>
#include <utility>

namespace chcrt::outofcore {
namespace {

GLuint boundBufferTexture(GLuint unit) {
    GLint previousUnit = 0, texture = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &previousUnit);
    glActiveTexture(GL_TEXTURE0 + unit);
    glGetIntegerv(GL_TEXTURE_BINDING_BUFFER, &texture);
    glActiveTexture(GLenum(previousUnit));
    return GLuint(texture);
}

} // namespace

OutOfCoreStats OutOfCoreStats::difference(const OutOfCoreStats& later, const OutOfCoreStats& earlier) {
    OutOfCoreStats d = later;
    d.queries -= earlier.queries;
    d.raysTraced -= earlier.raysTraced;
    d.traceMs -= earlier.traceMs;
    d.cacheHits -= earlier.cacheHits;
    d.cacheMisses -= earlier.cacheMisses;
    d.cacheEvictions -= earlier.cacheEvictions;
    d.cacheDeferred -= earlier.cacheDeferred;
    d.cachePostponed -= earlier.cachePostponed;
    d.uploadedBvhBytes -= earlier.uploadedBvhBytes;
    d.uploadedGeometryBytes -= earlier.uploadedGeometryBytes;
    d.proxyUploads -= earlier.proxyUploads;
    d.proxyUploadedBytes -= earlier.proxyUploadedBytes;
    for (uint32_t l = 0; l < kLodStatLevels; ++l) {
        d.requestsPerLevel[l] -= earlier.requestsPerLevel[l];
        d.uploadsPerLevel[l] -= earlier.uploadsPerLevel[l];
    }
    d.hostReads -= earlier.hostReads;
    d.hostBytesRead -= earlier.hostBytesRead;
    d.prefetchReads -= earlier.prefetchReads;
    d.prefetchHits -= earlier.prefetchHits;
    d.prefetchWastedBytes -= earlier.prefetchWastedBytes;
    d.prefetchSkipped -= earlier.prefetchSkipped;
    return d;
}

OutOfCoreStats& OutOfCoreStats::operator+=(const OutOfCoreStats& o) {
    const OutOfCoreStats sum = difference(o, OutOfCoreStats{}); // levels of `o`
    queries += sum.queries;
    raysTraced += sum.raysTraced;
    traceMs += sum.traceMs;
    cacheHits += sum.cacheHits;
    cacheMisses += sum.cacheMisses;
    cacheEvictions += sum.cacheEvictions;
    cacheDeferred += sum.cacheDeferred;
    cachePostponed += sum.cachePostponed;
    uploadedBvhBytes += sum.uploadedBvhBytes;
    uploadedGeometryBytes += sum.uploadedGeometryBytes;
    proxyUploads += sum.proxyUploads;
    proxyUploadedBytes += sum.proxyUploadedBytes;
    for (uint32_t l = 0; l < kLodStatLevels; ++l) {
        requestsPerLevel[l] += sum.requestsPerLevel[l];
        uploadsPerLevel[l] += sum.uploadsPerLevel[l];
    }
    hostReads += sum.hostReads;
    hostBytesRead += sum.hostBytesRead;
    prefetchReads += sum.prefetchReads;
    prefetchHits += sum.prefetchHits;
    prefetchWastedBytes += sum.prefetchWastedBytes;
    prefetchSkipped += sum.prefetchSkipped;
    peakResidentBytes = o.peakResidentBytes;
    hostPeakResidentBytes = o.hostPeakResidentBytes;
    residentBytes = o.residentBytes;
    allocatedBytes = o.allocatedBytes;
    hostResidentBytes = o.hostResidentBytes;
    slots = o.slots;
    residentSubtrees = o.residentSubtrees;
    return *this;
}

OutOfCoreTracer::OutOfCoreTracer(const std::filesystem::path& file, const OutOfCoreOptions& options,
                                 ChcrtOptions chcrt, std::string name)
    : options_(options), file_(std::make_unique<ChsFile>(file)) {
    if (options.lodPixels > 0.0f && file_->lodLevels() == 0) {
        throw InputError(name + ": " + file.string() + " has no LOD proxies (prepare it again with chcrt prepare "
                                "--lod-levels N, N > 0)");
    }
    store_ = std::make_unique<SubtreeStore>(*file_, options.hostCacheBytes);
    cache_ = std::make_unique<GpuSubtreeCache>(
        *store_, GpuCacheOptions{options.gpuCacheBytes, options.policy, options.maxUploadsPerTrace, options.lodPixels});
    chcrt.adaptive = false; // no full-scene tracer exists out of core
    chcrt_ = std::make_unique<ChcrtTracer>(buildCullingHierarchy(*file_), *cache_, nullptr, chcrt, std::move(name));
}

OutOfCoreTracer::~OutOfCoreTracer() = default;

PrimaryResolve& OutOfCoreTracer::primaryResolve() {
    if (!primaryResolve_) primaryResolve_ = std::make_unique<PrimaryResolve>(*this);
    return *primaryResolve_;
}

void OutOfCoreTracer::trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                            int height, TraceStats& stats) {
    const GLuint nodes = boundBufferTexture(CHCRT_UNIT_BVH_NODES);
    const GLuint triangles = boundBufferTexture(CHCRT_UNIT_BVH_TRIANGLES);
    const bool record = recordPrimarySubtrees_ && request.rayType == RayType::Primary && !request.anyHit;
    const ChcrtDebugImage selected = chcrt_->debugImageKind();
    if (record && selected != ChcrtDebugImage::None && selected != ChcrtDebugImage::Subtrees) {
        throw InputError("out-of-core primary visibility uses the subtrees debug image; no other can be selected");
    }
    try {
        if (record) {
            chcrt_->setDebugImage(ChcrtDebugImage::Subtrees);
            chcrt_->clearDebugImage();
        }
        cache_->beginTrace();
        // chcrt-lod chooses levels from the frame's camera, the same for every ray type of a frame, so that
        // secondary rays see the surfaces the primary rays hit.
        const float tanHalf = std::tan(0.5f * glm::radians(request.camera.fovYDegrees));
        cache_->setView(request.camera.eye, tanHalf > 0.0f ? 0.5f * float(height) / tanHalf : 0.0f);
        chcrt_->trace(request, rays, hits, width, height, stats);
        if (record) chcrt_->setDebugImage(selected);
    } catch (...) {
        // A subtree that cannot be read (an I/O error, a file truncated or overwritten while it is rendered) fails
        // the trace part way. The caller may go on rendering (the viewer): the interrupted trace's visibility fronts
        // are half updated, so they are dropped (the next trace starts from the root pair, as the first one does),
        // and the GL state the trace changed is left as a finished trace leaves it (ChcrtTracer::endTrace). The GPU
        // cache stays consistent: a slot changes only after its subtree was read.
        chcrt_->resetVisibility();
        glMemoryBarrier(GL_ALL_BARRIER_BITS);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glDisable(GL_DEPTH_TEST);
        if (record) chcrt_->setDebugImage(selected);
        glBindTextureUnit(CHCRT_UNIT_BVH_NODES, nodes);
        glBindTextureUnit(CHCRT_UNIT_BVH_TRIANGLES, triangles);
        throw;
    }
    glBindTextureUnit(CHCRT_UNIT_BVH_NODES, nodes);
    glBindTextureUnit(CHCRT_UNIT_BVH_TRIANGLES, triangles);
}

void OutOfCoreTracer::prefetchAfterFrame(const Camera& current, std::span<const Camera> next, int width, int height) {
    store_->advanceFrame();
    const uint64_t frameFirstAcquire = std::exchange(frameFirstAcquire_, cache_->acquireCount());
    if (options_.prefetchFrames == 0) return;
    std::vector<uint32_t> front;
    chcrt_->collectInvisibleFrontNextToVisible(front);
    const PrefetchRequest request{front, current, next.first(std::min<size_t>(next.size(), options_.prefetchFrames)),
                                  width, height,
                                  [&](uint32_t subtree) { return cache_->acquiredAfter(subtree, frameFirstAcquire); }};
    // Prefetch reads whole subtrees: under chcrt-lod those served as proxies from this view are left out, so that
    // a far view does not fill the host store with subtrees it traces as proxies.
    const std::vector<uint32_t> subtrees =
        choosePrefetchSubtrees(chcrt_->hierarchy(), request, [&](uint32_t subtree) {
            return cache_->isResident(subtree) || (cache_->lodEnabled() && cache_->levelFor(subtree) != 0);
        });
    store_->prefetch(subtrees, options_.prefetchBytesPerFrame);
}

OutOfCoreStats OutOfCoreTracer::snapshot() const {
    OutOfCoreStats s;
    const ChcrtStats& t = chcrt_->totalStats();
    s.queries = t.queries + t.pairsTestedBatched; // Table 3's occlusion queries, whichever form tested the pairs
    s.raysTraced = t.raysTraced;
    s.traceMs = t.totalMs();
    const GpuCacheStats& c = cache_->stats();
    s.cacheHits = c.hits;
    s.cacheMisses = c.misses;
    s.cacheEvictions = c.evictions;
    s.cacheDeferred = c.deferred;
    s.cachePostponed = c.postponed;
    s.uploadedBvhBytes = c.uploadedNodeBytes;
    s.uploadedGeometryBytes = c.uploadedTriangleBytes;
    s.proxyUploads = c.proxyUploads;
    s.proxyUploadedBytes = c.proxyUploadedBytes;
    for (uint32_t l = 0; l < kLodStatLevels; ++l) {
        s.requestsPerLevel[l] = c.requestsPerLevel[l];
        s.uploadsPerLevel[l] = c.uploadsPerLevel[l];
    }
    s.residentBytes = c.residentBytes;
    s.allocatedBytes = c.allocatedBytes;
    s.slots = c.slots;
    s.residentSubtrees = c.residentSubtrees;
    s.peakResidentBytes = c.peakResidentBytes;
    const SubtreeStoreStats h = store_->stats();
    s.hostReads = h.misses;
    s.hostBytesRead = h.bytesRead;
    s.hostResidentBytes = h.residentBytes;
    s.hostPeakResidentBytes = h.peakResidentBytes;
    s.prefetchReads = h.prefetched;
    s.prefetchHits = h.prefetchHits;
    s.prefetchWastedBytes = h.prefetchWastedBytes;
    s.prefetchSkipped = h.prefetchSkipped;
    return s;
}

} // namespace chcrt::outofcore
