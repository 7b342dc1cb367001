#include "culling/culling_hierarchy.h"

namespace chcrt {

float CullingHierarchy::surfaceArea(uint32_t node) const {
    const glm::vec3 e = nodes[node].boxMax - nodes[node].boxMin;
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
}

CullingHierarchy buildCullingHierarchy(const Bvh& bvh, const SubtreePartitionOptions& options) {
    const SubtreePartition partition(bvh, options);
    CullingHierarchy h;
    h.partition = options;
    h.maxSubtreeHeight = partition.maxRootHeight();
    // Breadth-first copy of the nodes above the cut; siblings stay adjacent (firstChild, firstChild + 1).
    std::vector<uint32_t> bvhIndex = {0};
    h.nodes.resize(1);
    for (size_t i = 0; i < bvhIndex.size(); ++i) {
        const uint32_t b = bvhIndex[i];
        const BvhNodeGpu& source = bvh.nodes[b];
        CullingHierarchy::Node node;
        node.boxMin = source.boundsMin;
        node.boxMax = source.boundsMax;
        if (bvh.isLeaf(b)) {
            node.tightCount = 1;
            node.tightMin[0] = source.boundsMin;
            node.tightMax[0] = source.boundsMax;
        } else {
            node.tightCount = 2;
            for (uint32_t c = 0; c < 2; ++c) {
                node.tightMin[c] = bvh.nodes[source.leftFirst + c].boundsMin;
                node.tightMax[c] = bvh.nodes[source.leftFirst + c].boundsMax;
            }
        }
        if (partition.isRoot(b)) {
            node.subtree = uint32_t(h.subtrees.size());
            h.subtrees.push_back({uint32_t(i), partition.height(b), partition.triangleCount(b), b});
        } else {
            node.firstChild = uint32_t(bvhIndex.size());
            bvhIndex.push_back(source.leftFirst);
            bvhIndex.push_back(source.leftFirst + 1);
            h.nodes.resize(bvhIndex.size());
        }
        h.nodes[i] = node;
    }
    return h;
}

} // namespace chcrt
