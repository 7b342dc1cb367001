#include "culling/outofcore/gpu_subtree_cache.h"

#include "renderer/core/error.h"
#include "renderer/gl/context.h"
#include "renderer/outofcore/gpu_cache_slots.h"
#include "shaders/shared/render_layout.h"

namespace chcrt::outofcore {

CachePolicy parseCachePolicy(const std::string& text) {
    if (text == "round-robin" || text == "rr") return CachePolicy::RoundRobin;
    if (text == "lru") return CachePolicy::Lru;
    throw InputError("--cache-policy " + text + ": expected round-robin or lru");
}

const char* toString(CachePolicy policy) { return policy == CachePolicy::Lru ? "lru" : "round-robin"; }

GpuSubtreeCache::GpuSubtreeCache(SubtreeStore& store, const GpuCacheOptions& options)
    : store_(store), options_(options) {
    const ChsHeader& h = store.file().header();
    slotNodes_ = h.maxSubtreeNodes;
    slotTriangles_ = std::max(1u, h.maxSubtreeTriangles);
    const uint64_t slotBytes = uint64_t(slotNodes_) * sizeof(BvhNodeGpu) + uint64_t(slotTriangles_) * sizeof(TriangleGpu);
    // The budget is clamped to what one texture buffer addresses and to the GPU memory the driver reports
    // (renderer/outofcore/gpu_cache_slots.h), so a budget beyond them allocates what fits instead of failing.
    GLint maxTexels = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
    const GpuCacheLimits limits{uint64_t(std::max(maxTexels, 0)), queryGpuMemory().availableBytes};
    const uint64_t slots = gpuCacheSlots(options.budgetBytes, slotNodes_, slotTriangles_, h.subtreeCount, limits);
    if (slots == 0) {
        throw InputError("--gpu-cache-mb " + std::to_string(options.budgetBytes >> 20) +
                         " is too small to hold one subtree of " + store.file().path().string() + " (needs " +
                         std::to_string((slotBytes + (1u << 20) - 1) >> 20) + " MB; prepare with smaller --subtree-triangles)");
    }
    nodes_ = createTextureBuffer(nullptr, slots * slotNodes_ * sizeof(BvhNodeGpu), GL_RGBA32F);
    triangles_ = createTextureBuffer(nullptr, slots * slotTriangles_ * sizeof(TriangleGpu), GL_RGBA32F);
    stats_.allocatedBytes = nodes_.bytes + triangles_.bytes;
    if (stats_.allocatedBytes > options.budgetBytes) throw std::logic_error("GPU cache allocation exceeds its budget");
    stats_.slots = uint32_t(slots);
    slotSubtree_.assign(slots, kNotResident);
    slotLastUse_.assign(slots, 0);
    slotPinned_.assign(slots, 0);
    subtreeSlot_.assign(h.subtreeCount, kNotResident);
}

void GpuSubtreeCache::resetCounters() {
    const GpuCacheStats keep = stats_;
    stats_ = {};
    stats_.residentBytes = keep.residentBytes;
    stats_.peakResidentBytes = keep.peakResidentBytes;
    stats_.allocatedBytes = keep.allocatedBytes;
    stats_.slots = keep.slots;
    stats_.residentSubtrees = keep.residentSubtrees;
}

uint32_t GpuSubtreeCache::chooseVictim() {
    const uint32_t n = slotCount();
    if (options_.policy == CachePolicy::RoundRobin) {
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t slot = (nextVictim_ + k) % n;
            if (slotPinned_[slot] != acquireCount_) {
                nextVictim_ = (slot + 1) % n;
                return slot;
            }
        }
        return kNotResident;
    }
    uint32_t best = kNotResident;
    for (uint32_t slot = 0; slot < n; ++slot) { // empty slots have lastUse 0 and go first
        if (slotPinned_[slot] == acquireCount_) continue;
        if (best == kNotResident || slotLastUse_[slot] < slotLastUse_[best]) best = slot;
    }
    return best;
}

