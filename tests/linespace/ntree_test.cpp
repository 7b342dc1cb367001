// N-tree with binary Line Spaces on its subdivided nodes: cells partition their parent and hold exactly the
// triangles that overlap them; a shaft is marked iff a non-empty child meets it (exact oracle), and no shaft
// marked empty contains geometry (random segments between its patches, brute force).
#include "linespace/ntree.h"
#include "linespace/shaft_geometry.h"
#include "linespace/shaft_index.h"
#include "renderer/core/error.h"
#include "renderer/core/memory_budget.h"
#include "shaders/shared/intersect.h"
#include "tests/linespace/linespace_test_util.h"

#include <gtest/gtest.h>

namespace chcrt::ls {
namespace {

TEST(NTree, CellsHoldExactlyTheirTriangles) {
    const Bvh bvh = buildBvh(test::makeScene(test::randomSoup(600, 12)));
    NTreeParams params;
    params.n = 4;
    params.depth = 2;
    const NTree tree = buildNTree(bvh, params);
    const Aabb root = tree.nodes[0].bounds();
    EXPECT_TRUE(root.contains(bvh.rootBounds()));
    EXPECT_FLOAT_EQ(root.extent().x, root.extent().y);
    uint32_t subdivided = 0;
    for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
        const NTreeNode& node = tree.nodes[i];
        EXPECT_LE(node.level, params.depth);
        const bool shouldSplit = node.level < params.depth && node.triangleCount > 0;
        ASSERT_EQ(node.firstChild != kNoChild, shouldSplit) << "node " << i;
        if (!shouldSplit) {
            continue;
        }
        EXPECT_EQ(node.space, subdivided++);
        for (uint32_t c = 0; c < 64; ++c) {
            const NTreeNode& child = tree.nodes[node.firstChild + c];
            EXPECT_FLOAT_EQ(child.size, node.size / 4.0f);
            EXPECT_TRUE(node.bounds().contains(Aabb{child.lower + 1e-5f, child.lower + glm::vec3(child.size) - 1e-5f}));
            // Brute force: the parent's triangles overlapping the child cube are exactly the child's list.
            const BoxD cell{glm::dvec3(child.lower), glm::dvec3(child.lower + glm::vec3(child.size))};
            std::vector<uint32_t> expected;
            for (uint32_t r = 0; r < node.triangleCount; ++r) {
                const uint32_t t = tree.triangleRefs[node.firstTriangle + r];
                const TriangleGpu& tri = bvh.triangles[t];
                if (shaftOverlapsTriangle(ShaftVolume(cell, cell), tri.v0, tri.v1, tri.v2)) {
                    expected.push_back(t);
                }
            }
            const std::vector<uint32_t> actual(tree.triangleRefs.begin() + child.firstTriangle,
                                               tree.triangleRefs.begin() + child.firstTriangle + child.triangleCount);
            EXPECT_EQ(actual, expected);
        }
    }
    EXPECT_EQ(tree.stats.subdividedCount, subdivided);
    EXPECT_GT(subdivided, 10u);
    EXPECT_THROW(buildNTree(bvh, NTreeParams{1, 3, 0}), InputError);
}

TEST(NTree, BinaryLineSpaceMarksExactlyTheShaftsMeetingNonEmptyChildren) {
    const Bvh bvh = buildBvh(test::makeScene(test::randomSoup(400, 13)));
    for (const uint32_t n : {3u, 5u}) {
        NTreeParams params;
        params.n = n;
        params.depth = 2;
        const NTree tree = buildNTree(bvh, params);
        const double dilation = shaftDilationForScene(bvh.rootBounds());
        test::Rng rng{n};
        uint64_t empty = 0, filled = 0;
        for (uint32_t i = 0; i < tree.nodes.size(); i += 7) {
            const NTreeNode& node = tree.nodes[i];
            if (node.firstChild == kNoChild) {
                continue;
            }
            const Aabb box = node.bounds();
            for (uint32_t s = 0; s < lsShaftCount(n, true); ++s) {
                const ShaftPatches p = decodeShaft(s, n, true);
                auto region = [&](uint32_t face, uint32_t patch, double grow) {
                    return patchRegion(box, n, PatchRect{face, patch % n, patch % n + 1, patch / n, patch / n + 1}, grow);
                };
                bool exact = false, dilated = false;
                for (uint32_t c = 0; c < n * n * n; ++c) {
                    const NTreeNode& child = tree.nodes[node.firstChild + c];
                    if (child.triangleCount == 0) {
                        continue;
                    }
                    const glm::dvec3 lo(child.lower), hi(child.lower + glm::vec3(child.size));
                    exact = exact || test::hullMeetsBox(region(p.startFace, p.startPatch, 0.0), region(p.endFace, p.endPatch, 0.0), lo, hi);
                    dilated = dilated ||
                              test::hullMeetsBox(region(p.startFace, p.startPatch, dilation), region(p.endFace, p.endPatch, dilation), lo, hi);
                }
                const bool bit = tree.binaryFilled(node.space, s);
                ASSERT_TRUE(!exact || bit) << "node " << i << " shaft " << s;
                ASSERT_TRUE(!bit || dilated) << "node " << i << " shaft " << s;
                if (bit) {
                    ++filled;
                    continue;
                }
                ++empty;
                // No geometry of the node in an empty shaft.
                for (int k = 0; k < 8; ++k) {
                    const BoxD ra = region(p.startFace, p.startPatch, 0.0), rb = region(p.endFace, p.endPatch, 0.0);
                    const glm::vec3 a(rng.uniform(float(ra.lower.x), float(ra.upper.x)), rng.uniform(float(ra.lower.y), float(ra.upper.y)),
                                      rng.uniform(float(ra.lower.z), float(ra.upper.z)));
                    const glm::vec3 b(rng.uniform(float(rb.lower.x), float(rb.upper.x)), rng.uniform(float(rb.lower.y), float(rb.upper.y)),
                                      rng.uniform(float(rb.lower.z), float(rb.upper.z)));
                    for (uint32_t r = 0; r < node.triangleCount; ++r) {
                        const TriangleGpu& t = bvh.triangles[tree.triangleRefs[node.firstTriangle + r]];
                        const float th = gpu::intersectRayTriangle(a, b - a, t.v0, t.v1, t.v2).x;
                        ASSERT_FALSE(th >= 0.0f && th <= 1.0f) << "empty shaft " << s << " of node " << i << " holds geometry";
                    }
                }
            }
        }
        EXPECT_GT(empty, 500u) << "N=" << n;
        EXPECT_GT(filled, 500u) << "N=" << n;
    }
}

} // namespace
} // namespace chcrt::ls

