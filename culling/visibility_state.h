#pragma once
// CHC+RT §4.5/§5.1: the visibility state of one ray set, kept across frames. It stores the query-pair hierarchy
// traversed so far: interior pairs (subdivided, in object or screen space) and its leaves, which form the
// visible front (terminal pairs whose subtree is intersected) and the invisible front (pairs whose query
// found no ray that could hit the node). Keeping the interior pairs lets invisibility be pulled up one level
// per frame (§5.1). No GL here; the tracer (chcrt_tracer.h) drives it.
#include "culling/query_pair_hierarchy.h"

#include <cstdint>
#include <vector>

namespace chcrt {

struct QueryPair {
    Tile tile;
    uint32_t bvhNode = 0;
    int32_t parent = -1;
    std::array<int32_t, 4> children{-1, -1, -1, -1};
    uint8_t childCount = 0; // 0 = leaf of the hierarchy
    bool visible = false;   // leaves: visible front (terminal) or invisible front
    uint8_t requeryPhase = 0; // §5.1: randomized frame offset of the lazy re-query of visible leaves
    bool alive = false;
    bool isLeaf() const { return childCount == 0; }
};

class VisibilityState {
public:
    // Starts from the single pair (whole screen, BVH root), as an invisible leaf so that the first frame
    // queries it and traverses down from there.
    VisibilityState(int width, int height, uint32_t seed);

    int width() const { return width_; }
    int height() const { return height_; }
    uint64_t frame() const { return frame_; }
    void advanceFrame() { ++frame_; }

    QueryPair& pair(int32_t index) { return pairs_[size_t(index)]; }
    const QueryPair& pair(int32_t index) const { return pairs_[size_t(index)]; }
    size_t slotCount() const { return pairs_.size(); }
    size_t pairCount() const { return pairs_.size() - free_.size(); }

    // Subdivides leaf `index` into the given children (each a new invisible leaf); returns their indices
    // through `out` (invalidates QueryPair references).
    int subdivide(int32_t index, const Tile* tiles, const uint32_t* nodes, int count, int32_t* out,
                  uint32_t requeryInterval);
    // §5.1 pull-up: every interior pair whose children are all invisible leaves (at the start of the call)
    // becomes an invisible leaf; returns how many were merged. One level per call = per frame.
    int pullUpInvisibility();
    // Leaves of the hierarchy (visible and invisible fronts), in slot order.
    void collectLeaves(std::vector<int32_t>& visible, std::vector<int32_t>& invisible) const;
    // Appends the nodes of the invisible front next to the visible part: invisible leaves with a sibling that is a
    // visible leaf or an interior pair (which has visible pairs below it). A small change of view or of the rays
    // most likely turns these visible; out of core they are what to prefetch (culling/outofcore/subtree_prefetch.h).
    // A node may be appended more than once (several tiles).
    void collectInvisibleNextToVisible(std::vector<uint32_t>& nodes) const;

private:
    int32_t allocate();
    void release(int32_t index);
    uint32_t nextRandom();

    int width_ = 0, height_ = 0;
    uint64_t frame_ = 0;
    uint64_t random_ = 0;
    std::vector<QueryPair> pairs_;
    std::vector<int32_t> free_;
};

} // namespace chcrt
