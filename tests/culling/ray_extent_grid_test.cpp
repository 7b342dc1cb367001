// RayExtentGrid (culling/ray_extent_grid.h): the CPU side's decisions from given cell boxes (unit), and the GPU
// reduction against the same boxes computed on the CPU from the rays (GL).
#include "culling/ray_extent_grid.h"
#include "shaders/shared/culling_layout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace chcrt {
namespace {

constexpr float kEmpty = float(CHCRT_CULLING_CELL_EMPTY);
constexpr float kBounded = float(CHCRT_CULLING_CELL_BOUNDED);
constexpr float kUnbounded = float(CHCRT_CULLING_CELL_UNBOUNDED);

// A 64×32 ray set: 4×2 cells of 16² pixels, all empty but the ones set.
struct Cells {
    std::vector<glm::vec4> lower = std::vector<glm::vec4>(8, glm::vec4(0.0f, 0.0f, 0.0f, kEmpty));
    std::vector<glm::vec4> upper = std::vector<glm::vec4>(8, glm::vec4(0.0f));
    void set(int cx, int cy, glm::vec3 lo, glm::vec3 hi, float state = kBounded) {
        lower[size_t(cy * 4 + cx)] = glm::vec4(lo, state);
        upper[size_t(cy * 4 + cx)] = glm::vec4(hi, 0.0f);
    }
};

bool reach(const RayExtentGrid& grid, Tile tile, glm::vec3 lo, glm::vec3 hi) {
    return grid.mayReach(tile, &lo, &hi, 1);
}

TEST(RayExtentGrid, TilesReachOnlyWhatTheirCellsBoxesOverlap) {
    Cells cells;
    cells.set(1, 0, glm::vec3(0.0f), glm::vec3(1.0f));           // pixels x 16..31, y 0..15
    cells.set(3, 1, glm::vec3(10.0f, 0.0f, 0.0f), glm::vec3(11.0f, 1.0f, 1.0f));
    RayExtentGrid grid;
    grid.setCells(64, 32, cells.lower, cells.upper);
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
}

TEST(RayExtentGrid, BoxesAreTouchedWithinTheRoundingPadAndUnboundedCellsReachEverything) {
    Cells cells;
    cells.set(0, 0, glm::vec3(1000.0f), glm::vec3(1001.0f));
    cells.set(1, 0, glm::vec3(0.0f), glm::vec3(0.0f), kUnbounded);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    cells.set(2, 0, glm::vec3(nan), glm::vec3(1.0f)); // a NaN box assumes nothing
    RayExtentGrid grid;
    grid.setCells(64, 32, cells.lower, cells.upper);
    // 2^-12 relative pad: 1001 + 0.2 still touches, 1001 + 0.5 does not.
    EXPECT_TRUE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(1001.2f, 1000.5f, 1000.5f), glm::vec3(1002.0f)));
    EXPECT_FALSE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(1001.5f, 1000.5f, 1000.5f), glm::vec3(1002.0f)));
    EXPECT_TRUE(reach(grid, Tile{16, 0, 16, 16}, glm::vec3(-1e6f), glm::vec3(-1e6f + 1.0f)));
    EXPECT_TRUE(reach(grid, Tile{32, 0, 16, 16}, glm::vec3(-1e6f), glm::vec3(-1e6f + 1.0f)));
}

TEST(RayExtentGrid, WithoutCellsEverythingIsReachable) {
    RayExtentGrid grid;
    EXPECT_TRUE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(0.0f), glm::vec3(1.0f)));
    // forget() (the tracer's primary rays) drops cells that excluded a box: reachable again.
    Cells cells;
    cells.set(0, 0, glm::vec3(0.0f), glm::vec3(1.0f));
    grid.setCells(64, 32, cells.lower, cells.upper);
    EXPECT_FALSE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(5.0f), glm::vec3(6.0f)));
    grid.forget();
    EXPECT_TRUE(reach(grid, Tile{0, 0, 16, 16}, glm::vec3(5.0f), glm::vec3(6.0f)));
}

} // namespace
} // namespace chcrt
