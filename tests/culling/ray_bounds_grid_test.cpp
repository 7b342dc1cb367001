// RayBoundsGrid (culling/ray_bounds_grid.h): the CPU side's decisions from given cell boxes — pieces, the coarse
// level, the rounding pad, empty, unbounded and NaN cells. The GPU reduction is tested in ray_bounds_grid_gl_test.
#include "culling/ray_bounds_grid.h"
#include "shaders/shared/culling_layout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace chcrt {
namespace {

constexpr float kEmpty = float(CHCRT_CULLING_CELL_EMPTY);
constexpr float kBounded = float(CHCRT_CULLING_CELL_BOUNDED);
constexpr float kUnbounded = float(CHCRT_CULLING_CELL_UNBOUNDED);

// A 64×32 ray set in cells of 16² pixels (4×2 cells), all empty but the ones set, in the read-back layout: per cell
// a header, the origins' box and the boxes of the pieces + 1 points that split the segments, then the ray interval
// (direction components and segment range; by default directions spread too wide for the frustum test, so the
// pieces alone decide).
struct Cells {
    int pieces;
    std::vector<glm::vec4> buffer;
    explicit Cells(int pieceCount) : pieces(pieceCount), buffer(size_t(8 * stride()), glm::vec4(0.0f)) {
        for (int cy = 0; cy < 2; ++cy) {
            for (int cx = 0; cx < 4; ++cx) {
                header(cx, cy, kEmpty, 0.0f, 0.0f);
                interval(cx, cy, glm::vec3(-1.0f), glm::vec3(1.0f), 0.0f, 1.0e3f);
            }
        }
    }
    int stride() const { return CHCRT_CULLING_BOUNDS_STRIDE(pieces); }
    void interval(int cx, int cy, glm::vec3 directionLo, glm::vec3 directionHi, float t0, float t1) {
        const size_t base = size_t((cy * 4 + cx) * stride()) + size_t(1 + 2 * (pieces + 2));
        buffer[base] = glm::vec4(directionLo, t0);
        buffer[base + 1] = glm::vec4(directionHi, t1);
    }
    void header(int cx, int cy, float state, float extent, float directionLength = 1.0f) {
        buffer[size_t((cy * 4 + cx) * stride())] = glm::vec4(state, extent, directionLength, 0.0f);
    }
    // Box j of cell (cx, cy): 0 = the origins, 1 + k = point k of the segments.
    void box(int cx, int cy, int j, glm::vec3 lo, glm::vec3 hi) {
        const size_t base = size_t((cy * 4 + cx) * stride());
        buffer[base + 1 + 2 * size_t(j)] = glm::vec4(lo, 0.0f);
        buffer[base + 2 + 2 * size_t(j)] = glm::vec4(hi, 0.0f);
    }
    // Every point's box (so every piece) and the origins' box the same.
    void setAll(int cx, int cy, glm::vec3 lo, glm::vec3 hi, float state = kBounded, float extent = 1.0f) {
        header(cx, cy, state, extent);
        for (int j = 0; j < pieces + 2; ++j) box(cx, cy, j, lo, hi);
    }
};

RayBoundsGrid makeGrid(const Cells& cells, int coarseCells = 2) {
    RayBoundsGrid grid(RayBoundsOptions{16, cells.pieces, coarseCells});
    grid.setCells(64, 32, cells.buffer);
    return grid;
}

bool reach(const RayBoundsGrid& grid, Tile tile, glm::vec3 lo, glm::vec3 hi) {
    return grid.mayReach(tile, &lo, &hi, 1);
}

TEST(RayBoundsGrid, TilesReachOnlyWhatTheirCellsBoxesOverlap) {
    for (int coarse : {1, 2, 4}) {
        SCOPED_TRACE(coarse);
        Cells cells(1);
        cells.setAll(1, 0, glm::vec3(0.0f), glm::vec3(1.0f)); // pixels x 16..31, y 0..15
        cells.setAll(3, 1, glm::vec3(10.0f, 0.0f, 0.0f), glm::vec3(11.0f, 1.0f, 1.0f));
        const RayBoundsGrid grid = makeGrid(cells, coarse);
        const Tile all{0, 0, 64, 32}, left{0, 0, 16, 32}, cell10{16, 0, 16, 16}, bottomRight{32, 16, 32, 16};
        EXPECT_FALSE(reach(grid, left, glm::vec3(-100.0f), glm::vec3(100.0f))) << "no active ray in the tile";
        EXPECT_TRUE(reach(grid, cell10, glm::vec3(0.5f), glm::vec3(2.0f)));
        EXPECT_FALSE(reach(grid, cell10, glm::vec3(5.0f), glm::vec3(6.0f)));
        EXPECT_FALSE(reach(grid, cell10, glm::vec3(10.0f, 0.0f, 0.0f), glm::vec3(11.0f, 1.0f, 1.0f))); // other cell's
        EXPECT_TRUE(reach(grid, bottomRight, glm::vec3(10.5f, 0.5f, 0.5f), glm::vec3(10.6f)));
        EXPECT_TRUE(reach(grid, all, glm::vec3(10.5f, 0.5f, 0.5f), glm::vec3(12.0f)));
        EXPECT_FALSE(reach(grid, all, glm::vec3(3.0f), glm::vec3(4.0f)));
        // A tile reaching past the ray set's edge only sees the cells inside it.
        EXPECT_TRUE(reach(grid, Tile{48, 16, 64, 64}, glm::vec3(10.5f, 0.5f, 0.5f), glm::vec3(10.6f)));
        // Several boxes: reachable when one is.
        const glm::vec3 lo[2] = {glm::vec3(5.0f), glm::vec3(0.9f)}, hi[2] = {glm::vec3(6.0f), glm::vec3(3.0f)};
        EXPECT_TRUE(grid.mayReach(cell10, lo, hi, 2));
        EXPECT_FALSE(grid.mayReach(cell10, lo, hi, 1));
        EXPECT_TRUE(grid.cellMayReach(1, 0, lo, hi, 2));
        EXPECT_FALSE(grid.cellMayReach(0, 0, lo, hi, 2));
    }
}

TEST(RayBoundsGrid, PiecesFollowADiagonalSegment) {
    // A segment from (0,0,0) to (8,8,0) in four pieces: a box beside its middle, inside the one box around the whole
    // segment, is not reached; boxes on the segment are.
    Cells cells(4);
    cells.header(0, 0, kBounded, 8.0f);
    cells.box(0, 0, 0, glm::vec3(0.0f), glm::vec3(0.0f));
    for (int j = 0; j <= 4; ++j) cells.box(0, 0, 1 + j, glm::vec3(2.0f * j, 2.0f * j, 0.0f), glm::vec3(2.0f * j, 2.0f * j, 0.0f));
    const RayBoundsGrid grid = makeGrid(cells);
    const Tile tile{0, 0, 16, 16};
    EXPECT_FALSE(reach(grid, tile, glm::vec3(6.0f, 0.0f, -1.0f), glm::vec3(7.0f, 1.0f, 1.0f)));
    EXPECT_TRUE(reach(grid, tile, glm::vec3(3.0f, 3.0f, -1.0f), glm::vec3(3.5f, 3.5f, 1.0f)));
    EXPECT_TRUE(reach(grid, tile, glm::vec3(7.5f, 7.5f, -1.0f), glm::vec3(9.0f, 9.0f, 1.0f)));
    // The coarse level (every piece's union) must not lose the segment either.
    EXPECT_TRUE(reach(grid, Tile{0, 0, 64, 32}, glm::vec3(3.0f, 3.0f, -1.0f), glm::vec3(3.5f, 3.5f, 1.0f)));
}

TEST(RayBoundsGrid, TheFrustumCullsBoxesInsideAPieceThatNoRayMeets) {
    // Rays from the origin along +x, directions x in [0.99, 1], y and z in [0, 0.05], t in [0, 10]: one piece holds
    // the whole segment bundle (a box up to y = z = 0.5), the frustum only y, z <= 0.05 t.
    Cells cells(1);
    cells.header(0, 0, kBounded, 10.0f);
    cells.box(0, 0, 0, glm::vec3(0.0f), glm::vec3(0.0f));
    cells.box(0, 0, 1, glm::vec3(0.0f), glm::vec3(0.0f));
    cells.box(0, 0, 2, glm::vec3(9.9f, 0.0f, 0.0f), glm::vec3(10.0f, 0.5f, 0.5f));
    cells.interval(0, 0, glm::vec3(0.99f, 0.0f, 0.0f), glm::vec3(1.0f, 0.05f, 0.05f), 0.0f, 10.0f);
    const Tile tile{0, 0, 16, 16};
    RayBoundsGrid grid = makeGrid(cells);
    const glm::vec3 besideLo(5.0f, 0.4f, 0.0f), besideHi(5.1f, 0.45f, 0.1f); // in the piece, y far above 0.05 t
    const glm::vec3 onLo(5.0f, 0.1f, 0.0f), onHi(5.1f, 0.2f, 0.1f);          // rays of y/x in [0.02, 0.04] meet it
    const glm::vec3 behindLo(-2.0f, 0.0f, 0.0f), behindHi(-1.0f, 0.1f, 0.1f); // t < 0: behind the origins
    EXPECT_FALSE(reach(grid, tile, besideLo, besideHi));
    EXPECT_TRUE(reach(grid, tile, onLo, onHi));
    EXPECT_FALSE(reach(grid, tile, behindLo, behindHi));
    EXPECT_TRUE(grid.cellMayReach(0, 0, &onLo, &onHi, 1));
    // Counted by the shape that decided: the beside box and the box behind passed a piece? Only the first did.
    grid.resetDecisions();
    EXPECT_FALSE(grid.cellMayReach(0, 0, &besideLo, &besideHi, 1));
    EXPECT_FALSE(grid.cellMayReach(0, 0, &behindLo, &behindHi, 1));
    EXPECT_TRUE(grid.cellMayReach(0, 0, &onLo, &onHi, 1));
    EXPECT_EQ(grid.decisions().frustum, 1u);
    EXPECT_EQ(grid.decisions().pieces, 1u);
    EXPECT_EQ(grid.decisions().reached, 1u);
    // Without the frustum the pieces alone decide; a cell whose directions fan out wider than
    // CHCRT_CULLING_FRUSTUM_MAX_SPREAD gets no frustum test either.
    RayBoundsGrid noFrustum(RayBoundsOptions{16, 1, 2, 1.0f / 4096.0f, false});
    noFrustum.setCells(64, 32, cells.buffer);
    EXPECT_TRUE(reach(noFrustum, tile, besideLo, besideHi));
    cells.interval(0, 0, glm::vec3(0.3f, 0.0f, 0.0f), glm::vec3(1.0f, 0.05f, 0.05f), 0.0f, 10.0f);
    EXPECT_TRUE(reach(makeGrid(cells), tile, besideLo, besideHi));
}

TEST(RayBoundsGrid, TheFrustumIsConservativeForEveryRayOfItsIntervals) {
    // Random rays inside one cell's intervals, and boxes around points of those rays: every such box must be reached.
    std::mt19937 random(3);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int trial = 0; trial < 200; ++trial) {
        const glm::vec3 oLo(unit(random) * 10.0f, unit(random) * 10.0f, unit(random) * 10.0f);
        const glm::vec3 oHi = oLo + glm::vec3(unit(random), unit(random), unit(random));
        glm::vec3 dLo(unit(random) * 2.0f - 1.0f, unit(random) * 2.0f - 1.0f, unit(random) * 2.0f - 1.0f);
        const glm::vec3 dHi = dLo + glm::vec3(unit(random), unit(random), unit(random)) * 0.4f;
        const float t0 = unit(random) * 2.0f, t1 = t0 + unit(random) * 20.0f;
        for (int ray = 0; ray < 20; ++ray) {
            const glm::vec3 o = oLo + (oHi - oLo) * glm::vec3(unit(random), unit(random), unit(random));
            const glm::vec3 d = dLo + (dHi - dLo) * glm::vec3(unit(random), unit(random), unit(random));
            const glm::vec3 p = o + d * (t0 + (t1 - t0) * unit(random));
            const glm::vec3 lo = p - 0.01f, hi = p + 0.01f;
            EXPECT_TRUE(gpu::rayIntervalMayHit(oLo, oHi, dLo, dHi, t0, t1, lo, hi)) << trial << " " << ray;
        }
    }
}

