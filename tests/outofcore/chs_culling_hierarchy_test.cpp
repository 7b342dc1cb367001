// The CHC+RT culling hierarchy read from a prepared file (issue #5 part 2, task 1): for a one-part file it is
// the hierarchy buildCullingHierarchy computes from the in-core load with the same limits; for a streamed
// (multi-part) file its termination subtrees are exactly the file's subtrees.
#include "culling/outofcore/chs_culling_hierarchy.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

void expectSameBox(const glm::vec3& aMin, const glm::vec3& aMax, const glm::vec3& bMin, const glm::vec3& bMax,
                   const std::string& what) {
    EXPECT_EQ(aMin, bMin) << what;
    EXPECT_EQ(aMax, bMax) << what;
}

TEST(ChsCullingHierarchy, OnePartFileEqualsTheInCoreHierarchy) {
    test::ScratchDir dir;
    const auto file = dir.file("one.chs");
    const outofcore::PrepareReport report = test::prepareSmall("city:20k", file, 1000);
    ASSERT_EQ(report.chunks, 1u);
    ASSERT_GT(report.subtrees, 10u);
    const outofcore::ChsFile chs(file);
    const CullingHierarchy fromFile = outofcore::buildCullingHierarchy(chs);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    SubtreePartitionOptions limits;
    limits.maxSubtreeHeight = chs.header().subtreeHeightLimit;
    limits.maxSubtreeTriangles = chs.header().subtreeTriangleLimit;
    const CullingHierarchy inCore = buildCullingHierarchy(loaded.bvh, limits);

    EXPECT_EQ(fromFile.partition.maxSubtreeHeight, inCore.partition.maxSubtreeHeight);
    EXPECT_EQ(fromFile.partition.maxSubtreeTriangles, inCore.partition.maxSubtreeTriangles);
    EXPECT_EQ(fromFile.maxSubtreeHeight, inCore.maxSubtreeHeight);
    ASSERT_EQ(fromFile.nodes.size(), inCore.nodes.size());
    ASSERT_EQ(fromFile.subtrees.size(), inCore.subtrees.size());
    for (size_t i = 0; i < inCore.nodes.size(); ++i) {
        const CullingHierarchy::Node& a = fromFile.nodes[i];
        const CullingHierarchy::Node& b = inCore.nodes[i];
        const std::string what = "node " + std::to_string(i);
        expectSameBox(a.boxMin, a.boxMax, b.boxMin, b.boxMax, what);
        EXPECT_EQ(a.firstChild, b.firstChild) << what;
        EXPECT_EQ(a.subtree, b.subtree) << what;
        ASSERT_EQ(a.tightCount, b.tightCount) << what;
        for (uint32_t c = 0; c < a.tightCount; ++c) {
            expectSameBox(a.tightMin[c], a.tightMax[c], b.tightMin[c], b.tightMax[c], what + " tight " + std::to_string(c));
        }
    }
    for (size_t i = 0; i < inCore.subtrees.size(); ++i) {
        const std::string what = "subtree " + std::to_string(i);
        EXPECT_EQ(fromFile.subtrees[i].node, inCore.subtrees[i].node) << what;
        EXPECT_EQ(fromFile.subtrees[i].height, inCore.subtrees[i].height) << what;
        EXPECT_EQ(fromFile.subtrees[i].triangles, inCore.subtrees[i].triangles) << what;
        EXPECT_EQ(fromFile.subtrees[i].bvhNode, inCore.subtrees[i].bvhNode) << what;
    }
}

TEST(ChsCullingHierarchy, StreamedFileHasExactlyTheFileSubtrees) {
    test::ScratchDir dir;
    const auto file = dir.file("streamed.chs");
    const outofcore::PrepareReport report = test::prepareSmall("city:200k", file, 4000, 20ull << 20);
    ASSERT_GT(report.chunks, 2u);
    const outofcore::ChsFile chs(file);
    const CullingHierarchy h = outofcore::buildCullingHierarchy(chs);
    ASSERT_EQ(h.nodes.size(), chs.upperNodes().size());
    ASSERT_EQ(h.subtrees.size(), chs.subtrees().size());
    uint64_t triangles = 0;
    uint32_t terminal = 0;
    for (size_t i = 0; i < h.subtrees.size(); ++i) {
        const outofcore::ChsSubtreeRecord& r = chs.subtrees()[i];
        const CullingHierarchy::Subtree& s = h.subtrees[i];
        EXPECT_EQ(s.node, r.upperNode);
        EXPECT_EQ(s.bvhNode, r.upperNode);
        EXPECT_EQ(s.triangles, r.triangleCount);
        EXPECT_EQ(s.height, r.height);
        EXPECT_EQ(h.nodes[s.node].subtree, i);
        EXPECT_EQ(h.nodes[s.node].boxMin, glm::vec3(r.boundsMin[0], r.boundsMin[1], r.boundsMin[2]));
        EXPECT_EQ(h.nodes[s.node].boxMax, glm::vec3(r.boundsMax[0], r.boundsMax[1], r.boundsMax[2]));
        EXPECT_LE(s.height, h.maxSubtreeHeight);
        triangles += s.triangles;
    }
    // Every node is reachable from the root, every termination root is a subtree, children lie in their parent.
    std::vector<uint32_t> stack = {0};
    std::vector<uint8_t> reached(h.nodes.size(), 0);
    while (!stack.empty()) {
        const uint32_t n = stack.back();
        stack.pop_back();
        ASSERT_FALSE(reached[n]);
        reached[n] = 1;
        const CullingHierarchy::Node& node = h.nodes[n];
        if (node.isTerminal()) {
            ++terminal;
            continue;
        }
        for (uint32_t c = 0; c < 2; ++c) {
            const CullingHierarchy::Node& child = h.nodes[node.firstChild + c];
            EXPECT_TRUE(glm::all(glm::lessThanEqual(node.boxMin, child.boxMin)));
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(node.boxMax, child.boxMax)));
            stack.push_back(node.firstChild + c);
        }
    }
    EXPECT_EQ(terminal, h.subtrees.size());
    EXPECT_EQ(triangles, chs.header().triangleCount);
}

} // namespace
} // namespace chcrt
