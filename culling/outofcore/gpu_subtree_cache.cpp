#include "culling/outofcore/gpu_subtree_cache.h"

#include "renderer/core/aabb.h"
#include "renderer/core/error.h"
#include "renderer/gl/context.h"
#include "renderer/outofcore/gpu_cache_slots.h"
#include "shaders/shared/culling_layout.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <cmath>

namespace chcrt::outofcore {

CachePolicy parseCachePolicy(const std::string& text) {
    if (text == "round-robin" || text == "rr") return CachePolicy::RoundRobin;
    if (text == "lru") return CachePolicy::Lru;
    throw InputError("--cache-policy " + text + ": expected round-robin or lru");
}

const char* toString(CachePolicy policy) { return policy == CachePolicy::Lru ? "lru" : "round-robin"; }

GpuSubtreeCache::GpuSubtreeCache(SubtreeStore& store, const GpuCacheOptions& options)
    : store_(store), options_(options), compact_(store.file().compact()) {
    const ChsFile& file = store.file();
    const ChsHeader& h = file.header();
    // The budget is clamped to what one texture buffer addresses and to the GPU memory the driver reports
    // (renderer/outofcore/gpu_cache_slots.h), so a budget beyond them allocates what fits instead of failing.
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    GpuCacheLimits limits{uint64_t(std::max(maxTexels, 0)), queryGpuMemory().availableBytes};
    const uint64_t budget = gpuCacheBudget(options.budgetBytes, limits);
    Pool subtrees;
    subtrees.slotNodes = nodeUnits(h.maxSubtreeNodes);
    subtrees.slotTriangles = std::max(1u, h.maxSubtreeTriangles);
    subtrees.slotVertices = file.maxSubtreeVertices();
    const uint64_t slotBytes = shapeOf(subtrees).bytes();
    // chcrt-lod: a pool per proxy level, each of up to kLodPoolShare of the budget and at most what all of that
    // level's proxies take packed (packed_ring.h), split among the buffers as those proxies need them, but never at
    // the cost of the one subtree slot that tracing needs.
    std::vector<Pool> proxyPools;
    uint64_t proxyBytes = 0, proxyNodeTexels = 0, proxyTriangleTexels = 0, proxyVertices = 0;
    if (lodEnabled()) {
        for (uint32_t level = 1; level <= file.lodLevels(); ++level) {
            PackedRing::Units demand{};
            uint64_t demandBytes = 0, proxies = 0;
            for (uint32_t s = 0; s < h.subtreeCount; ++s) {
                if (file.lodRecord(s, level).nodeCount == 0) continue;
                const PackedRing::Units units = proxyUnits(s, level);
                for (size_t p = 0; p < units.size(); ++p) demand[p] += units[p];
                demandBytes += GpuSlotShape{units[0], units[1], units[2], compact_}.bytes();
                ++proxies;
            }
            const double share = level == file.lodLevels() ? kLodCoarsestPoolShare : kLodPoolShare;
            const uint64_t left = budget > slotBytes + proxyBytes ? budget - slotBytes - proxyBytes : 0; // one subtree slot stays
            const uint64_t bytes = std::min({demandBytes, uint64_t(double(budget) * share), left});
            PackedRing::Units capacity{};
            for (size_t p = 0; p < capacity.size(); ++p) {
                capacity[p] = bytes == demandBytes ? demand[p] : uint64_t(double(demand[p]) * double(bytes) / double(demandBytes));
            }
            Pool pool;
            pool.ring.emplace(capacity, h.subtreeCount);
            pool.slotKey.assign(h.subtreeCount, kNotResident);
            const GpuSlotShape extent = extentOf(pool);
            proxyBytes += extent.bytes();
            proxyNodeTexels += extent.nodeTexels();
            proxyTriangleTexels += extent.triangleTexels();
            proxyVertices += extent.vertices;
            if (demandBytes != 0) {
                stats_.proxySlots += uint32_t(std::min<uint64_t>(proxies, extent.bytes() * proxies / demandBytes));
            }
            proxyPools.push_back(std::move(pool));
        }
    }
    if (limits.maxTextureBufferTexels != 0) {
        const uint64_t used = std::max({proxyNodeTexels, proxyTriangleTexels, proxyVertices});
        limits.maxTextureBufferTexels = limits.maxTextureBufferTexels > used ? limits.maxTextureBufferTexels - used : 1;
    }
    limits.availableGpuBytes = 0; // applied to `budget` above
    const uint64_t slots = gpuCacheSlots(budget > proxyBytes ? budget - proxyBytes : 0, shapeOf(subtrees),
                                         h.subtreeCount, limits);
    if (slots == 0) {
        throw InputError("--gpu-cache-mb " + std::to_string(options.budgetBytes >> 20) +
                         " is too small to hold one subtree of " + file.path().string() + " (needs " +
                         std::to_string((slotBytes + (1u << 20) - 1) >> 20) + " MB; prepare with smaller --subtree-triangles)");
    }
    subtrees.slotKey.assign(slots, kNotResident);
    slotEpochs_.assign(slots, 0u);
    pools_.push_back(std::move(subtrees));
    for (Pool& p : proxyPools) pools_.push_back(std::move(p));
    // Pools one after another in each buffer: the subtree pool first (slot k's root = k × slotNodes, as without LOD).
    uint64_t nodes = 0, triangles = 0, vertices = 0;
    for (Pool& p : pools_) {
        p.firstNode = nodes;
        p.firstTriangle = triangles;
        p.firstVertex = vertices;
        const GpuSlotShape extent = extentOf(p);
        nodes += extent.nodes;
        triangles += extent.triangles;
        vertices += extent.vertices;
        p.lastUse.assign(p.slotKey.size(), 0);
        p.pinned.assign(p.slotKey.size(), 0);
        p.slotOf.assign(h.subtreeCount, kNotResident);
    }
    stats_.slots = slotCount() + stats_.proxySlots;
    lastAcquired_.assign(h.subtreeCount, 0);
    const GpuSlotShape total{nodes, triangles, vertices, compact_};
    nodes_ = createTextureBuffer(nullptr, total.nodeBytes(), compact_ ? GL_RGBA32UI : GL_RGBA32F);
    triangles_ = createTextureBuffer(nullptr, total.triangleBytes(), compact_ ? GL_RGBA32UI : GL_RGBA32F);
    if (compact_) vertices_ = createTextureBuffer(nullptr, total.vertexBytes(), GL_RGB32F);
    stats_.allocatedBytes = nodes_.bytes + triangles_.bytes + vertices_.bytes;
    if (stats_.allocatedBytes > options.budgetBytes) throw std::logic_error("GPU cache allocation exceeds its budget");
}

uint32_t GpuSubtreeCache::nodeUnits(uint32_t nodes) const { return uint32_t(gpuEntryShape(nodes, 0, 0, compact_).nodes); }

GpuSlotShape GpuSubtreeCache::shapeOf(const Pool& pool) const {
    return {pool.slotNodes, pool.slotTriangles, pool.slotVertices, compact_};
}

GpuSlotShape GpuSubtreeCache::extentOf(const Pool& pool) const {
    if (pool.ring) return {pool.ring->capacity()[0], pool.ring->capacity()[1], pool.ring->capacity()[2], compact_};
    const uint64_t slots = pool.slotKey.size();
    return {slots * pool.slotNodes, slots * pool.slotTriangles, slots * pool.slotVertices, compact_};
}

PackedRing::Units GpuSubtreeCache::proxyUnits(uint32_t subtree, uint32_t level) const {
    const ChsLodRecord& r = store_.file().lodRecord(subtree, level);
    const GpuSlotShape shape = gpuEntryShape(r.nodeCount, r.triangleCount, store_.file().vertexCount(subtree, level), compact_);
    return {shape.nodes, shape.triangles, shape.vertices};
}

bool GpuSubtreeCache::proxyFits(const Pool& pool, uint32_t subtree, uint32_t level) const {
    return pool.ring && store_.file().lodRecord(subtree, level).nodeCount != 0 && pool.ring->fits(proxyUnits(subtree, level));
}

void GpuSubtreeCache::resetCounters() {
    const GpuCacheStats keep = stats_;
    stats_ = {};
    stats_.residentBytes = keep.residentBytes;
    stats_.peakResidentBytes = keep.peakResidentBytes;
    stats_.allocatedBytes = keep.allocatedBytes;
    stats_.slots = keep.slots;
    stats_.proxySlots = keep.proxySlots;
    stats_.residentSubtrees = keep.residentSubtrees;
}

uint32_t GpuSubtreeCache::levelFor(uint32_t subtree) const {
    if (!viewSet_ || !lodEnabled() || pools_.size() < 2) return 0;
    const ChsFile& file = store_.file();
    const ChsSubtreeRecord& r = file.subtrees()[subtree];
    const glm::vec3 lo(r.boundsMin[0], r.boundsMin[1], r.boundsMin[2]), hi(r.boundsMax[0], r.boundsMax[1], r.boundsMax[2]);
    const float distance = std::sqrt(squaredDistanceToBox(eye_, lo, hi));
    if (!(distance > 0.0f)) return 0; // the eye inside the box: full detail
    // A proxy's error is a distance in world units from the subtree's surface; seen from the eye it covers at most
    // error × focal / distance pixels (distance to the nearest point of the box bounds it from below). The floor
    // keeps the ratio finite for an eye on the box's face.
    const float floorDistance = 1e-6f * glm::length(hi - lo);
    const float pixelsPerUnit = focalPixels_ / std::max(distance, floorDistance);
    for (uint32_t level = uint32_t(pools_.size()) - 1; level >= 1; --level) {
        const ChsLodRecord& lod = file.lodRecord(subtree, level);
        if (!proxyFits(pools_[level], subtree, level)) {
            continue; // no proxy, or one larger than the level's pool: a finer level serves
        }
        if (lod.errorWorld * pixelsPerUnit < options_.lodPixels) return level;
    }
    return 0;
}

uint32_t GpuSubtreeCache::chooseVictim(Pool& pool) {
    const uint32_t n = uint32_t(pool.slotKey.size());
    if (options_.policy == CachePolicy::RoundRobin) {
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t slot = (pool.nextVictim + k) % n;
            if (pool.pinned[slot] != acquireCount_) {
                pool.nextVictim = (slot + 1) % n;
                return slot;
            }
        }
        return kNotResident;
    }
    uint32_t best = kNotResident;
    for (uint32_t slot = 0; slot < n; ++slot) { // empty slots have lastUse 0 and go first
        if (pool.pinned[slot] == acquireCount_) continue;
        if (best == kNotResident || pool.lastUse[slot] < pool.lastUse[best]) best = slot;
    }
    return best;
}