void GpuSubtreeCache::upload(uint32_t subtree, uint32_t slot) {
    const std::shared_ptr<const SubtreeData> data = store_.get(subtree);
    const uint32_t nodeBase = slot * slotNodes_, triBase = slot * slotTriangles_;
    std::vector<BvhNodeGpu> nodes = data->nodes;
    for (BvhNodeGpu& node : nodes) node.leftFirst += node.triCount != 0 ? triBase : nodeBase;
    const size_t nodeBytes = nodes.size() * sizeof(BvhNodeGpu), triBytes = data->triangles.size() * sizeof(TriangleGpu);
    glNamedBufferSubData(nodes_.buffer.id(), GLintptr(uint64_t(nodeBase) * sizeof(BvhNodeGpu)), GLsizeiptr(nodeBytes),
                         nodes.data());
    if (triBytes != 0) {
        glNamedBufferSubData(triangles_.buffer.id(), GLintptr(uint64_t(triBase) * sizeof(TriangleGpu)),
                             GLsizeiptr(triBytes), data->triangles.data());
    }
    const uint32_t previous = slotSubtree_[slot];
    if (previous != kNotResident) {
        const ChsSubtreeRecord& r = store_.file().subtrees()[previous];
        stats_.residentBytes -= uint64_t(r.nodeCount) * sizeof(BvhNodeGpu) + uint64_t(r.triangleCount) * sizeof(TriangleGpu);
        subtreeSlot_[previous] = kNotResident;
        ++stats_.evictions;
        --stats_.residentSubtrees;
    }
    slotSubtree_[slot] = subtree;
    subtreeSlot_[subtree] = slot;
    stats_.residentBytes += nodeBytes + triBytes;
    stats_.peakResidentBytes = std::max(stats_.peakResidentBytes, stats_.residentBytes);
    ++stats_.residentSubtrees;
    stats_.uploadedNodeBytes += nodeBytes;
    stats_.uploadedTriangleBytes += triBytes;
    ++stats_.misses;
}

void GpuSubtreeCache::acquire(std::span<const uint32_t> subtrees, std::span<uint32_t> gpuRoots) {
    ++acquireCount_;
    // Resident ones first, so that a miss never evicts a subtree this same request needs (CHC+RT §5.4:
    // resident scheduled subtrees are intersected first).
    for (size_t i = 0; i < subtrees.size(); ++i) {
        const uint32_t slot = subtreeSlot_.at(subtrees[i]);
        gpuRoots[i] = kNotResident;
        if (slot == kNotResident) continue;
        ++stats_.hits;
        slotPinned_[slot] = acquireCount_;
        if (slotLastUse_[slot] <= traceStartTick_) ++slotsUsedThisTrace_;
        slotLastUse_[slot] = ++tick_;
        gpuRoots[i] = slot * slotNodes_;
    }
    for (size_t i = 0; i < subtrees.size(); ++i) {
        if (gpuRoots[i] != kNotResident) continue;
        const uint32_t already = subtreeSlot_[subtrees[i]]; // requested twice in one call
        if (already != kNotResident) {
            gpuRoots[i] = already * slotNodes_;
            continue;
        }
        if (uploadBudgetExhausted()) {
            ++stats_.postponed;
            continue;
        }
        const uint32_t slot = chooseVictim();
        if (slot == kNotResident) {
            ++stats_.deferred;
            continue;
        }
        upload(subtrees[i], slot);
        ++uploadsThisTrace_;
        slotPinned_[slot] = acquireCount_;
        if (slotLastUse_[slot] <= traceStartTick_) ++slotsUsedThisTrace_;
        slotLastUse_[slot] = ++tick_;
        gpuRoots[i] = slot * slotNodes_;
    }
    glBindTextureUnit(CHCRT_UNIT_BVH_NODES, nodes_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_BVH_TRIANGLES, triangles_.texture.id());
}

} // namespace chcrt::outofcore