TEST(RayBoundsGrid, BoxesArePaddedByTheExtentAndUnboundedCellsReachEverything) {
    Cells cells(2);
    cells.setAll(0, 0, glm::vec3(1000.0f), glm::vec3(1001.0f));
    cells.setAll(1, 0, glm::vec3(0.0f), glm::vec3(0.0f), kUnbounded);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    cells.setAll(2, 0, glm::vec3(nan), glm::vec3(1.0f)); // a NaN box assumes nothing
    cells.setAll(3, 0, glm::vec3(0.0f), glm::vec3(1.0f), kBounded, 8192.0f); // computed from coordinates ~8192
    const RayBoundsGrid grid = makeGrid(cells);
    // 2^-12 of the magnitude 1001: 1001 + 0.2 still touches, 1001 + 0.5 does not.
    EXPECT_TRUE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(1001.2f, 1000.5f, 1000.5f), glm::vec3(1002.0f)));
    EXPECT_FALSE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(1001.5f, 1000.5f, 1000.5f), glm::vec3(1002.0f)));
    EXPECT_TRUE(reach(grid, Tile{16, 0, 16, 16}, glm::vec3(-1e6f), glm::vec3(-1e6f + 1.0f)));
    EXPECT_TRUE(reach(grid, Tile{32, 0, 16, 16}, glm::vec3(-1e6f), glm::vec3(-1e6f + 1.0f)));
    // The extent widens the pad: 2^-12 of 8192 = 2.
    EXPECT_TRUE(reach(grid, Tile{48, 0, 16, 16}, glm::vec3(2.9f, 0.5f, 0.5f), glm::vec3(4.0f)));
    EXPECT_FALSE(reach(grid, Tile{48, 0, 16, 16}, glm::vec3(3.1f, 0.5f, 0.5f), glm::vec3(4.0f)));
    const std::array<uint32_t, 3> states = grid.cellStates();
    EXPECT_EQ(states[0], 4u);
    EXPECT_EQ(states[1], 2u);
    EXPECT_EQ(states[2], 2u);
}