uint64_t GpuSubtreeCache::entryBytes(uint32_t level, uint32_t subtree) const {
    const ChsFile& file = store_.file();
    uint32_t nodes, triangles;
    if (level == 0) {
        nodes = file.subtrees()[subtree].nodeCount, triangles = file.subtrees()[subtree].triangleCount;
    } else {
        nodes = file.lodRecord(subtree, level).nodeCount, triangles = file.lodRecord(subtree, level).triangleCount;
    }
    return gpuEntryShape(nodes, triangles, file.vertexCount(subtree, level), compact_).bytes();
}

void GpuSubtreeCache::upload(uint32_t level, uint32_t subtree, uint32_t slot) {
    Pool& pool = pools_[level];
    const std::shared_ptr<const SubtreeData> data = store_.get(subtree, level, false); // nodes and triangles only
    const uint64_t nodeBase = pool.nodeBase(slot), triBase = pool.triangleBase(slot);
    size_t nodeBytes, triBytes, vertexBytes = 0;
    if (compact_) {
        // As stored: indices stay local, and the root's texel 2 tells the traversal where the subtree's triangles and
        // vertices start (shared/bvh_layout.h; its nodes start at the root).
        const uint64_t vertexBase = pool.vertexBase(slot);
        nodeBytes = data->compactNodes.size() * sizeof(glm::uvec4);
        triBytes = data->compactTriangles.size() * sizeof(glm::uvec4);
        vertexBytes = data->vertices.size() * sizeof(glm::vec3);
        const glm::uvec4 stored = data->compactNodes[2];
        const glm::uvec4 bases{uint32_t(triBase), uint32_t(vertexBase), stored.z, stored.w}; // steps y, z kept
        glNamedBufferSubData(nodes_.buffer.id(), GLintptr(nodeBase * sizeof(glm::uvec4)), GLsizeiptr(nodeBytes),
                             data->compactNodes.data());
        glNamedBufferSubData(nodes_.buffer.id(), GLintptr((nodeBase + 2) * sizeof(glm::uvec4)), sizeof(bases), &bases);
        if (triBytes != 0) {
            glNamedBufferSubData(triangles_.buffer.id(), GLintptr(triBase * sizeof(glm::uvec4)), GLsizeiptr(triBytes),
                                 data->compactTriangles.data());
        }
        if (vertexBytes != 0) {
            glNamedBufferSubData(vertices_.buffer.id(), GLintptr(vertexBase * sizeof(glm::vec3)), GLsizeiptr(vertexBytes),
                                 data->vertices.data());
        }
    } else {
        UninitializedVector<BvhNodeGpu>& nodes = rebased_;
        nodes.resize(data->nodes.size());
        for (size_t i = 0; i < nodes.size(); ++i) {
            nodes[i] = data->nodes[i];
            nodes[i].leftFirst += uint32_t(nodes[i].triCount != 0 ? triBase : nodeBase);
        }
        nodeBytes = nodes.size() * sizeof(BvhNodeGpu), triBytes = data->triangles.size() * sizeof(TriangleGpu);
        glNamedBufferSubData(nodes_.buffer.id(), GLintptr(nodeBase * sizeof(BvhNodeGpu)), GLsizeiptr(nodeBytes), nodes.data());
        if (triBytes != 0) {
            glNamedBufferSubData(triangles_.buffer.id(), GLintptr(triBase * sizeof(TriangleGpu)), GLsizeiptr(triBytes),
                                 data->triangles.data());
        }
    }
    evict(level, slot);
    pool.slotKey[slot] = subtree;
    pool.slotOf[subtree] = slot;
    stats_.residentBytes += nodeBytes + triBytes + vertexBytes;
    stats_.peakResidentBytes = std::max(stats_.peakResidentBytes, stats_.residentBytes);
    ++stats_.residentSubtrees;
    stats_.uploadedNodeBytes += nodeBytes;
    stats_.uploadedTriangleBytes += triBytes + vertexBytes;
    ++stats_.misses;
    ++stats_.uploadsPerLevel[level];
    if (level != 0) {
        ++stats_.proxyUploads;
        stats_.proxyUploadedBytes += nodeBytes + triBytes + vertexBytes;
    }
}

