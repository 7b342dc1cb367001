// The culling hierarchy (§4.3/§5.4 upper BVH as plain data) built from an in-core BVH: the same termination cut as
// SubtreePartition, adjacent siblings, boxes nested, tighter-bounds boxes = the BVH children's boxes.
#include "culling/culling_hierarchy.h"
#include "renderer/bvh/bvh.h"
#include "renderer/scene/procedural/procedural.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

bool contains(const glm::vec3& outerMin, const glm::vec3& outerMax, const glm::vec3& innerMin, const glm::vec3& innerMax) {
    return glm::all(glm::lessThanEqual(outerMin, innerMin)) && glm::all(glm::lessThanEqual(innerMax, outerMax));
}

TEST(CullingHierarchy, MatchesThePartitionAndNestsBoxes) {
    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec("plant:20k", spec));
    const Bvh bvh = buildBvh(generateProceduralScene(spec));
    for (uint32_t height : {3u, 7u, 24u}) {
        SubtreePartitionOptions options;
        options.maxSubtreeHeight = height;
        const SubtreePartition partition(bvh, options);
        const CullingHierarchy h = buildCullingHierarchy(bvh, options);
        ASSERT_EQ(h.subtrees.size(), partition.roots().size()) << height;
        EXPECT_EQ(h.maxSubtreeHeight, partition.maxRootHeight());
        uint64_t triangles = 0;
        std::vector<uint32_t> bvhRoots;
        for (size_t s = 0; s < h.subtrees.size(); ++s) {
            const CullingHierarchy::Subtree& sub = h.subtrees[s];
            EXPECT_EQ(h.nodes[sub.node].subtree, s);
            EXPECT_TRUE(partition.isRoot(sub.bvhNode));
            EXPECT_EQ(sub.height, partition.height(sub.bvhNode));
            EXPECT_EQ(sub.triangles, partition.triangleCount(sub.bvhNode));
            EXPECT_LE(sub.height, height);
            triangles += sub.triangles;
            bvhRoots.push_back(sub.bvhNode);
        }
        std::sort(bvhRoots.begin(), bvhRoots.end());
        EXPECT_EQ(bvhRoots, partition.roots());
        EXPECT_EQ(triangles, partition.triangleCount(0));
        // Every node is reached exactly once from the root, children adjacent and inside their parent.
        std::vector<int> reached(h.nodes.size(), 0);
        reached[0] = 1;
        for (size_t i = 0; i < h.nodes.size(); ++i) {
            const CullingHierarchy::Node& n = h.nodes[i];
            EXPECT_NE(n.isTerminal(), n.firstChild != CullingHierarchy::kNone);
            for (uint32_t c = 0; c < n.tightCount; ++c) {
                EXPECT_TRUE(contains(n.boxMin, n.boxMax, n.tightMin[c], n.tightMax[c]));
            }
            if (n.isTerminal()) continue;
            ASSERT_EQ(n.tightCount, 2u);
            for (uint32_t c = 0; c < 2; ++c) {
                const CullingHierarchy::Node& child = h.nodes[n.firstChild + c];
                ++reached[n.firstChild + c];
                EXPECT_EQ(child.boxMin, n.tightMin[c]);
                EXPECT_EQ(child.boxMax, n.tightMax[c]);
            }
        }
        for (int r : reached) EXPECT_EQ(r, 1);
    }
}

} // namespace
} // namespace chcrt