TEST(RayBoundsGrid, BoxesTouchingAtTheirEdgeAreReachedAndOneUlpBeyondAreNot) {
    // With the pad off, the test is inclusive at exactly the box's edge: a query box starting at the cell box's
    // upper corner is reached, one starting one ulp beyond it is not.
    Cells cells(1);
    cells.setAll(0, 0, glm::vec3(0.0f), glm::vec3(1.0f));
    RayBoundsGrid grid(RayBoundsOptions{16, 1, 2, 0.0f});
    grid.setCells(64, 32, cells.buffer);
    const Tile tile{0, 0, 16, 16};
    EXPECT_TRUE(reach(grid, tile, glm::vec3(1.0f, 0.5f, 0.5f), glm::vec3(2.0f)));
    EXPECT_FALSE(reach(grid, tile, glm::vec3(std::nextafter(1.0f, 2.0f), 0.5f, 0.5f), glm::vec3(2.0f)));
    EXPECT_TRUE(reach(grid, tile, glm::vec3(-1.0f), glm::vec3(0.0f)));
    EXPECT_FALSE(reach(grid, tile, glm::vec3(-1.0f), glm::vec3(std::nextafter(0.0f, -1.0f), 0.5f, 0.5f)));
}

TEST(RayBoundsGrid, WithoutCellsEverythingIsReachable) {
    Cells cells(1);
    cells.setAll(0, 0, glm::vec3(0.0f), glm::vec3(1.0f));
    RayBoundsGrid grid = makeGrid(cells);
    EXPECT_FALSE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(5.0f), glm::vec3(6.0f)));
    grid.forget();
    EXPECT_FALSE(grid.known());
    EXPECT_TRUE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(5.0f), glm::vec3(6.0f)));
    const glm::vec3 lo(5.0f), hi(6.0f);
    EXPECT_TRUE(grid.cellMayReach(0, 0, &lo, &hi, 1));
}

