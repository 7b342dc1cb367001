#include "culling/subtree_partition.h"

#include "renderer/core/error.h"

#include <algorithm>

namespace chcrt {

SubtreePartition::SubtreePartition(const Bvh& bvh, const SubtreePartitionOptions& options) : options_(options) {
    if (options.maxSubtreeHeight == 0 || options.maxSubtreeTriangles == 0) {
        throw InputError("subtree partition: maximum height and triangle count must be positive");
    }
    const size_t n = bvh.nodes.size();
    height_.assign(n, 0);
    triangles_.assign(n, 0);
    parent_.assign(n, UINT32_MAX);
    firstChild_.assign(n, UINT32_MAX);
    area_.assign(n, 0.0f);
    isRoot_.assign(n, 0);
    // Children always have larger indices than their parent (leftFirst > node), so one reverse sweep
    // computes heights and triangle counts bottom-up.
    for (size_t i = n; i-- > 0;) {
        const BvhNodeGpu& node = bvh.nodes[i];
        const glm::vec3 e = node.boundsMax - node.boundsMin;
        area_[i] = 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
        if (node.triCount != 0) {
            triangles_[i] = node.triCount;
            continue;
        }
        const uint32_t a = node.leftFirst, b = node.leftFirst + 1;
        parent_[a] = parent_[b] = uint32_t(i);
        firstChild_[i] = a;
        height_[i] = 1 + std::max(height_[a], height_[b]);
        triangles_[i] = triangles_[a] + triangles_[b];
    }
    // Topmost nodes within both limits, found top-down (a leaf always qualifies by height; a leaf with more
    // triangles than the limit still becomes a root, as it cannot be split).
    std::vector<uint32_t> stack = {0};
    while (!stack.empty()) {
        const uint32_t node = stack.back();
        stack.pop_back();
        const bool fits = height_[node] <= options.maxSubtreeHeight && triangles_[node] <= options.maxSubtreeTriangles;
        if (fits || bvh.isLeaf(node)) {
            isRoot_[node] = 1;
            roots_.push_back(node);
            maxRootHeight_ = std::max(maxRootHeight_, height_[node]);
            continue;
        }
        stack.push_back(bvh.nodes[node].leftFirst);
        stack.push_back(bvh.nodes[node].leftFirst + 1);
    }
    std::sort(roots_.begin(), roots_.end());
}

} // namespace chcrt