namespace chcrt::ls {
namespace {

// --max-memory-mb bounds the N-tree as it grows (its size depends on where the triangles lie): a budget below what
// the tree needs is a one-line InputError naming it, raised before the tree has grown past the budget; the same build
// fits a budget of what it needed.
TEST(NTree, GrowsOnlyWithinTheMemoryBudget) {
    const Bvh bvh = buildBvh(test::makeScene(test::randomSoup(600, 12)));
    NTreeParams params;
    params.n = 4;
    params.depth = 3;
    const uint64_t saved = memoryBudgetBytes();
    const NTree tree = buildNTree(bvh, params);
    const uint64_t needed = 2 * (tree.nodes.size() * sizeof(NTreeNode) + tree.triangleRefs.size() * sizeof(uint32_t) +
                                 tree.binaryWords.size() * sizeof(uint32_t));
    setMemoryBudgetBytes(needed / 4);
    try {
        buildNTree(bvh, params);
        ADD_FAILURE() << "an N-tree needing " << needed << " bytes was built within " << needed / 4;
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("N-tree"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("--max-memory-mb"), std::string::npos) << e.what();
    }
    setMemoryBudgetBytes(needed + 2 * uint64_t(params.n * params.n * params.n) * sizeof(NTreeNode));
    EXPECT_NO_THROW(buildNTree(bvh, params));
    setMemoryBudgetBytes(saved);
}

} // namespace
} // namespace chcrt::ls