TEST(RayBoundsGrid, EntryLowerBoundsNeverExceedTheDistanceFromTheOrigins) {
    // Origins in [0, 1]³, directions up to length 2: a box 10 away along x is entered at t >= 4.5 (less the margin).
    Cells cells(1);
    cells.setAll(0, 0, glm::vec3(0.0f), glm::vec3(1.0f));
    cells.header(0, 0, kBounded, 1.0f, 2.0f);
    const RayBoundsGrid grid = makeGrid(cells);
    const float bound = grid.entryLowerBound(0, 0, glm::vec3(10.0f, 0.0f, 0.0f), glm::vec3(11.0f, 1.0f, 1.0f));
    EXPECT_LT(bound, 4.5f);
    EXPECT_GT(bound, 4.4f);
    EXPECT_EQ(grid.entryLowerBound(0, 0, glm::vec3(0.5f), glm::vec3(3.0f)), 0.0f) << "origins inside the box";
    EXPECT_EQ(grid.entryLowerBound(1, 0, glm::vec3(10.0f), glm::vec3(11.0f)), 0.0f) << "empty cell: nothing known";
}

TEST(RayBoundsGrid, CellRangesAndOptionLimits) {
    Cells cells(1);
    const RayBoundsGrid grid = makeGrid(cells);
    EXPECT_EQ(grid.cellRange(Tile{0, 0, 64, 32}), (std::array<int, 4>{0, 0, 4, 2}));
    EXPECT_EQ(grid.cellRange(Tile{17, 3, 1, 1}), (std::array<int, 4>{1, 0, 2, 1}));
    EXPECT_EQ(grid.cellRange(Tile{60, 20, 100, 100}), (std::array<int, 4>{3, 1, 4, 2}));
    EXPECT_THROW(RayBoundsGrid(RayBoundsOptions{0, 1, 1}), std::exception);
    EXPECT_THROW(RayBoundsGrid(RayBoundsOptions{8, 9, 1}), std::exception);
    EXPECT_THROW(RayBoundsGrid(RayBoundsOptions{8, 4, 0}), std::exception);
    EXPECT_THROW(RayBoundsGrid(RayBoundsOptions{12, 4, 2}), std::exception) << "not a power of two";
}

} // namespace
} // namespace chcrt
