// hemisphereRayBounds (culling/hemisphere_ray_bounds.h) against the rays it bounds: cells whose surface points face one
// way, two ways (a wall meeting the ground) or every way, samples all over the hemisphere, rotation ranges from none to
// beyond a turn. The rays are made as the renderer's ray generation makes them (float arithmetic of
// shaders/render/raygen.frag.glsl and render/sampling.glsl) and the frames reduced as
// shaders/culling/surface_frames.comp.glsl reduces them: every direction must lie in the cell's direction box and every
// end point p_j = o + d·s_j in the box of point j, before the grid's padding. A negative control bounds rays rotated by
// 36° as if they were not rotated, and must find rays outside.
#include "culling/hemisphere_ray_bounds.h"
#include "shaders/shared/culling_layout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace chcrt {
namespace {

constexpr float kPi = 3.14159265358979f;

// render/sampling.glsl in float.
void buildTangentFrame(glm::vec3 n, glm::vec3& tangent, glm::vec3& bitangent) {
    const glm::vec3 reference = std::fabs(n.y) < 0.999f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
    tangent = glm::normalize(glm::cross(reference, n));
    bitangent = glm::cross(n, tangent);
}

glm::vec3 cosineHemisphere(glm::vec2 u, float rotation) {
    const float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y + rotation;
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u.x))};
}

struct SurfacePoint {
    glm::vec3 origin, normal;
};

int normalClass(glm::vec3 n) {
    const glm::vec3 a = glm::abs(n);
    const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    return 2 * axis + (n[axis] < 0.0f ? 1 : 0);
}

// One cell's frames as the shader reduces them.
std::vector<glm::vec4> reduceFrames(const std::vector<SurfacePoint>& points) {
    std::vector<glm::vec4> frames(CHCRT_CULLING_FRAMES_STRIDE, glm::vec4(0.0f));
    const float big = 3.0e38f;
    std::vector<glm::vec3> lower(CHCRT_CULLING_FRAME_BOXES * CHCRT_CULLING_FRAME_CLASSES, glm::vec3(big));
    std::vector<glm::vec3> upper(lower.size(), glm::vec3(-big));
    float shortest = big, longest = 0.0f;
    for (const SurfacePoint& p : points) {
        glm::vec3 t, b;
        buildTangentFrame(p.normal, t, b);
        const int base = CHCRT_CULLING_FRAME_BOXES * normalClass(p.normal);
        const glm::vec3 values[4] = {p.origin, p.normal, t, b};
        for (int k = 0; k < 4; ++k) {
            lower[size_t(base + k)] = glm::min(lower[size_t(base + k)], values[k]);
            upper[size_t(base + k)] = glm::max(upper[size_t(base + k)], values[k]);
        }
        shortest = std::min(shortest, glm::length(p.normal));
        longest = std::max(longest, glm::length(p.normal));
    }
    const float state = points.empty() ? CHCRT_CULLING_CELL_EMPTY : CHCRT_CULLING_CELL_BOUNDED;
    frames[0] = glm::vec4(state, shortest, longest, 0.0f);
    for (size_t j = 0; j < lower.size(); ++j) {
        const bool used = j % CHCRT_CULLING_FRAME_BOXES == 0 && lower[j].x <= upper[j].x;
        frames[1 + 2 * j] = glm::vec4(lower[j], used ? 1.0f : 0.0f);
        frames[2 + 2 * j] = glm::vec4(upper[j], 0.0f);
    }
    return frames;
}

glm::vec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> g;
    return glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
}

// The rays of `points` for `set` with per-pixel rotations drawn from [0, rotation] against the bounds made for
// `boundedRotation`: how many directions or end points fall outside them.
size_t raysOutside(const std::vector<SurfacePoint>& points, HemisphereSample set, float rotation, int pieces,
                   std::mt19937& rng, size_t& checked) {
    const std::vector<glm::vec4> frames = reduceFrames(points);
    const glm::vec3 sceneMin(-1e6f), sceneMax(1e6f);
    const std::vector<glm::vec4> bounds = hemisphereRayBounds(frames, 1, 1, pieces, set, sceneMin, sceneMax);
    EXPECT_EQ(bounds[0].x, float(CHCRT_CULLING_CELL_BOUNDED));
    const int interval = 1 + 2 * (pieces + 2);
    const glm::vec3 dLo(bounds[size_t(interval)]), dHi(bounds[size_t(interval) + 1]);
    EXPECT_EQ(bounds[size_t(interval)].w, 0.0f);
    EXPECT_EQ(bounds[size_t(interval) + 1].w, set.length);
    std::uniform_real_distribution<float> fraction(0.0f, 1.0f);
    size_t outside = 0;
    for (const SurfacePoint& p : points) {
        for (int k = 0; k < 8; ++k) {
            const float turn = k == 0 ? 0.0f : (k == 1 ? rotation : fraction(rng) * rotation);
            glm::vec3 t, b;
            buildTangentFrame(p.normal, t, b);
            const glm::vec3 local = cosineHemisphere(set.sample, turn);
            const glm::vec3 d = glm::normalize(local.x * t + local.y * b + local.z * p.normal);
            bool inside = glm::all(glm::greaterThanEqual(d, dLo)) && glm::all(glm::lessThanEqual(d, dHi));
            inside = inside && glm::all(glm::greaterThanEqual(p.origin, glm::vec3(bounds[1]))) &&
                     glm::all(glm::lessThanEqual(p.origin, glm::vec3(bounds[2])));
            for (int j = 0; j <= pieces; ++j) {
                const glm::vec3 q = p.origin + d * (set.length * float(j) / float(pieces));
                // The bounds' float conversion rounds by an ulp of the coordinates at most.
                const float ulp = 4.0f * std::numeric_limits<float>::epsilon() * std::max(1.0f, glm::length(q));
                inside = inside && glm::all(glm::greaterThanEqual(q, glm::vec3(bounds[size_t(3 + 2 * j)]) - ulp)) &&
                         glm::all(glm::lessThanEqual(q, glm::vec3(bounds[size_t(4 + 2 * j)]) + ulp));
            }
            outside += !inside;
            ++checked;
        }
    }
    return outside;
}

