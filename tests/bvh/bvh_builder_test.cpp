// Structural tests of the binned SAH builder: invariants over many inputs and options, SAH quality against
// the object-median build, the depth guarantee, thread-count independence, statistics and progress.
#include "renderer/bvh/bvh.h"
#include "renderer/core/error.h"
#include "tests/bvh/bvh_test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>

namespace chcrt {
namespace {

using test::checkBvhInvariants;

constexpr uint32_t kForcedSplitTriangles = 16; // the builder's cap on SAH leaves

uint32_t leafLimit(const BvhBuildOptions& options) { return std::max(options.maxLeafTriangles, kForcedSplitTriangles); }

bool identicalTrees(const Bvh& a, const Bvh& b) {
    return a.nodes.size() == b.nodes.size() && a.triangles.size() == b.triangles.size() &&
           std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNodeGpu)) == 0 &&
           std::memcmp(a.triangles.data(), b.triangles.data(), a.triangles.size() * sizeof(TriangleGpu)) == 0;
}

TEST(BvhBuilder, EmptySceneThrows) {
    Scene scene;
    scene.materials.push_back(Material{});
    EXPECT_THROW(buildBvh(scene), InputError);
}

TEST(BvhBuilder, BadInputThrows) {
    Scene scene = test::makeTriangleSoup(10, 1);
    BvhBuildOptions options;
    options.binCount = 1;
    EXPECT_THROW(buildBvh(scene, options), InputError);
    options = {};
    options.maxLeafTriangles = 0;
    EXPECT_THROW(buildBvh(scene, options), InputError);
    scene.triangles[3].y = uint32_t(scene.positions.size());
    EXPECT_THROW(buildBvh(scene), InputError);
}

TEST(BvhBuilder, SingleTriangleIsOneLeaf) {
    const Scene scene = test::makeTriangleSoup(1, 2);
    const Bvh bvh = buildBvh(scene);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_TRUE(bvh.isLeaf(0));
    EXPECT_EQ(bvh.triangles[0].originalId, 0u);
    EXPECT_TRUE(checkBvhInvariants(bvh, scene, 1));
    EXPECT_EQ(bvh.stats.maxDepth, 0u);
}

// Invariants over sizes around the leaf size and the phase boundaries, and over the build options.
TEST(BvhBuilder, InvariantsOverSizesAndOptions) {
    for (uint32_t count : {2u, 3u, 5u, 17u, 100u, 5000u, 20000u}) {
        const Scene scene = test::makeTriangleSoup(count, 10 + count);
        for (uint32_t maxLeaf : {1u, 4u, 8u}) {
            for (uint32_t bins : {2u, 8u, 32u}) {
                for (bool median : {false, true}) {
                    BvhBuildOptions options;
                    options.maxLeafTriangles = maxLeaf;
                    options.binCount = bins;
                    options.medianSplit = median;
                    options.threads = 2;
                    const Bvh bvh = buildBvh(scene, options);
                    EXPECT_TRUE(checkBvhInvariants(bvh, scene, median ? maxLeaf : leafLimit(options)))
                        << count << " triangles, leaf " << maxLeaf << ", bins " << bins << ", median " << median;
                }
            }
        }
    }
}

TEST(BvhBuilder, MedianBuildIsBalanced) {
    const Scene scene = test::makeTriangleSoup(1000, 3);
    BvhBuildOptions options;
    options.medianSplit = true;
    options.maxLeafTriangles = 1;
    const Bvh bvh = buildBvh(scene, options);
    EXPECT_EQ(bvh.stats.leafCount, 1000u);
    EXPECT_EQ(bvh.stats.maxDepth, 10u); // ceil(log2(1000))
}

TEST(BvhBuilder, StructuredAndClusteredInputsAreValid) {
    const Scene grid = test::makeHeightfield(120, 4);
    EXPECT_TRUE(checkBvhInvariants(buildBvh(grid), grid, kForcedSplitTriangles));
    const Scene clusters = test::makeClusteredSoup(30000, 7, 5);
    EXPECT_TRUE(checkBvhInvariants(buildBvh(clusters), clusters, kForcedSplitTriangles));
}

