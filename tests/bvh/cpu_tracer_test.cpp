// The CPU tracer against a brute-force loop over all triangles (same intersection arithmetic, same
// tie-break), on random, structured and hand-made edge cases. Results must be identical, not close: both
// run intersectRayTriangle on the same floats.
#include "renderer/bvh/cpu_tracer.h"
#include "tests/bvh/bvh_test_scenes.h"

#include "shaders/shared/intersect.h"

#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <vector>

namespace chcrt {
namespace {

testing::AssertionResult sameHit(const Hit& expected, const Hit& actual) {
    if (expected.triangleId == actual.triangleId && expected.t == actual.t && expected.u == actual.u &&
        expected.v == actual.v) {
        return testing::AssertionSuccess();
    }
    return testing::AssertionFailure() << "expected id " << expected.triangleId << " t " << expected.t << ", got id "
                                       << actual.triangleId << " t " << actual.t;
}

std::string describe(const Ray& ray) {
    std::ostringstream text;
    text.precision(9);
    text << "ray o=(" << ray.origin.x << "," << ray.origin.y << "," << ray.origin.z << ") d=(" << ray.direction.x << ","
         << ray.direction.y << "," << ray.direction.z << ") [" << ray.tmin << "," << ray.tmax << "]";
    return text.str();
}

// Closest hit equals brute force; any-hit agrees on hit/miss and returns a genuine hit inside the window.
void expectMatchesBruteForce(const Bvh& bvh, const Scene& scene, const std::vector<Ray>& rays) {
    int hits = 0;
    for (const Ray& ray : rays) {
        const Hit expected = test::traceBruteForce(scene, ray);
        ASSERT_TRUE(sameHit(expected, traceClosestCpu(bvh, ray))) << describe(ray);
        const Hit any = traceAnyCpu(bvh, ray);
        ASSERT_EQ(any.hit(), expected.hit()) << describe(ray);
        if (any.hit()) {
            ++hits;
            const glm::uvec3 t = scene.triangles[any.triangleId];
            const glm::vec3 tuv = gpu::intersectRayTriangle(ray.origin, ray.direction, scene.positions[t.x],
                                                            scene.positions[t.y], scene.positions[t.z]);
            EXPECT_EQ(tuv.x, any.t);
            EXPECT_GE(any.t, ray.tmin);
            EXPECT_LE(any.t, ray.tmax);
            EXPECT_GE(any.t, expected.t);
        }
    }
    // The rays must exercise both outcomes, or the comparison proves little.
    EXPECT_GT(hits, int(rays.size()) / 10);
    EXPECT_LT(hits, int(rays.size()));
}

std::vector<Ray> randomRays(const Scene& scene, uint32_t count, uint32_t seed, float margin = 0.3f) {
    std::mt19937 rng(seed);
    std::vector<Ray> rays;
    const Aabb bounds = scene.bounds();
    for (uint32_t i = 0; i < count; ++i) {
        rays.push_back(test::makeRandomRay(rng, bounds, margin));
    }
    return rays;
}

TEST(CpuTracer, RandomRaysMatchBruteForceOnSoup) {
    // Dense enough that rays often pass several triangles, sparse enough that some miss.
    const Scene scene = test::makeTriangleSoup(3000, 21, 10.0f, 1.5f);
    const std::vector<Ray> rays = randomRays(scene, 3000, 22);
    for (uint32_t maxLeaf : {1u, 4u, 8u}) {
        for (bool median : {false, true}) {
            BvhBuildOptions options;
            options.maxLeafTriangles = maxLeaf;
            options.medianSplit = median;
            SCOPED_TRACE(testing::Message() << "leaf " << maxLeaf << " median " << median);
            expectMatchesBruteForce(buildBvh(scene, options), scene, rays);
        }
    }
}

TEST(CpuTracer, RandomRaysMatchBruteForceOnHeightfieldAndClusters) {
    const Scene field = test::makeHeightfield(40, 23);
    expectMatchesBruteForce(buildBvh(field), field, randomRays(field, 3000, 24));
    const Scene clusters = test::makeClusteredSoup(3000, 6, 25);
    // Aim at the clusters: rays at random points of the huge box would almost all miss.
    std::mt19937 rng(26);
    std::vector<Ray> rays;
    const Aabb bounds = clusters.bounds();
    for (int i = 0; i < 2000; ++i) {
        const glm::uvec3 t = clusters.triangles[rng() % clusters.triangles.size()];
        Aabb target;
        target.grow(clusters.positions[t.x]);
        target.grow(clusters.positions[t.y]);
        target.grow(clusters.positions[t.z]);
        Ray ray = test::makeRandomRay(rng, bounds, 0.1f);
        ray.direction = glm::normalize(target.center() + glm::vec3(float(rng() % 3) - 1.0f) - ray.origin);
        rays.push_back(ray);
    }
    expectMatchesBruteForce(buildBvh(clusters), clusters, rays);
}

TEST(CpuTracer, RayWindowsMatchBruteForce) {
    const Scene scene = test::makeTriangleSoup(2000, 27, 10.0f, 1.5f);
    const Bvh bvh = buildBvh(scene);
    std::vector<Ray> rays = randomRays(scene, 3000, 28);
    std::mt19937 rng(29);
    std::uniform_real_distribution<float> along(0.0f, 30.0f);
    for (Ray& ray : rays) {
        const float a = along(rng);
        const float b = along(rng);
        ray.tmin = std::min(a, b);
        ray.tmax = std::max(a, b) + 0.01f;
    }
    expectMatchesBruteForce(bvh, scene, rays);
    // A window that ends exactly at a hit includes it; one that starts exactly there does too.
    for (int i = 0; i < 200; ++i) {
        Ray ray = rays[size_t(i)];
        ray.tmin = 0.0f;
        ray.tmax = 1e30f;
        const Hit full = test::traceBruteForce(scene, ray);
        if (!full.hit()) {
            continue;
        }
        ray.tmax = full.t;
        EXPECT_TRUE(sameHit(full, traceClosestCpu(bvh, ray))) << describe(ray);
        ray.tmin = full.t; // [t, t] is an inactive ray by definition (tmax <= tmin)
        EXPECT_FALSE(traceClosestCpu(bvh, ray).hit()) << describe(ray);
        ray.tmax = 1e30f;
        EXPECT_TRUE(sameHit(full, traceClosestCpu(bvh, ray))) << describe(ray);
        ray.tmax = std::nextafter(full.t, 0.0f);
        ray.tmin = 0.0f;
        EXPECT_TRUE(sameHit(test::traceBruteForce(scene, ray), traceClosestCpu(bvh, ray))) << describe(ray);
        EXPECT_NE(traceClosestCpu(bvh, ray).triangleId, full.triangleId);
    }
}

TEST(CpuTracer, InactiveRaysMissWithoutTraversal) {
    Scene scene = test::makeTriangleSoup(0, 0);
    test::addTriangle(scene, glm::vec3(-1, -1, 0), glm::vec3(1, -1, 0), glm::vec3(0, 1, 0));
    const Bvh bvh = buildBvh(scene);
    Ray ray;
    ray.origin = glm::vec3(0, 0, 5);
    ray.direction = glm::vec3(0, 0, -1);
    ray.tmax = 100.0f;
    ASSERT_TRUE(traceClosestCpu(bvh, ray).hit());
    for (const auto& [tmin, tmax] : {std::pair{0.0f, 0.0f}, {3.0f, 3.0f}, {10.0f, 2.0f}, {0.0f, -1.0f}}) {
        ray.tmin = tmin;
        ray.tmax = tmax;
        const Hit closest = traceClosestCpu(bvh, ray);
        EXPECT_FALSE(closest.hit()) << tmin << " " << tmax;
        EXPECT_EQ(closest.t, float(CHCRT_NO_HIT_T));
        EXPECT_FALSE(traceAnyCpu(bvh, ray).hit());
    }
}

// Directions along ±x, ±y, ±z have zero components (safeInverseDirection makes them ±1e30). Origins are random
// floats, so they do not lie on a box face (RayInBoxFacePlaneWithZeroDirectionComponent covers that case).
TEST(CpuTracer, AxisParallelRaysMatchBruteForce) {
    const Scene scene = test::makeTriangleSoup(3000, 30, 10.0f, 2.0f);
    const Aabb box = scene.bounds();
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < 3000; ++i) {
        Ray ray;
        ray.origin = box.lower + box.extent() * glm::vec3(unit(rng), unit(rng), unit(rng));
        ray.direction = glm::vec3(0.0f);
        ray.direction[i % 3] = (i / 3) % 2 == 0 ? 1.0f : -1.0f;
        ray.tmax = 1e30f;
        rays.push_back(ray);
    }
    expectMatchesBruteForce(buildBvh(scene), scene, rays);
}

// Origins inside the root box and inside leaf boxes: entry distances are negative.
TEST(CpuTracer, RaysStartingInsideBoxesMatchBruteForce) {
    const Scene scene = test::makeTriangleSoup(2000, 32, 10.0f, 1.5f);
    const Bvh bvh = buildBvh(scene);
    std::mt19937 rng(33);
    std::vector<Ray> rays;
    const Aabb bounds = scene.bounds();
    for (int i = 0; i < 3000; ++i) {
        Ray ray = test::makeRandomRay(rng, bounds, 0.0f);
        if (i % 2 == 0) {
            // From the centre of a random leaf's box in a random direction.
            uint32_t node = rng() % uint32_t(bvh.nodes.size());
            while (!bvh.isLeaf(node)) {
                node = bvh.nodes[node].leftFirst + rng() % 2;
            }
            ray.origin = 0.5f * (bvh.nodes[node].boundsMin + bvh.nodes[node].boundsMax);
            ray.direction = glm::normalize(test::makeRandomRay(rng, bounds, 0.0f).direction);
        }
        rays.push_back(ray);
    }
    expectMatchesBruteForce(bvh, scene, rays);
}

// Two triangles sharing the edge from (1,0,0) to (0,1,0); the rays pass exactly through the edge (all values
// are dyadic, so both triangles report exactly the same t). The lower original id must win, whichever leaf
// the traversal reaches first, including when the triangles sit in different leaves whose boxes are entered
// at the same t (so the second leaf must not be pruned by the first leaf's equal hit).
TEST(CpuTracer, SharedEdgeTieGoesToLowerId) {
    const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(2, 2, 0); // different boxes, so maxLeaf 1 splits them
    for (bool swapIds : {false, true}) {
        Scene scene = test::makeTriangleSoup(0, 0);
        if (swapIds) {
            test::addTriangle(scene, b, d, c);
            test::addTriangle(scene, a, b, c);
        } else {
            test::addTriangle(scene, a, b, c);
            test::addTriangle(scene, b, d, c);
        }
        // One leaf (default SAH), and two leaves via the median build or via expensive intersections.
        BvhBuildOptions medianOptions;
        medianOptions.maxLeafTriangles = 1;
        medianOptions.medianSplit = true;
        BvhBuildOptions expensiveOptions;
        expensiveOptions.maxLeafTriangles = 1;
        expensiveOptions.intersectionCost = 10.0f;
        for (const BvhBuildOptions& options : {BvhBuildOptions{}, medianOptions, expensiveOptions}) {
            const Bvh bvh = buildBvh(scene, options);
            ASSERT_EQ(bvh.nodes.size(), options.maxLeafTriangles == 1 ? 3u : 1u);
            const uint32_t maxLeaf = options.maxLeafTriangles;
            for (const glm::vec3& direction : {glm::vec3(0, 0, -1), glm::vec3(0.5f, 0.5f, -1.0f), glm::vec3(-0.25f, 0.25f, -1.0f)}) {
                Ray ray;
                ray.origin = glm::vec3(0.5f, 0.5f, 0.0f) - direction; // reaches the edge point at t = 1
                ray.direction = direction;
                ray.tmax = 10.0f;
                // Both triangles are hit at the same t (otherwise the test would not test the tie-break).
                for (uint32_t id = 0; id < 2; ++id) {
                    const glm::uvec3 t = scene.triangles[id];
                    ASSERT_EQ(gpu::intersectRayTriangle(ray.origin, ray.direction, scene.positions[t.x],
                                                        scene.positions[t.y], scene.positions[t.z]).x, 1.0f);
                }
                const Hit hit = traceClosestCpu(bvh, ray);
                EXPECT_EQ(hit.triangleId, 0u) << "swap " << swapIds << " leaf " << maxLeaf;
                EXPECT_EQ(hit.t, 1.0f);
            }
        }
    }
}

// Exact duplicates with different ids: every ray hitting them must report the lowest id.
TEST(CpuTracer, DuplicateTrianglesResolveToLowestId) {
    Scene scene = test::makeTriangleSoup(500, 34, 10.0f, 2.0f);
    const size_t original = scene.triangles.size();
    for (size_t i = 0; i < original; i += 5) { // re-add every fifth triangle twice, at higher ids
        const glm::uvec3 t = scene.triangles[i];
        const glm::vec3 p0 = scene.positions[t.x], p1 = scene.positions[t.y], p2 = scene.positions[t.z];
        test::addTriangle(scene, p0, p1, p2);
        test::addTriangle(scene, p0, p1, p2);
    }
    BvhBuildOptions options;
    options.maxLeafTriangles = 1;
    const Bvh bvh = buildBvh(scene, options);
    const std::vector<Ray> rays = randomRays(scene, 2000, 35);
    expectMatchesBruteForce(bvh, scene, rays);
    for (const Ray& ray : rays) {
        EXPECT_LT(traceClosestCpu(bvh, ray).triangleId + 1, original + 1); // never a duplicate's id
    }
}

TEST(CpuTracer, BatchedTracingMatchesSingleRays) {
    const Scene scene = test::makeHeightfield(60, 36);
    const Bvh bvh = buildBvh(scene);
    std::vector<Ray> rays = randomRays(scene, 5000, 37);
    rays[7].tmax = rays[7].tmin; // an inactive ray in the batch
    std::vector<Hit> hits(rays.size());
    for (bool anyHit : {false, true}) {
        traceCpu(bvh, rays, hits, anyHit);
        for (size_t i = 0; i < rays.size(); ++i) {
            const Hit single = anyHit ? traceAnyCpu(bvh, rays[i]) : traceClosestCpu(bvh, rays[i]);
            ASSERT_TRUE(sameHit(single, hits[i])) << i;
        }
        EXPECT_FALSE(hits[7].hit());
    }
}

} // namespace
} // namespace chcrt

namespace chcrt {
namespace {

// A zero direction component with the origin exactly on that axis's box face: an infinite inverse would make
// (bound - origin) * invDir = 0 * inf = NaN and reject the box; safeInverseDirection (intersect.h) prevents it.
TEST(CpuTracer, RayInBoxFacePlaneWithZeroDirectionComponent) {
    Scene scene = test::makeTriangleSoup(0, 0);
    test::addTriangle(scene, glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
    const Bvh bvh = buildBvh(scene);
    Ray ray;
    ray.origin = glm::vec3(0.0f, 0.5f, 1.0f); // x on the box's min-x face
    ray.direction = glm::vec3(0, 0, -1);
    ray.tmax = 10.0f;
    ASSERT_TRUE(test::traceBruteForce(scene, ray).hit());
    EXPECT_TRUE(traceClosestCpu(bvh, ray).hit());
}

} // namespace
} // namespace chcrt
