#include "renderer/render/hit_comparison.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chcrt {
namespace {

// Two triangles sharing the edge x = 0 in the plane z = 0, plus a third at z = -1 behind them.
Scene twoTriangles() {
    Scene s;
    s.positions = {{-1, -1, 0}, {0, -1, 0}, {0, 1, 0}, {1, -1, 0}, {-5, -5, -1}, {5, -5, -1}, {0, 5, -1}};
    s.normals.assign(s.positions.size(), glm::vec3(0, 0, 1));
    s.triangles = {{0, 1, 2}, {1, 3, 2}, {4, 5, 6}};
    s.triangleMaterials = {0, 0, 0};
    s.materials.resize(1);
    return s;
}

Ray rayDown(float x, float y) {
    Ray r;
    r.origin = {x, y, 5};
    r.direction = {0, 0, -1};
    r.tmin = 0;
    r.tmax = 100;
    return r;
}

Hit hit(float t, uint32_t id) {
    Hit h;
    h.t = t;
    h.triangleId = id;
    return h;
}

TEST(HitComparison, ClassifiesMatchesTiesBorderCasesAndDifferences) {
    const Scene scene = twoTriangles();
    const std::vector<Ray> rays = {rayDown(-0.5f, -0.5f), rayDown(0.0f, 0.0f), rayDown(-0.5f, -0.5f),
                                   rayDown(-0.5f, -0.5f), rayDown(0.0f, 1.0f)};
    const std::vector<Hit> a = {hit(5, 0), hit(5, 0), hit(5, 0), hit(5, 0), hit(5, 0)};
    const std::vector<Hit> b = {hit(5.00001f, 0),  // same triangle, t within tolerance: match
                                hit(5, 1),         // shared edge, same t: tie
                                hit(6, 2),         // the nearer triangle missed deep inside it: difference
                                Hit{},             // missed deep inside: difference
                                hit(6, 2)};        // the apex (0,1) of triangle 0 is on its border: border case
    std::vector<size_t> differingPixels;
    const HitComparison c = compareHits(scene, rays, a, b, false, HitTolerance{}, &differingPixels);
    EXPECT_EQ(differingPixels, (std::vector<size_t>{2, 3})); // what `verify --show-diff` prints
    EXPECT_EQ(c.activeRays, 5u);
    EXPECT_EQ(c.ties, 1u);
    EXPECT_EQ(c.differing, 2u);
    EXPECT_EQ(c.edgeCases, 1u);
    // Any-hit comparisons look at hit/miss only.
    const HitComparison any = compareHits(scene, rays, a, b, true, HitTolerance{});
    EXPECT_EQ(any.differing, 1u);
}

TEST(HitComparison, InactiveRaysMustMiss) {
    const Scene scene = twoTriangles();
    Ray inactive = rayDown(0.5f, 0.5f);
    inactive.tmax = inactive.tmin;
    const std::vector<Ray> rays = {inactive, inactive};
    const std::vector<Hit> a = {Hit{}, hit(5, 1)};
    const std::vector<Hit> b = {Hit{}, Hit{}};
    const HitComparison c = compareHits(scene, rays, a, b, false, HitTolerance{});
    EXPECT_EQ(c.activeRays, 0u);
    EXPECT_EQ(c.differing, 1u);
}

TEST(HitComparison, ExactComparisonWantsSameIdAndSameBitsOfT) {
    const std::vector<Ray> rays(4, rayDown(0.5f, 0.5f));
    const std::vector<Hit> a = {hit(5, 1), hit(5, 1), hit(5, 1), Hit{}};
    const std::vector<Hit> b = {hit(5, 1), hit(std::nextafter(5.0f, 6.0f), 1), hit(5, 0), hit(5, 1)};
    const HitComparison closest = compareHitsExactly(rays, a, b, false);
    EXPECT_EQ(closest.differing, 3u); // one ulp of t, another id, hit vs miss
    // Any-hit: only hit/miss counts.
    EXPECT_EQ(compareHitsExactly(rays, a, b, true).differing, 1u);
}

} // namespace
} // namespace chcrt
