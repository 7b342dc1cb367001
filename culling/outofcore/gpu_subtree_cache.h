#pragma once
// GPU side of out-of-core rendering (CHC+RT §5.4): termination subtrees of a prepared scene are uploaded on
// demand into fixed-size slots of two texture buffers (nodes, triangles; layouts of shaders/shared/bvh_layout.h)
// whose sizes follow from --gpu-cache-mb. Every slot holds the largest subtree of the file, so any subtree fits
// any slot and allocation is a choice of victim: round-robin (the paper's policy) or least recently used.
// Uploads rebase the subtree's local indices by the slot's first node and triangle. The budget is checked
// against the buffers actually allocated, which never grow.
//
// Subtree indices are indices into the file's directory (ChsFile::subtrees()).
#include "culling/subtree_source.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/outofcore/subtree_store.h"

#include <string>
#include <vector>

namespace chcrt::outofcore {

enum class CachePolicy { RoundRobin, Lru };
CachePolicy parseCachePolicy(const std::string& text); // "round-robin" | "lru"; InputError otherwise
const char* toString(CachePolicy policy);

struct GpuCacheOptions {
    uint64_t budgetBytes = 1024ull << 20;
    CachePolicy policy = CachePolicy::Lru;
    // Subtrees uploaded per trace at most (0 = no limit: every trace is complete and exact). The viewer streams
    // with a limit so that a cold cache costs several short frames instead of one long one.
    uint32_t maxUploadsPerTrace = 0;
};

struct GpuCacheStats {
    uint64_t hits = 0;
    uint64_t misses = 0;    // uploads
    uint64_t evictions = 0; // uploads that replaced a resident subtree
    uint64_t deferred = 0;  // requests answered kNotResident (all slots pinned by the same acquire)
    uint64_t postponed = 0; // requests answered kNotResident because the per-trace upload limit was reached
    uint64_t uploadedNodeBytes = 0;     // BVH MB transferred (Table 3)
    uint64_t uploadedTriangleBytes = 0; // geometry MB transferred
    uint64_t residentBytes = 0;  // nodes + triangles of the resident subtrees
    uint64_t peakResidentBytes = 0; // the most residentBytes has been (kept by resetCounters)
    uint64_t allocatedBytes = 0; // both texture buffers, as allocated (<= budget)
    uint32_t slots = 0;
    uint32_t residentSubtrees = 0;
};

class GpuSubtreeCache final : public SubtreeSource {
public:
    // Needs a current GL context. Throws InputError when the budget cannot hold one slot.
    GpuSubtreeCache(SubtreeStore& store, const GpuCacheOptions& options);

    void acquire(std::span<const uint32_t> subtrees, std::span<uint32_t> gpuRoots) override;
    // The limit holds only while some slot is not used by the current trace: once this trace's subtrees fill the
    // cache, later traces could not do better (the working set exceeds the cache), so the trace completes.
    bool uploadBudgetExhausted() const override {
        return options_.maxUploadsPerTrace != 0 && uploadsThisTrace_ >= options_.maxUploadsPerTrace &&
               slotsUsedThisTrace_ < stats_.slots;
    }
    void beginTrace() { // the per-trace upload limit starts again
        uploadsThisTrace_ = 0;
        slotsUsedThisTrace_ = 0;
        traceStartTick_ = tick_;
    }

    const GpuCacheStats& stats() const { return stats_; }
    void resetCounters(); // per-frame statistics: zero hits/misses/evictions/uploads, keep residency
    uint32_t slotCount() const { return uint32_t(slotSubtree_.size()); }
    uint32_t slotNodes() const { return slotNodes_; }
    uint32_t slotTriangles() const { return slotTriangles_; }
    bool isResident(uint32_t subtree) const { return subtreeSlot_.at(subtree) != kNotResident; }
    // The subtree in a slot (kNotResident when empty).
    uint32_t slotSubtree(uint32_t slot) const { return slotSubtree_[slot]; }
    GLuint nodeBuffer() const { return nodes_.buffer.id(); }
    GLuint triangleBuffer() const { return triangles_.buffer.id(); }
    GLuint nodeTexture() const { return nodes_.texture.id(); }
    GLuint triangleTexture() const { return triangles_.texture.id(); }

private:
    uint32_t chooseVictim(); // kNotResident when every slot is pinned
    void upload(uint32_t subtree, uint32_t slot);

    SubtreeStore& store_;
    GpuCacheOptions options_;
    uint32_t slotNodes_ = 0, slotTriangles_ = 0;
    TextureBuffer nodes_, triangles_;
    std::vector<uint32_t> slotSubtree_;
    std::vector<uint64_t> slotLastUse_;
    std::vector<uint64_t> slotPinned_; // == acquireCount_: used by the current acquire, not evictable
    std::vector<uint32_t> subtreeSlot_;
    uint64_t acquireCount_ = 0, tick_ = 0;
    uint32_t nextVictim_ = 0; // round-robin pointer
    uint32_t uploadsThisTrace_ = 0, slotsUsedThisTrace_ = 0;
    uint64_t traceStartTick_ = 0;
    GpuCacheStats stats_;
};

} // namespace chcrt::outofcore
