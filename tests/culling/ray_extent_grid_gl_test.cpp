// RayExtentGrid's GPU reduction (shaders/culling/ray_cell_bounds.comp.glsl) against the cell boxes computed on the
// CPU from the same rays: random bounded, inactive, unbounded and NaN rays over a ray set whose size is not a
// multiple of the cell.
#include "culling/ray_extent_grid.h"
#include "renderer/gl/context.h"
#include "shaders/shared/culling_layout.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace chcrt {
namespace {

TEST(RayExtentGridGl, GpuCellBoxesEqualTheCpuReductionOfTheRays) {
    auto context = createHeadlessContext(GlBackend::Egl, true);
    constexpr int w = 45, h = 37, cell = CHCRT_CULLING_RAY_CELL; // 3 × 3 cells, partial at the edges
    std::vector<glm::vec4> origins(size_t(w) * h), directions(size_t(w) * h);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-50.0f, 50.0f), t(0.0f, 5.0f);
    for (size_t i = 0; i < origins.size(); ++i) {
        const float tmin = t(rng) * 0.01f;
        origins[i] = glm::vec4(u(rng), u(rng), u(rng), tmin);
        directions[i] = glm::vec4(glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.01f)), tmin + t(rng));
    }
    // Cell (1, 1): inactive rays only. Cell (2, 0): one unbounded ray. Cell (0, 2): one NaN origin.
    for (int y = cell; y < 2 * cell; ++y)
        for (int x = cell; x < 2 * cell; ++x) directions[size_t(y) * w + x].w = origins[size_t(y) * w + x].w;
    directions[size_t(3) * w + 2 * cell + 1].w = std::numeric_limits<float>::infinity();
    origins[size_t(2 * cell + 1) * w + 3].x = std::numeric_limits<float>::quiet_NaN();

    GlTexture originTexture = createTexture2D(w, h, GL_RGBA32F), directionTexture = createTexture2D(w, h, GL_RGBA32F);
    glTextureSubImage2D(originTexture.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, origins.data());
    glTextureSubImage2D(directionTexture.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, directions.data());
    RayExtentGrid grid;
    grid.update(originTexture.id(), directionTexture.id(), w, h);
    ASSERT_EQ(grid.cellsX(), 3);
    ASSERT_EQ(grid.cellsY(), 3);

    // Every ray's segment end points must be reachable from its cell; a box away from all of them must not be
    // (except where a cell is unbounded).
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const glm::vec4 o = origins[size_t(y) * w + x], d = directions[size_t(y) * w + x];
            if (!(d.w > o.w) || std::isnan(o.x) || std::isinf(d.w)) continue;
            const Tile pixel{x, y, 1, 1};
            for (float s : {o.w, d.w, 0.5f * (o.w + d.w)}) {
                const glm::vec3 p = glm::vec3(o) + glm::vec3(d) * s;
                ASSERT_TRUE(grid.mayReach(pixel, &p, &p, 1)) << x << ", " << y << " at t = " << s;
            }
        }
    }
    const glm::vec3 far(1000.0f), farUpper(1001.0f);
    EXPECT_FALSE(grid.mayReach(Tile{0, 0, cell, cell}, &far, &farUpper, 1));          // bounded
    EXPECT_FALSE(grid.mayReach(Tile{cell, cell, cell, cell}, &far, &farUpper, 1));    // inactive only
    EXPECT_TRUE(grid.mayReach(Tile{2 * cell, 0, cell, cell}, &far, &farUpper, 1));    // unbounded ray
    EXPECT_TRUE(grid.mayReach(Tile{0, 2 * cell, cell, cell}, &far, &farUpper, 1));    // NaN origin
    EXPECT_FALSE(grid.mayReach(Tile{2 * cell, 2 * cell, w, h}, &far, &farUpper, 1)); // partial edge cell
    // The reduction is tight up to the pad: a box just outside the cell's rays' extent along x is not reached.
    float maxX = -1e30f;
    for (int y = 0; y < cell; ++y) {
        for (int x = 0; x < cell; ++x) {
            const glm::vec4 o = origins[size_t(y) * w + x], d = directions[size_t(y) * w + x];
            maxX = std::max({maxX, o.x + d.x * o.w, o.x + d.x * d.w});
        }
    }
    const glm::vec3 beyondLower(maxX + 1.0f, -1e3f, -1e3f), beyondUpper(maxX + 2.0f, 1e3f, 1e3f);
    EXPECT_FALSE(grid.mayReach(Tile{0, 0, cell, cell}, &beyondLower, &beyondUpper, 1));
    const glm::vec3 insideLower(maxX - 0.01f, -1e3f, -1e3f);
    EXPECT_TRUE(grid.mayReach(Tile{0, 0, cell, cell}, &insideLower, &beyondUpper, 1));
}

} // namespace
} // namespace chcrt
