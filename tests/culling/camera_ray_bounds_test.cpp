// cameraRayBounds (culling/camera_ray_bounds.h) against the rays it bounds: random cameras inside and outside random
// scene boxes, ray sets whose size is not a multiple of the cell, every cell size and piece count. The rays are made
// as the renderer's ray generation makes them (float arithmetic of shaders/render/raygen.frag.glsl) and reduced as the
// GPU reduction reduces them (shaders/culling/ray_bounds.comp.glsl, with intersect.h's slab test): every end point,
// direction and segment end must lie in the cell's bounds before the grid's padding is added, within 1/16 of that
// padding (the margin the padding keeps for the shader's own rounding).
#include "culling/camera_ray_bounds.h"
#include "culling/ray_bounds_grid.h"
#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/culling_layout.h"
#include "shaders/shared/intersect.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace chcrt {
namespace {

struct Config {
    Camera camera;
    int width = 0, height = 0, cellSize = 0, pieces = 0;
    glm::vec3 sceneMin{0.0f}, sceneMax{0.0f};
};

// The shader's ray of pixel (x, y), in float.
glm::vec3 shaderDirection(const PrimaryRayBasis& b, int x, int y) {
    const glm::vec2 ndc = (glm::vec2(float(x), float(y)) + 0.5f) / glm::vec2(float(b.width), float(b.height)) * 2.0f - 1.0f;
    return glm::normalize(b.forward + ndc.x * b.right + ndc.y * b.up);
}

struct Checked {
    size_t rays = 0, cellsEmpty = 0;
};

// Every ray of the configuration against its cell's bounds (counts into `checked`).
void expectRaysInsideTheirCells(const Config& c, Checked& checked) {
    const PrimaryRayBasis basis = primaryRayBasis(makeCameraFrame(c.camera, c.width, c.height), c.width, c.height);
    const std::vector<glm::vec4> raw = cameraRayBounds(basis, c.cellSize, c.pieces, c.sceneMin, c.sceneMax);
    const int cellsX = (c.width + c.cellSize - 1) / c.cellSize;
    const size_t stride = size_t(CHCRT_CULLING_BOUNDS_STRIDE(c.pieces));
    const int points = c.pieces + 2;
    EXPECT_EQ(raw.size(), size_t(cellsX) * size_t((c.height + c.cellSize - 1) / c.cellSize) * stride);
    for (int y = 0; y < c.height; ++y) {
        for (int x = 0; x < c.width; ++x) {
            const glm::vec4* cell = &raw[(size_t(y / c.cellSize) * size_t(cellsX) + size_t(x / c.cellSize)) * stride];
            const glm::vec3 o = basis.eye, d = shaderDirection(basis, x, y);
            const glm::vec2 entryExit = gpu::intersectRayAabb(o, gpu::safeInverseDirection(d), c.sceneMin, c.sceneMax);
            const float t0 = std::max(0.0f, entryExit.x), t1 = std::min(float(CHCRT_NO_HIT_T), entryExit.y);
            if (!(t0 <= t1)) continue; // misses the scene: the reduction leaves it out
            ++checked.rays;
            ASSERT_EQ(cell[0].x, float(CHCRT_CULLING_CELL_BOUNDED)) << "pixel " << x << ", " << y;
            const float extent = std::max({std::fabs(o.x), std::fabs(o.y), std::fabs(o.z)}) +
                                 std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)}) * std::max(t0, t1);
            ASSERT_GE(cell[0].y, extent * (1.0f - 1e-6f));
            ASSERT_GE(cell[0].z, glm::length(d));
            // The grid pads by relativePad of this magnitude; a sixteenth of it is the tolerance here.
            const float tolerance = std::max(1.0f, cell[0].y) * RayBoundsOptions{}.relativePad / 16.0f;
            for (int j = 0; j <= c.pieces; ++j) {
                const float s = j == 0 ? t0 : (j == c.pieces ? t1 : t0 + (t1 - t0) * (float(j) / float(c.pieces)));
                const glm::vec3 p = o + d * s;
                const glm::vec3 lo(cell[1 + 2 * (j + 1)]), hi(cell[2 + 2 * (j + 1)]);
                for (int i = 0; i < 3; ++i) {
                    ASSERT_GE(p[i], lo[i] - tolerance) << "pixel " << x << ", " << y << " point " << j << " axis " << i;
                    ASSERT_LE(p[i], hi[i] + tolerance) << "pixel " << x << ", " << y << " point " << j << " axis " << i;
                }
            }
            EXPECT_EQ(glm::vec3(cell[1]), o);
            EXPECT_EQ(glm::vec3(cell[2]), o);
            const glm::vec4 lower = cell[1 + 2 * points], upper = cell[2 + 2 * points];
            for (int i = 0; i < 3; ++i) {
                ASSERT_GE(d[i], lower[i]) << "pixel " << x << ", " << y << " axis " << i;
                ASSERT_LE(d[i], upper[i]) << "pixel " << x << ", " << y << " axis " << i;
            }
            ASSERT_LE(lower.w, t0);
            ASSERT_GE(upper.w, t1);
        }
    }
    for (size_t i = 0; i < raw.size(); i += stride) checked.cellsEmpty += raw[i].x == float(CHCRT_CULLING_CELL_EMPTY);
}

