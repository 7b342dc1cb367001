#pragma once
// CHC+RT §5.2 termination in object space: the BVH is cut into *termination subtrees*, the topmost nodes whose
// subtree height and triangle count are both within limits. The query-pair hierarchy (query_pair_hierarchy.h)
// splits only the nodes above this cut; a visible pair whose node is a termination root schedules that whole
// subtree for shader traversal. Subtrees are also the scheduling unit of by-tile batching and (later) the
// caching unit of out-of-core rendering (§5.4). This class does not own or modify the BVH.
#include "renderer/bvh/bvh.h"

#include <cstdint>
#include <vector>

namespace chcrt {

struct SubtreePartitionOptions {
    // §5.2: the traversal stack must be at least as deep as the subtree height; the paper used 24 levels.
    uint32_t maxSubtreeHeight = 24;
    // §5.2: matters for out-of-core scenes; the paper used 1M.
    uint32_t maxSubtreeTriangles = 1u << 20;
};

class SubtreePartition {
public:
    // Throws InputError when an option is 0.
    SubtreePartition(const Bvh& bvh, const SubtreePartitionOptions& options = {});

    const SubtreePartitionOptions& options() const { return options_; }
    // Termination roots in increasing node order (a leaf is its own subtree when its parent is too large).
    const std::vector<uint32_t>& roots() const { return roots_; }
    bool isRoot(uint32_t node) const { return isRoot_[node] != 0; }
    // Height of a node's subtree in edges (leaf = 0) and triangles below it, for every node.
    uint32_t height(uint32_t node) const { return height_[node]; }
    uint32_t triangleCount(uint32_t node) const { return triangles_[node]; }
    // First child of an inner node (the second is the next index).
    uint32_t childOf(uint32_t node) const { return firstChild_[node]; }
    // Parent of a node (root: UINT32_MAX).
    uint32_t parent(uint32_t node) const { return parent_[node]; }
    // Surface area of a node's box (CHC+RT §4.4 split heuristic).
    float surfaceArea(uint32_t node) const { return area_[node]; }
    uint32_t maxRootHeight() const { return maxRootHeight_; }

private:
    SubtreePartitionOptions options_;
    std::vector<uint32_t> roots_;
    std::vector<uint8_t> isRoot_;
    std::vector<uint32_t> height_;
    std::vector<uint32_t> triangles_;
    std::vector<uint32_t> parent_;
    std::vector<uint32_t> firstChild_;
    std::vector<float> area_;
    uint32_t maxRootHeight_ = 0;
};

} // namespace chcrt