// All centroids coincide: no plane separates them, so the builder must fall back to median splits.
TEST(BvhBuilder, CoincidentCentroidsFallBackToMedian) {
    Scene scene = test::makeTriangleSoup(0, 6);
    for (int i = 0; i < 100; ++i) {
        test::addTriangle(scene, glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    }
    const Bvh bvh = buildBvh(scene);
    EXPECT_TRUE(checkBvhInvariants(bvh, scene, kForcedSplitTriangles));
    EXPECT_GT(bvh.stats.leafCount, 1u);
}

// Exponentially spaced triangles: every SAH split peels off a few, so only the depth guard keeps the tree
// shallower than the traversal stack.
TEST(BvhBuilder, DepthStaysBelowStackSizeOnAdversarialInput) {
    const Scene scene = test::makeExponentialRow(3000);
    for (uint32_t maxLeaf : {1u, 4u}) {
        BvhBuildOptions options;
        options.maxLeafTriangles = maxLeaf;
        const Bvh bvh = buildBvh(scene, options);
        EXPECT_TRUE(checkBvhInvariants(bvh, scene, leafLimit(options)));
        EXPECT_LT(bvh.stats.maxDepth, uint32_t(CHCRT_MAX_BVH_DEPTH));
        EXPECT_GT(bvh.stats.maxDepth, 40u) << "input no longer adversarial: the guard is not exercised";
    }
}

// NaN vertices are rejected by validateScene; given anyway, the build must still end with every triangle
// in exactly one leaf.
TEST(BvhBuilder, NanVerticesTerminate) {
    Scene scene = test::makeTriangleSoup(3000, 8);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (size_t i = 0; i < scene.positions.size(); i += 7) {
        scene.positions[i][int(i % 3)] = nan;
    }
    for (size_t i = 1; i < 60; i += 3) {
        scene.positions[i] = glm::vec3(nan);
    }
    const Bvh bvh = buildBvh(scene);
    EXPECT_TRUE(checkBvhInvariants(bvh, scene, kForcedSplitTriangles, /*checkBounds=*/false));
    EXPECT_LT(bvh.stats.maxDepth, uint32_t(CHCRT_MAX_BVH_DEPTH));
}

TEST(BvhBuilder, SahBeatsMedianOnRandomClusteredAndStructuredScenes) {
    const Scene scenes[] = {test::makeTriangleSoup(20000, 9), test::makeClusteredSoup(20000, 5, 10),
                            test::makeHeightfield(100, 11)};
    for (const Scene& scene : scenes) {
        BvhBuildOptions median;
        median.medianSplit = true;
        const Bvh sahBvh = buildBvh(scene);
        const Bvh medianBvh = buildBvh(scene, median);
        EXPECT_LT(sahBvh.stats.sahCost, medianBvh.stats.sahCost) << scene.name;
    }
    // Clusters far apart are where object medians hurt most: expect a clear margin there.
    BvhBuildOptions median;
    median.medianSplit = true;
    EXPECT_LT(buildBvh(scenes[1]).stats.sahCost, 0.8 * buildBvh(scenes[1], median).stats.sahCost);
}

// Large enough for both phases (parallel binning above 64K triangles, many subtrees).
TEST(BvhBuilder, IdenticalForAnyThreadCount) {
    const Scene scene = test::makeTriangleSoup(150000, 12);
    BvhBuildOptions options;
    options.threads = 1;
    const Bvh single = buildBvh(scene, options);
    EXPECT_TRUE(checkBvhInvariants(single, scene, leafLimit(options)));
    for (uint32_t threads : {2u, 3u}) {
        options.threads = threads;
        const Bvh multi = buildBvh(scene, options);
        EXPECT_TRUE(checkBvhInvariants(multi, scene, leafLimit(options))) << threads << " threads";
        EXPECT_TRUE(identicalTrees(single, multi)) << threads << " threads";
    }
    options.threads = 2;
    EXPECT_TRUE(identicalTrees(buildBvh(scene, options), buildBvh(scene, options)));
}

TEST(BvhBuilder, StatisticsMatchTheTree) {
    const Scene scene = test::makeClusteredSoup(10000, 4, 13);
    const Bvh bvh = buildBvh(scene);
    const BvhStats& stats = bvh.stats;
    EXPECT_EQ(stats.nodeCount, bvh.nodes.size());
    uint32_t leaves = 0;
    for (uint32_t i = 0; i < bvh.nodes.size(); ++i) {
        leaves += bvh.isLeaf(i) ? 1 : 0;
    }
    EXPECT_EQ(stats.leafCount, leaves);
    EXPECT_EQ(stats.nodeCount, 2 * stats.leafCount - 1);
    EXPECT_DOUBLE_EQ(stats.averageLeafTriangles, 10000.0 / leaves);
    EXPECT_EQ(stats.bytes, bvh.nodes.size() * 32 + bvh.triangles.size() * 48);
    EXPECT_DOUBLE_EQ(stats.sahCost, computeSahCost(bvh));
    EXPECT_GT(stats.buildSeconds, 0.0);
    EXPECT_GT(stats.maxDepth, 0u);
    const Aabb root = bvh.rootBounds();
    const Aabb sceneBox = scene.bounds();
    EXPECT_EQ(root.lower, sceneBox.lower);
    EXPECT_EQ(root.upper, sceneBox.upper);
}

// Two unit-sized triangles 10 apart on x with one-triangle leaves: root + two leaves, cost by hand.
TEST(BvhBuilder, SahCostOfAHandMadeTree) {
    Scene scene = test::makeTriangleSoup(0, 0);
    test::addTriangle(scene, glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 1));
    test::addTriangle(scene, glm::vec3(10, 0, 0), glm::vec3(11, 0, 0), glm::vec3(10, 1, 1));
    BvhBuildOptions options;
    options.maxLeafTriangles = 1;
    const Bvh bvh = buildBvh(scene, options);
    ASSERT_EQ(bvh.nodes.size(), 3u);
    const double rootArea = 2.0 * (11 * 1 + 1 * 1 + 1 * 11); // 11 x 1 x 1
    const double leafArea = 2.0 * 3;                          // 1 x 1 x 1
    EXPECT_DOUBLE_EQ(computeSahCost(bvh, 1.0f, 1.0f), 1.0 + 2 * leafArea / rootArea);
    EXPECT_DOUBLE_EQ(computeSahCost(bvh, 2.0f, 3.0f), 2.0 + 2 * 3.0 * leafArea / rootArea);
}

