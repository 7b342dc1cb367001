#include "culling/outofcore/chs_culling_hierarchy.h"

#include "renderer/core/error.h"

#include <algorithm>

namespace chcrt::outofcore {

CullingHierarchy buildCullingHierarchy(const ChsFile& file) {
    const ChsHeader& header = file.header();
    const std::vector<ChsUpperNode>& upper = file.upperNodes();
    const std::vector<ChsSubtreeRecord>& directory = file.subtrees();
    const auto corrupt = [&](const std::string& what) {
        return InputError(file.path().string() + ": corrupted prepared scene (" + what + ")");
    };
    CullingHierarchy h;
    h.partition.maxSubtreeHeight = header.subtreeHeightLimit;
    h.partition.maxSubtreeTriangles = header.subtreeTriangleLimit;
    h.nodes.resize(upper.size());
    h.subtrees.resize(directory.size());
    std::vector<uint8_t> seen(directory.size(), 0);
    const auto box = [](const float* lo, const float* hi) {
        return std::pair<glm::vec3, glm::vec3>{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
    };
    for (uint32_t i = 0; i < upper.size(); ++i) {
        const ChsUpperNode& u = upper[i];
        CullingHierarchy::Node& node = h.nodes[i];
        std::tie(node.boxMin, node.boxMax) = box(u.boundsMin, u.boundsMax);
        node.tightCount = 1;
        node.tightMin[0] = node.boxMin;
        node.tightMax[0] = node.boxMax;
        if (u.subtree == kChsNoSubtree) {
            if (u.firstChild <= i || uint64_t(u.firstChild) + 1 >= upper.size()) throw corrupt("upper node " + std::to_string(i));
            node.firstChild = u.firstChild;
            node.tightCount = 2;
            for (uint32_t c = 0; c < 2; ++c) {
                const ChsUpperNode& child = upper[u.firstChild + c];
                std::tie(node.tightMin[c], node.tightMax[c]) = box(child.boundsMin, child.boundsMax);
            }
            continue;
        }
        if (u.subtree >= directory.size() || seen[u.subtree] || directory[u.subtree].upperNode != i) {
            throw corrupt("upper node " + std::to_string(i) + " subtree");
        }
        seen[u.subtree] = 1;
        const ChsSubtreeRecord& r = directory[u.subtree];
        node.subtree = u.subtree;
        h.subtrees[u.subtree] = {i, r.height, r.triangleCount, i};
        h.maxSubtreeHeight = std::max(h.maxSubtreeHeight, r.height);
        // §5.1 tighter bounds: the root's two children, as buildCullingHierarchy takes them from the BVH.
        const BvhNodeGpu root = file.readSubtreeNode(u.subtree, 0);
        if (root.triCount == 0) {
            node.tightCount = 2;
            for (uint32_t c = 0; c < 2; ++c) {
                const BvhNodeGpu child = file.readSubtreeNode(u.subtree, root.leftFirst + c);
                node.tightMin[c] = child.boundsMin;
                node.tightMax[c] = child.boundsMax;
            }
        }
    }
    if (std::count(seen.begin(), seen.end(), 0) != 0) throw corrupt("subtree not reachable from the upper hierarchy");
    return h;
}

} // namespace chcrt::outofcore
