// Representative candidates: every candidate equals the brute-force first hit of its shaft's centroid ray,
// shafts whose centroid ray hits nothing are empty, and approximateHit extrapolates the plane and rejects by
// the normal angle as §3.1 describes.
#include "linespace/candidate_linespace.h"
#include "linespace/linespace_build.h"
#include "linespace/shaft_index.h"
#include "linespace/subtree_query.h"
#include "shaders/shared/intersect.h"
#include "tests/linespace/linespace_test_util.h"

#include <gtest/gtest.h>

namespace chcrt::ls {
namespace {

TEST(CandidateLineSpace, EveryCandidateIsTheCentroidRayHit) {
    const Scene scene = test::makeScene(test::randomSoup(2000, 4));
    const Bvh bvh = buildBvh(scene);
    LineSpaceParams params;
    params.n = 4;
    params.depth = 3;
    params.triangleThreshold = 8;
    const LineSpaces spaces = buildLineSpaces(bvh, params);
    const std::vector<TriangleRange> ranges = subtreeTriangleRanges(bvh);
    uint64_t candidates = 0, emptyByMiss = 0;
    for (uint32_t space = 0; space < spaces.bvhNodes.size(); ++space) {
        const uint32_t node = spaces.bvhNodes[space];
        const Aabb box{bvh.nodes[node].boundsMin, bvh.nodes[node].boundsMax};
        for (uint32_t s = 0; s < lsShaftCount(params.n, false); ++s) {
            glm::vec3 origin, direction;
            centroidRay(box, params.n, s, origin, direction);
            // Brute force over the node's triangles: smallest t in [0, 1], ties to the lower original id.
            uint32_t best = kEmptyShaft;
            float bestT = 0.0f;
            for (uint32_t i = ranges[node].first; i < ranges[node].first + ranges[node].count; ++i) {
                const TriangleGpu& t = bvh.triangles[i];
                const float th = gpu::intersectRayTriangle(origin, direction, t.v0, t.v1, t.v2).x;
                if (th >= 0.0f && th <= 1.0f &&
                    (best == kEmptyShaft || th < bestT || (th == bestT && t.originalId < bvh.triangles[best].originalId))) {
                    best = i;
                    bestT = th;
                }
            }
            const ShaftPatches p = decodeShaft(s, params.n, false);
            const uint32_t symmetric = lsShaftIndexFromPatches(p.startFace, p.startPatch, p.endFace, p.endPatch, params.n, true);
            const uint32_t stored = spaces.candidates.lookup(space, s);
            ASSERT_EQ(stored, best) << "space " << space << " shaft " << s;
            if (best != kEmptyShaft) {
                ++candidates;
                EXPECT_TRUE(spaces.binaryFilled(space, symmetric)); // candidates are a subset of the binary LS
            } else if (spaces.binaryFilled(space, symmetric)) {
                ++emptyByMiss; // geometry in the shaft, but the centroid ray misses it: empty (§3.1)
            }
        }
    }
    EXPECT_GT(candidates, 1000u);
    EXPECT_GT(emptyByMiss, 100u);
    EXPECT_EQ(candidates, spaces.candidates.filledCount());
}

TEST(CandidateLineSpace, ApproximateHitExtrapolatesThePlane) {
    // One small triangle in the plane y = 0 inside a node box [-1, 1] x [-1, 1] x [-1, 1] (a second triangle at
    // a corner sets the box). Rays hitting the plane away from the triangle still hit (extrapolation) with flat
    // normals; with normals fanned out, far extrapolation tilts the normal and is rejected.
    test::TriangleList triangles = {{glm::vec3(-0.2f, 0.0f, -0.2f), glm::vec3(0.2f, 0.0f, -0.2f), glm::vec3(0.0f, 0.0f, 0.2f)},
                                    {glm::vec3(-1.0f, -1.0f, -1.0f), glm::vec3(-0.99f, -1.0f, -1.0f), glm::vec3(-1.0f, -0.99f, -1.0f)},
                                    {glm::vec3(1.0f, 1.0f, 1.0f), glm::vec3(0.99f, 1.0f, 1.0f), glm::vec3(1.0f, 0.99f, 1.0f)}};
    Scene scene = test::makeScene(triangles);
    const Bvh bvh = buildBvh(scene);
    uint32_t flat = kEmptyShaft;
    for (uint32_t i = 0; i < bvh.triangles.size(); ++i) {
        flat = bvh.triangles[i].originalId == 0 ? i : flat;
    }
    Ray ray;
    ray.origin = glm::vec3(0.7f, 1.0f, 0.6f);
    ray.direction = glm::vec3(0.0f, -1.0f, 0.0f);
    ray.tmin = 0.0f;
    ray.tmax = 10.0f;
    const float cos30 = std::cos(glm::radians(30.0f));
    ApproximateHit h = intersectCandidatePlane(bvh, scene, flat, ray, 0.0f, 10.0f, cos30);
    ASSERT_TRUE(h.hit);
    EXPECT_FLOAT_EQ(h.t, 1.0f);
    EXPECT_GT(h.u + h.v, 1.0f); // outside the triangle: extrapolated
    EXPECT_NEAR(std::abs(h.normal.y), 1.0f, 1e-6f); // the flat vertex normals (winding gives -Y)
    EXPECT_FALSE(intersectCandidatePlane(bvh, scene, flat, ray, 0.0f, 0.5f, cos30).hit); // beyond [tLo, tHi]
    // frontOnly (faces=front): this ray meets the plane's back side (the counter-clockwise normal is -Y); the
    // same ray going up from below meets its front side.
    EXPECT_FALSE(intersectCandidatePlane(bvh, scene, flat, ray, 0.0f, 10.0f, cos30, true).hit);
    Ray up = ray;
    up.origin = glm::vec3(0.7f, -1.0f, 0.6f);
    up.direction = glm::vec3(0.0f, 1.0f, 0.0f);
    const ApproximateHit front = intersectCandidatePlane(bvh, scene, flat, up, 0.0f, 10.0f, cos30, true);
    ASSERT_TRUE(front.hit);
    EXPECT_FLOAT_EQ(front.t, 1.0f);
    EXPECT_TRUE(intersectCandidatePlane(bvh, scene, flat, up, 0.0f, 10.0f, cos30, false).hit);
    // Fan the vertex normals out by 20 degrees: near the triangle the extrapolated normal stays within 30
    // degrees of the mean, far outside it deviates more and the hit is discarded (an edge, §3.1).
    const float s = std::sin(glm::radians(20.0f)), c = std::cos(glm::radians(20.0f));
    scene.normals[0] = glm::vec3(-s, c, 0.0f);
    scene.normals[1] = glm::vec3(s, c, 0.0f);
    scene.normals[2] = glm::vec3(0.0f, c, s);
    ray.origin = glm::vec3(0.05f, 1.0f, 0.0f);
    EXPECT_TRUE(intersectCandidatePlane(bvh, scene, flat, ray, 0.0f, 10.0f, cos30).hit);
    ray.origin = glm::vec3(0.9f, 1.0f, 0.0f);
    EXPECT_FALSE(intersectCandidatePlane(bvh, scene, flat, ray, 0.0f, 10.0f, cos30).hit);
    ray.direction = glm::vec3(1.0f, 0.0f, 0.0f); // parallel to the plane
    EXPECT_FALSE(intersectCandidatePlane(bvh, scene, flat, ray, 0.0f, 10.0f, cos30).hit);
}

TEST(CandidateLineSpace, ApproximateHitUsesTheShaftsCandidate) {
    // A large horizontal quad: every ray through the node that crosses it gets a candidate of the quad, and the
    // approximate hit equals the exact hit (the plane is the geometry).
    test::TriangleList triangles = {{glm::vec3(-1.0f, 0.0f, -1.0f), glm::vec3(1.0f, 0.0f, -1.0f), glm::vec3(1.0f, 0.0f, 1.0f)},
                                    {glm::vec3(-1.0f, 0.0f, -1.0f), glm::vec3(1.0f, 0.0f, 1.0f), glm::vec3(-1.0f, 0.0f, 1.0f)},
                                    {glm::vec3(-1.0f, -1.0f, -1.0f), glm::vec3(-0.99f, -1.0f, -1.0f), glm::vec3(-1.0f, -0.99f, -1.0f)},
                                    {glm::vec3(1.0f, 1.0f, 1.0f), glm::vec3(0.99f, 1.0f, 1.0f), glm::vec3(1.0f, 0.99f, 1.0f)}};
    const Scene scene = test::makeScene(triangles);
    const Bvh bvh = buildBvh(scene);
    LineSpaceParams params;
    params.n = 6;
    params.depth = 0; // one Line Space on the root
    const LineSpaces spaces = buildLineSpaces(bvh, params);
    ASSERT_EQ(spaces.bvhNodes.size(), 1u);
    const Aabb box = bvh.rootBounds();
    test::Rng rng{3};
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        Ray ray;
        ray.origin = rng.uniform3(glm::vec3(-0.9f, 0.5f, -0.9f), glm::vec3(0.9f, 0.9f, 0.9f));
        ray.direction = rng.uniform3(glm::vec3(-0.9f, -0.1f, -0.9f), glm::vec3(0.9f, -0.1f, 0.9f)) - ray.origin;
        ray.tmax = 10.0f;
        const ApproximateHit h = approximateHit(bvh, scene, spaces.candidates, 0, box, params.n, ray, 30.0f);
        if (h.hit) {
            ++hits;
            EXPECT_NEAR(ray.origin.y + h.t * ray.direction.y, 0.0f, 1e-5f);
            EXPECT_LT(bvh.triangles[h.triangle].originalId, 2u);
        }
    }
    EXPECT_GT(hits, 1500); // most rays' shafts have a quad candidate
}

} // namespace
} // namespace chcrt::ls
