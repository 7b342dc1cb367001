// BVH statistics: SAH cost, node/leaf counts, depth, memory. Walks the flat node array only, so it works on
// any tree in the GPU layout (built here, optimised, or loaded from a cache).
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/bvh_internal.h"

#include <utility>

namespace chcrt {

namespace {

// Surface area in double: float areas of huge (adversarial) boxes overflow, and the sum over millions of
// nodes would lose precision.
double surfaceArea(const glm::vec3& lower, const glm::vec3& upper) {
    const double x = double(upper.x) - double(lower.x);
    const double y = double(upper.y) - double(lower.y);
    const double z = double(upper.z) - double(lower.z);
    if (!(x >= 0.0 && y >= 0.0 && z >= 0.0)) {
        return 0.0; // empty (or NaN) box
    }
    return 2.0 * (x * y + y * z + z * x);
}

} // namespace

Aabb Bvh::rootBounds() const {
    Aabb box;
    if (!nodes.empty()) {
        box.lower = nodes[0].boundsMin;
        box.upper = nodes[0].boundsMax;
    }
    return box;
}

double computeSahCost(const Bvh& bvh, float traversalCost, float intersectionCost) {
    if (bvh.nodes.empty()) {
        return 0.0;
    }
    const double rootArea = surfaceArea(bvh.nodes[0].boundsMin, bvh.nodes[0].boundsMax);
    double cost = 0.0;
    for (const BvhNodeGpu& node : bvh.nodes) {
        // A flat root (all triangles in one plane point/line) has zero area: weigh every node equally then.
        const double weight = rootArea > 0.0 ? surfaceArea(node.boundsMin, node.boundsMax) / rootArea : 1.0;
        cost += weight * (node.triCount == 0 ? double(traversalCost) : double(intersectionCost) * node.triCount);
    }
    return cost;
}

namespace detail {

void measureBvh(Bvh& bvh, float traversalCost, float intersectionCost) {
    BvhStats& stats = bvh.stats;
    stats.nodeCount = uint32_t(bvh.nodes.size());
    stats.leafCount = 0;
    stats.maxDepth = 0;
    stats.sahCost = computeSahCost(bvh, traversalCost, intersectionCost);
    stats.bytes = uint64_t(bvh.nodes.size()) * sizeof(BvhNodeGpu) + uint64_t(bvh.triangles.size()) * sizeof(TriangleGpu);
    if (bvh.nodes.empty()) {
        stats.averageLeafTriangles = 0.0;
        return;
    }
    // Depth-first walk from the root; the depth is bounded (< CHCRT_MAX_BVH_DEPTH), the stack is not assumed to be.
    std::vector<std::pair<uint32_t, uint32_t>> stack{{0u, 0u}}; // (node, depth)
    uint64_t leafTriangles = 0;
    while (!stack.empty()) {
        const auto [node, depth] = stack.back();
        stack.pop_back();
        stats.maxDepth = std::max(stats.maxDepth, depth);
        const BvhNodeGpu& n = bvh.nodes[node];
        if (n.triCount != 0) {
            ++stats.leafCount;
            leafTriangles += n.triCount;
        } else {
            stack.emplace_back(n.leftFirst + 1, depth + 1);
            stack.emplace_back(n.leftFirst, depth + 1);
        }
    }
    stats.averageLeafTriangles = stats.leafCount == 0 ? 0.0 : double(leafTriangles) / stats.leafCount;
}

} // namespace detail

} // namespace chcrt
