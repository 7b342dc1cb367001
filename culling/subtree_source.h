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

    // Hit hints (culling/README.md "Hit hints") name nodes of the bound buffers, which must still hold the subtrees
    // the hints were recorded in. contentEpoch() counts the replacements of resident subtrees (a cache slot given to
    // another one); in core it never changes.
    virtual uint64_t contentEpoch() const { return 0; }
    // Whether hints may name this source's nodes at all (false where entries of other shapes share the buffers,
    // e.g. LOD proxies).
    virtual bool hintsSupported() const { return true; }
    // Slots: the node records of each (nonzero out of core), which start at multiples of it: a hinted node's slot is
    // node / hintSlotNodes(), and in the compact layout its subtree root (the frame its box and triangles decode in)
    // node - node % hintSlotNodes(). bind() then also binds, at CHCRT_UNIT_CULLING_HINT_SLOTS, each slot's epoch
    // (shared/culling_layout.h), so that the hint pass drops only the hints of the slots replaced since.
    virtual uint32_t hintSlotNodes() const { return 0; }
    // Binds the buffers as acquire() does, for a pass that reads resident subtrees before this trace asks for any
    // (the hint pass). In core the renderer has bound them.
    virtual void bind() {}
};

} // namespace chcrt