TEST(CameraRayBounds, HoldEveryRayOfRandomCamerasInsideAndOutsideTheScene) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const int cellSizes[] = {1, 2, 4, 8, 16, 32};
    size_t rays = 0, emptyCells = 0, outside = 0;
    for (int trial = 0; trial < 300; ++trial) {
        Config c;
        for (int i = 0; i < 3; ++i) {
            c.sceneMin[i] = -100.0f * unit(rng);
            c.sceneMax[i] = c.sceneMin[i] + 1.0f + 200.0f * unit(rng);
        }
        const glm::vec3 size = c.sceneMax - c.sceneMin;
        // A third of the cameras outside the box (some looking away from it), the rest inside.
        const float spread = trial % 3 == 0 ? 3.0f : 1.0f;
        for (int i = 0; i < 3; ++i) c.camera.eye[i] = c.sceneMin[i] + size[i] * (0.5f + spread * (unit(rng) - 0.5f));
        for (int i = 0; i < 3; ++i) c.camera.target[i] = c.sceneMin[i] + size[i] * unit(rng);
        if (trial % 7 == 0) c.camera.target = c.camera.eye + (c.camera.eye - c.camera.target); // away from the box
        if (glm::length(c.camera.target - c.camera.eye) < 1e-3f) c.camera.target.x += 1.0f;
        c.camera.up = trial % 11 == 0 ? glm::vec3(0.3f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
        c.camera.fovYDegrees = 20.0f + 130.0f * unit(rng);
        c.width = 1 + int(70.0f * unit(rng));
        c.height = 1 + int(50.0f * unit(rng));
        c.cellSize = cellSizes[trial % 6];
        c.pieces = 1 + trial % 8;
        outside += glm::any(glm::lessThan(c.camera.eye, c.sceneMin)) || glm::any(glm::greaterThan(c.camera.eye, c.sceneMax));
        SCOPED_TRACE("trial " + std::to_string(trial));
        Checked checked;
        expectRaysInsideTheirCells(c, checked);
        if (::testing::Test::HasFatalFailure()) return;
        rays += checked.rays;
        emptyCells += checked.cellsEmpty;
    }
    EXPECT_GT(rays, 100000u);
    EXPECT_GT(outside, 50u);
    EXPECT_GT(emptyCells, 0u) << "some cells look past the scene: nothing to reach there";
}

// Looking straight down onto the box from above, every ray enters through the top face: the entry points p_0 lie on
// that plane, and the bounds along the vertical axis (displacement, not distance) keep them on it, up to their
// rounding margin (1e-4 of the 470 m; the grid pads by 0.12 m there), where bounds from the intervals of direction
// and distance alone would make a slab as thick as the cell's spread of distances (metres here).
TEST(CameraRayBounds, ADownwardViewsEntryPointsLieOnTheTopPlane) {
    Config c;
    c.sceneMin = glm::vec3(-100.0f, 0.0f, -100.0f);
    c.sceneMax = glm::vec3(100.0f, 30.0f, 100.0f);
    c.camera.eye = glm::vec3(0.0f, 500.0f, 0.0f);
    c.camera.target = glm::vec3(0.0f, 0.0f, 1.0f);
    c.camera.up = glm::vec3(0.0f, 0.0f, 1.0f);
    c.camera.fovYDegrees = 20.0f;
    c.width = c.height = 64;
    c.cellSize = 16;
    c.pieces = 4;
    Checked checked;
    expectRaysInsideTheirCells(c, checked);
    EXPECT_EQ(checked.rays, 64u * 64u);
    const PrimaryRayBasis basis = primaryRayBasis(makeCameraFrame(c.camera, c.width, c.height), c.width, c.height);
    const std::vector<glm::vec4> raw = cameraRayBounds(basis, c.cellSize, c.pieces, c.sceneMin, c.sceneMax);
    const size_t stride = size_t(CHCRT_CULLING_BOUNDS_STRIDE(c.pieces));
    for (size_t cell = 0; cell < raw.size() / stride; ++cell) {
        const glm::vec4* b = &raw[cell * stride];
        EXPECT_NEAR(b[3].y, 30.0f, 0.06f) << "cell " << cell; // p_0: the entry, lower bound
        EXPECT_NEAR(b[4].y, 30.0f, 0.06f) << "cell " << cell; // upper bound
        EXPECT_NEAR(b[3 + 2 * c.pieces].y, 0.0f, 0.06f) << "cell " << cell; // p_P: the exit through the bottom
    }
}

TEST(CameraRayBounds, ANonFiniteCameraCullsNothing) {
    PrimaryRayBasis basis = primaryRayBasis(makeCameraFrame(Camera{}, 8, 8), 8, 8);
    basis.eye.x = std::numeric_limits<float>::quiet_NaN();
    const std::vector<glm::vec4> raw = cameraRayBounds(basis, 4, 2, glm::vec3(-1.0f), glm::vec3(1.0f));
    const size_t stride = size_t(CHCRT_CULLING_BOUNDS_STRIDE(2));
    ASSERT_EQ(raw.size(), 4 * stride);
    for (size_t i = 0; i < raw.size(); i += stride) EXPECT_EQ(raw[i].x, float(CHCRT_CULLING_CELL_UNBOUNDED));
}

} // namespace
} // namespace chcrt