void GpuSubtreeCache::evict(uint32_t level, uint32_t slot) {
    Pool& pool = pools_[level];
    const uint32_t previous = pool.slotKey[slot];
    if (previous == kNotResident) return;
    stats_.residentBytes -= entryBytes(level, previous);
    pool.slotOf[previous] = kNotResident;
    pool.slotKey[slot] = kNotResident;
    ++stats_.evictions;
    ++replacements_;
    if (level == 0) {
        slotEpochs_[slot] = uint32_t(replacements_);
        slotEpochsChanged_ = true;
    }
    --stats_.residentSubtrees;
}

uint32_t GpuSubtreeCache::placeProxy(uint32_t level, uint32_t subtree) {
    Pool& pool = pools_[level];
    std::vector<uint32_t>& evicted = evictedScratch_;
    evicted.clear();
    const bool placed = pool.ring->place(subtree, proxyUnits(subtree, level),
                                         [&](uint32_t other) { return pool.pinned[other] == acquireCount_; }, evicted);
    for (uint32_t victim : evicted) {
        if (pool.lastUse[victim] > traceStartTick_) proxyPoolFullThisTrace_ = true; // this trace's entries fill it
        evict(level, victim);
    }
    if (!placed) {
        proxyPoolFullThisTrace_ = true;
        return kNotResident;
    }
    return subtree; // a packed pool's slot is the subtree index
}