class RecordingProgress final : public Progress {
public:
    void begin(const std::string& text, uint64_t count) override {
        label = text;
        total = count;
        ++begins;
    }
    void update(uint64_t done) override {
        const std::lock_guard lock(mutex);
        monotone = monotone && done >= last; // per-worker flushes arrive in order of the shared counter
        last = std::max(last, done);
        ++updates;
    }
    void end() override { ++ends; }

    std::mutex mutex;
    std::string label;
    uint64_t total = 0;
    uint64_t last = 0;
    int begins = 0;
    int ends = 0;
    int updates = 0;
    bool monotone = true;
};

TEST(BvhBuilder, ReportsProgress) {
    const Scene scene = test::makeTriangleSoup(100000, 14);
    RecordingProgress progress;
    BvhBuildOptions options;
    options.threads = 1; // one worker: updates strictly in order
    buildBvh(scene, options, progress);
    EXPECT_EQ(progress.label, "Building BVH");
    EXPECT_EQ(progress.total, 100000u);
    EXPECT_EQ(progress.begins, 1);
    EXPECT_EQ(progress.ends, 1);
    EXPECT_GT(progress.updates, 1);
    EXPECT_TRUE(progress.monotone);
    EXPECT_EQ(progress.last, 100000u);
}

} // namespace
} // namespace chcrt