TEST(HemisphereRayBounds, EveryRayOfACellLiesInItsBounds) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), coordinate(-30.0f, 30.0f);
    size_t checked = 0;
    for (int trial = 0; trial < 300; ++trial) {
        // Surface points facing one way, a wall meeting the ground, or every way (a plant), around a random spot.
        const int kind = trial % 3;
        const glm::vec3 spot(coordinate(rng), coordinate(rng), coordinate(rng));
        const glm::vec3 wall = randomUnit(rng), ground(0.0f, 1.0f, 0.0f);
        std::vector<SurfacePoint> points;
        for (int i = 0; i < 64; ++i) {
            const glm::vec3 n = kind == 0 ? wall : (kind == 1 ? (i % 2 ? wall : ground) : randomUnit(rng));
            points.push_back({spot + glm::vec3(unit(rng), unit(rng), unit(rng)) * 2.0f, n});
        }
        const float rotations[4] = {0.0f, 0.6283185f, 2.0f * kPi, 9.0f};
        const float rotation = rotations[trial % 4];
        const HemisphereSample set{glm::vec2(unit(rng), unit(rng)), rotation, 0.5f + 10.0f * unit(rng)};
        EXPECT_EQ(raysOutside(points, set, rotation, 1 + trial % 8, rng, checked), 0u) << "trial " << trial;
    }
    EXPECT_GT(checked, 100000u);
}

TEST(HemisphereRayBounds, RaysRotatedBeyondTheBoundedRangeAreFound) {
    // Negative control: rays rotated per pixel by up to 36° bounded as if no pixel rotated its sample.
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    size_t checked = 0, outside = 0;
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<SurfacePoint> points;
        const glm::vec3 wall = randomUnit(rng);
        for (int i = 0; i < 32; ++i) points.push_back({glm::vec3(unit(rng), unit(rng), unit(rng)), wall});
        const HemisphereSample set{glm::vec2(0.2f + 0.6f * unit(rng), unit(rng)), 0.0f, 4.0f};
        outside += raysOutside(points, set, 0.6283185f, 4, rng, checked);
    }
    EXPECT_GT(outside, checked / 10);
}

TEST(HemisphereRayBounds, CellsWithoutUsableFramesCullNothingOrEverything) {
    const HemisphereSample set{glm::vec2(0.3f, 0.7f), 0.6f, 2.0f};
    const glm::vec3 sceneMin(-10.0f), sceneMax(10.0f);
    const int stride = CHCRT_CULLING_BOUNDS_STRIDE(4);
    std::vector<SurfacePoint> points = {{glm::vec3(1.0f), glm::vec3(0.0f, 0.0f, 1.0f)}};
    // No surface point: empty.
    EXPECT_EQ(hemisphereRayBounds(reduceFrames({}), 1, 1, 4, set, sceneMin, sceneMax)[0].x, CHCRT_CULLING_CELL_EMPTY);
    // A NaN in the cell (the shader's state), frames missing from the buffer, normals not of unit length, a NaN or
    // infinite length: unbounded.
    std::vector<glm::vec4> frames = reduceFrames(points);
    frames[0].x = CHCRT_CULLING_CELL_UNBOUNDED;
    EXPECT_EQ(hemisphereRayBounds(frames, 1, 1, 4, set, sceneMin, sceneMax)[0].x, CHCRT_CULLING_CELL_UNBOUNDED);
    const std::vector<glm::vec4> two = hemisphereRayBounds(reduceFrames(points), 2, 1, 4, set, sceneMin, sceneMax);
    EXPECT_EQ(two[0].x, CHCRT_CULLING_CELL_BOUNDED);
    EXPECT_EQ(two[size_t(stride)].x, CHCRT_CULLING_CELL_UNBOUNDED);
    points[0].normal = glm::vec3(0.0f, 0.0f, 0.9f);
    EXPECT_EQ(hemisphereRayBounds(reduceFrames(points), 1, 1, 4, set, sceneMin, sceneMax)[0].x,
              CHCRT_CULLING_CELL_UNBOUNDED);
    points[0].normal = glm::vec3(0.0f, 0.0f, 1.0f);
    for (float length : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        const HemisphereSample bad{set.sample, set.maxRotation, length};
        EXPECT_EQ(hemisphereRayBounds(reduceFrames(points), 1, 1, 4, bad, sceneMin, sceneMax)[0].x,
                  CHCRT_CULLING_CELL_UNBOUNDED);
    }
    // End points are clipped to the scene's box.
    const HemisphereSample longRays{set.sample, set.maxRotation, 100.0f};
    const std::vector<glm::vec4> clipped =
        hemisphereRayBounds(reduceFrames(points), 1, 1, 4, longRays, sceneMin, sceneMax);
    EXPECT_EQ(clipped[0].x, CHCRT_CULLING_CELL_BOUNDED);
    EXPECT_LE(clipped[4 + 2 * 4].z, sceneMax.z);
}

} // namespace
} // namespace chcrt