void GpuSubtreeCache::use(Pool& pool, uint32_t slot) {
    pool.pinned[slot] = acquireCount_;
    if (pool.lastUse[slot] <= traceStartTick_ && !pool.ring) ++slotsUsedThisTrace_;
    pool.lastUse[slot] = ++tick_;
}

void GpuSubtreeCache::acquire(std::span<const uint32_t> subtrees, std::span<uint32_t> gpuRoots) {
    ++acquireCount_;
    std::vector<uint32_t> levels(subtrees.size());
    for (size_t i = 0; i < subtrees.size(); ++i) {
        levels[i] = levelFor(subtrees[i]);
        ++stats_.requestsPerLevel[levels[i]];
        lastAcquired_.at(subtrees[i]) = acquireCount_;
    }
    // Resident ones first, so that a miss never evicts a subtree this same request needs (CHC+RT §5.4:
    // resident scheduled subtrees are intersected first).
    for (size_t i = 0; i < subtrees.size(); ++i) {
        Pool& pool = pools_[levels[i]];
        const uint32_t slot = pool.slotOf.at(subtrees[i]);
        gpuRoots[i] = kNotResident;
        if (slot == kNotResident) continue;
        ++stats_.hits;
        use(pool, slot);
        gpuRoots[i] = pool.root(slot);
    }
    for (size_t i = 0; i < subtrees.size(); ++i) {
        if (gpuRoots[i] != kNotResident) continue;
        Pool& pool = pools_[levels[i]];
        const uint32_t already = pool.slotOf[subtrees[i]]; // requested twice in one call
        if (already != kNotResident) {
            gpuRoots[i] = pool.root(already);
            continue;
        }
        if (uploadBudgetExhausted()) {
            ++stats_.postponed;
            continue;
        }
        const uint32_t slot = pool.ring ? placeProxy(levels[i], subtrees[i]) : chooseVictim(pool);
        if (slot == kNotResident) {
            ++stats_.deferred;
            continue;
        }
        upload(levels[i], subtrees[i], slot);
        ++uploadsThisTrace_;
        use(pool, slot);
        gpuRoots[i] = pool.root(slot);
    }
    bind();
}

void GpuSubtreeCache::bind() {
    glBindTextureUnit(CHCRT_UNIT_BVH_NODES, nodes_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_BVH_TRIANGLES, triangles_.texture.id());
    if (compact_) glBindTextureUnit(CHCRT_UNIT_BVH_VERTICES, vertices_.texture.id());
    if (slotEpochsChanged_) { // the slots' epochs for the hint pass (SubtreeSource::hintSlotNodes)
        const size_t bytes = slotEpochs_.size() * sizeof(uint32_t); // at least one slot (the constructor checks)
        if (slotEpochTexture_.bytes != bytes) slotEpochTexture_ = createTextureBuffer(nullptr, bytes, GL_R32UI);
        glNamedBufferSubData(slotEpochTexture_.buffer.id(), 0, GLsizeiptr(bytes), slotEpochs_.data());
        slotEpochsChanged_ = false;
    }
    glBindTextureUnit(CHCRT_UNIT_CULLING_HINT_SLOTS, slotEpochTexture_.texture.id());
}

} // namespace chcrt::outofcore
