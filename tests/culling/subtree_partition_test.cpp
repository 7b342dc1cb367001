// Termination subtrees (CHC+RT §5.2): every leaf lies in exactly one subtree, subtrees respect the height and
// triangle limits (except single leaves), and the cut is topmost (no root's parent would also fit).
#include "culling/subtree_partition.h"

#include "renderer/core/error.h"
#include "renderer/scene/procedural/procedural.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

Bvh makeBvh(const char* spec) {
    ProceduralSpec s;
    EXPECT_TRUE(parseProceduralSpec(spec, s));
    return buildBvh(generateProceduralScene(s));
}

TEST(SubtreePartition, EveryLeafInExactlyOneSubtreeWithinTheLimits) {
    const Bvh bvh = makeBvh("city:20k");
    for (uint32_t maxHeight : {1u, 3u, 8u, 24u}) {
        for (uint32_t maxTriangles : {16u, 1000u, 1u << 20}) {
            SubtreePartitionOptions options;
            options.maxSubtreeHeight = maxHeight;
            options.maxSubtreeTriangles = maxTriangles;
            const SubtreePartition partition(bvh, options);
            ASSERT_FALSE(partition.roots().empty());
            // Count, for every leaf, the termination roots on its path to the BVH root.
            size_t leaves = 0;
            for (uint32_t node = 0; node < bvh.nodes.size(); ++node) {
                if (!bvh.isLeaf(node)) continue;
                ++leaves;
                int rootsOnPath = 0;
                for (uint32_t n = node; n != UINT32_MAX; n = partition.parent(n)) rootsOnPath += partition.isRoot(n);
                EXPECT_EQ(rootsOnPath, 1) << "leaf " << node;
            }
            uint64_t triangles = 0;
            for (uint32_t root : partition.roots()) {
                triangles += partition.triangleCount(root);
                if (!bvh.isLeaf(root)) {
                    EXPECT_LE(partition.height(root), maxHeight);
                    EXPECT_LE(partition.triangleCount(root), maxTriangles);
                }
                EXPECT_LE(partition.height(root), partition.maxRootHeight());
                // Topmost: the parent does not fit (otherwise it would be the root).
                const uint32_t parent = partition.parent(root);
                if (parent != UINT32_MAX) {
                    EXPECT_TRUE(partition.height(parent) > maxHeight || partition.triangleCount(parent) > maxTriangles);
                }
            }
            EXPECT_EQ(triangles, bvh.triangles.size());
            EXPECT_GT(leaves, 0u);
        }
    }
}

TEST(SubtreePartition, HeightsAndCountsMatchTheTree) {
    const Bvh bvh = makeBvh("plant:5k");
    const SubtreePartition partition(bvh);
    EXPECT_EQ(partition.height(0), bvh.stats.maxDepth);
    EXPECT_EQ(partition.triangleCount(0), bvh.triangles.size());
    // The whole tree fits the paper's defaults at this size: one subtree, the root.
    ASSERT_EQ(partition.roots().size(), 1u);
    EXPECT_EQ(partition.roots()[0], 0u);
    for (uint32_t node = 0; node < bvh.nodes.size(); ++node) {
        if (bvh.isLeaf(node)) continue;
        const uint32_t a = partition.childOf(node);
        EXPECT_EQ(a, bvh.nodes[node].leftFirst);
        EXPECT_EQ(partition.height(node), 1 + std::max(partition.height(a), partition.height(a + 1)));
        EXPECT_EQ(partition.parent(a), node);
    }
}

TEST(SubtreePartition, RejectsZeroLimits) {
    const Bvh bvh = makeBvh("city:2k");
    SubtreePartitionOptions options;
    options.maxSubtreeHeight = 0;
    EXPECT_THROW(SubtreePartition(bvh, options), InputError);
}

} // namespace
} // namespace chcrt
