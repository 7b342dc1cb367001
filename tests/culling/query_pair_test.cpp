// The query-pair hierarchy's split heuristic and tiles (CHC+RT §4.4, §5.2) and the visibility state's
// subdivision and one-level pull-up (§5.1).
#include "culling/query_pair_hierarchy.h"
#include "culling/visibility_state.h"

#include "renderer/scene/procedural/procedural.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

TEST(SplitHeuristic, ComparesNormalizedAreasWeightedByTq) {
    // A_bvh/A_root > tq * A_tile/A_screen -> object space.
    EXPECT_TRUE(preferObjectSplit(1.0f, 1.0f, 100, 100, 0.5f));   // root pair: 1 > 0.5
    EXPECT_FALSE(preferObjectSplit(0.4f, 1.0f, 100, 100, 0.5f));  // 0.4 < 0.5
    EXPECT_TRUE(preferObjectSplit(0.6f, 1.0f, 100, 100, 0.5f));
    EXPECT_FALSE(preferObjectSplit(0.1f, 1.0f, 25, 100, 0.5f));   // 0.1 < 0.125
    EXPECT_TRUE(preferObjectSplit(0.2f, 1.0f, 25, 100, 0.5f));    // 0.2 > 0.125
    EXPECT_FALSE(preferObjectSplit(0.5f, 1.0f, 100, 100, 1.0f));  // equal is a screen split
}

TEST(SplitTile, QuadrantsCoverTheTileExactly) {
    for (int w : {1, 7, 64, 65, 96, 512}) {
        for (int h : {1, 5, 64, 72, 512}) {
            const Tile tile{3, 9, w, h};
            std::array<Tile, 4> children;
            if (w <= 16 && h <= 16) continue; // decideSplit never splits these
            const int count = splitTile(tile, 16, children);
            ASSERT_GE(count, 2);
            int64_t area = 0;
            for (int i = 0; i < count; ++i) {
                const Tile& c = children[size_t(i)];
                EXPECT_GT(c.width, 0);
                EXPECT_GT(c.height, 0);
                EXPECT_GE(c.x, tile.x);
                EXPECT_GE(c.y, tile.y);
                EXPECT_LE(c.x + c.width, tile.x + tile.width);
                EXPECT_LE(c.y + c.height, tile.y + tile.height);
                area += c.area();
                for (int j = 0; j < i; ++j) {
                    const Tile& d = children[size_t(j)];
                    const bool disjoint = c.x >= d.x + d.width || d.x >= c.x + c.width || c.y >= d.y + d.height ||
                                          d.y >= c.y + c.height;
                    EXPECT_TRUE(disjoint);
                }
            }
            EXPECT_EQ(area, tile.area());
        }
    }
}

TEST(DecideSplit, TerminatesOnlyAtMinimumTileAndTerminationRoot) {
    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec("city:5k", spec));
    const Bvh bvh = buildBvh(generateProceduralScene(spec));
    SubtreePartitionOptions po;
    po.maxSubtreeHeight = 4;
    const SubtreePartition partition(bvh, po);
    ASSERT_FALSE(partition.isRoot(0));
    QueryPairOptions options;
    options.minTileSize = 64;
    // Root pair on the whole screen: A_bvh/A_root = 1 > 0.5 -> object split.
    EXPECT_EQ(decideSplit(Tile{0, 0, 512, 512}, 0, partition, 512, 512, options), PairSplit::Object);
    // Minimum tile: only object splits remain.
    EXPECT_EQ(decideSplit(Tile{0, 0, 64, 64}, 0, partition, 512, 512, options), PairSplit::Object);
    const uint32_t root = partition.roots().front();
    EXPECT_EQ(decideSplit(Tile{0, 0, 512, 512}, root, partition, 512, 512, options), PairSplit::Screen);
    EXPECT_EQ(decideSplit(Tile{0, 0, 64, 64}, root, partition, 512, 512, options), PairSplit::None);
}

TEST(VisibilityState, PullUpMergesOneLevelPerCall) {
    VisibilityState state(128, 128, 1);
    ASSERT_EQ(state.pairCount(), 1u);
    std::array<Tile, 4> tiles;
    const int count = splitTile(state.pair(0).tile, 32, tiles);
    ASSERT_EQ(count, 4);
    const std::array<uint32_t, 4> nodes{0, 0, 0, 0};
    std::array<int32_t, 4> children;
    state.subdivide(0, tiles.data(), nodes.data(), 4, children.data(), 3);
    std::array<Tile, 4> grand;
    ASSERT_EQ(splitTile(state.pair(children[0]).tile, 32, grand), 4);
    std::array<int32_t, 4> grandChildren;
    state.subdivide(children[0], grand.data(), nodes.data(), 4, grandChildren.data(), 3);
    EXPECT_EQ(state.pairCount(), 9u);
    std::vector<int32_t> visible, invisible;
    state.collectLeaves(visible, invisible);
    EXPECT_EQ(visible.size(), 0u);
    EXPECT_EQ(invisible.size(), 7u);
    // Mark one grandchild visible: its parent cannot merge; the root cannot merge either (child interior).
    state.pair(grandChildren[2]).visible = true;
    EXPECT_EQ(state.pullUpInvisibility(), 0);
    state.pair(grandChildren[2]).visible = false;
    // All invisible: one level per call.
    EXPECT_EQ(state.pullUpInvisibility(), 1);
    EXPECT_EQ(state.pairCount(), 5u);
    EXPECT_EQ(state.pullUpInvisibility(), 1);
    EXPECT_EQ(state.pairCount(), 1u);
    EXPECT_TRUE(state.pair(0).isLeaf());
    EXPECT_FALSE(state.pair(0).visible);
}

} // namespace
} // namespace chcrt
