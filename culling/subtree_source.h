#pragma once
// Where the subtrees CHC+RT schedules for intersection live on the GPU (CHC+RT §5.4). In core they are part of the
// scene's BVH buffers and a subtree's GPU root is its BVH node index; out of core a cache uploads missing subtrees
// into slots of fixed-size texture buffers (culling/outofcore/). The tracer asks before each intersection batch.
#include <cstdint>
#include <span>

namespace chcrt {

class SubtreeSource {
public:
    static constexpr uint32_t kNotResident = 0xffffffffu;

    virtual ~SubtreeSource() = default;
    // Binds the node and triangle texture buffers (CHCRT_UNIT_BVH_NODES / CHCRT_UNIT_BVH_TRIANGLES of
    // shaders/shared/render_layout.h) and makes as many of `subtrees` (indices into the culling hierarchy's
    // termination roots) resident as fit; gpuRoots[i] is then the root node index of subtrees[i] in the bound
    // buffers, or kNotResident when it did not fit this time (the tracer intersects it in a later round).
    // Node and triangle records use the layout of shaders/shared/bvh_layout.h with indices into the bound buffers.
    virtual void acquire(std::span<const uint32_t> subtrees, std::span<uint32_t> gpuRoots) = 0;
    // True when acquire() left subtrees non-resident because a per-trace upload budget ran out (an interactive
    // viewer streaming a large scene); the tracer then postpones them to a later trace instead of waiting, and that
    // trace is incomplete (ChcrtStats::subtreesPostponed). Sources without a budget never do.
    virtual bool uploadBudgetExhausted() const { return false; }
    // The bound buffers hold the compact subtree layout (shared/bvh_layout.h): the tracer's programs are compiled
    // with CHCRT_COMPACT_SUBTREES 1 and bind nothing else to those units.
    virtual bool compactLayout() const { return false; }
};

} // namespace chcrt
