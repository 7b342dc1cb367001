// Binary Line Space correctness: the shaft/triangle and shaft/box tests agree with independent oracles, and
// no shaft marked empty contains geometry: (a) many random segments between random points of its two patches
// hit no triangle (brute force), (b) random rays classified by the shared shaft index into an empty shaft hit
// nothing in the node, (c) for box-shaped geometry the bits equal an exact, independently written oracle.
#include "linespace/binary_linespace.h"
#include "linespace/shaft_geometry.h"
#include "linespace/shaft_index.h"
#include "linespace/subtree_query.h"
#include "shaders/shared/intersect.h"
#include "tests/linespace/linespace_test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chcrt::ls {
namespace {

using test::Rng;

Aabb nodeBox(const Bvh& bvh, uint32_t node) { return {bvh.nodes[node].boundsMin, bvh.nodes[node].boundsMax}; }

glm::vec3 randomPointOnPatch(Rng& rng, const Aabb& box, uint32_t n, uint32_t face, uint32_t patch) {
    const BoxD r = patchRegion(box, n, PatchRect{face, patch % n, patch % n + 1, patch / n, patch / n + 1}, 0.0);
    return glm::vec3(rng.uniform(float(r.lower.x), float(r.upper.x)), rng.uniform(float(r.lower.y), float(r.upper.y)),
                     rng.uniform(float(r.lower.z), float(r.upper.z)));
}

// Does the segment p -> q (t in [0, 1]) hit any triangle of the subtree (brute force)?
bool segmentHitsTriangles(const Bvh& bvh, const TriangleRange& range, const glm::vec3& p, const glm::vec3& q) {
    for (uint32_t i = range.first; i < range.first + range.count; ++i) {
        const TriangleGpu& t = bvh.triangles[i];
        const float th = gpu::intersectRayTriangle(p, q - p, t.v0, t.v1, t.v2).x;
        if (th >= 0.0f && th <= 1.0f) {
            return true;
        }
    }
    return false;
}

TEST(ShaftGeometry, TriangleTestAgreesWithSegmentsAndIsExactOnSimpleCases) {
    // A shaft between the x = 0 and x = 1 faces' full patches of the unit cube is the cube itself.
    const Aabb cube{glm::vec3(0.0f), glm::vec3(1.0f)};
    const ShaftVolume whole(patchRegion(cube, 1, PatchRect{0, 0, 1, 0, 1}, 0.0), patchRegion(cube, 1, PatchRect{1, 0, 1, 0, 1}, 0.0));
    EXPECT_TRUE(shaftOverlapsTriangle(whole, {0.5f, 0.5f, 0.5f}, {0.6f, 0.5f, 0.5f}, {0.5f, 0.6f, 0.5f}));
    EXPECT_FALSE(shaftOverlapsTriangle(whole, {1.5f, 0.5f, 0.5f}, {1.6f, 0.5f, 0.5f}, {1.5f, 0.6f, 0.5f}));
    // Shaft from patch (0,0) of face x=0 (y, z in [0, .5]) to patch (1,1) of face x=1 (y, z in [.5, 1]): a
    // slanted prism. The point (0.5, 0.5, 0.5) is on it; (0.5, 0.9, 0.1) is not; a triangle spanning the
    // diagonal gap between its corners is cut only by the edge axes.
    const ShaftVolume slanted(patchRegion(cube, 2, PatchRect{0, 0, 1, 0, 1}, 0.0),
                              patchRegion(cube, 2, PatchRect{1, 1, 2, 1, 2}, 0.0));
    EXPECT_TRUE(shaftOverlapsTriangle(slanted, {0.5f, 0.45f, 0.5f}, {0.5f, 0.55f, 0.5f}, {0.5f, 0.5f, 0.55f}));
    EXPECT_FALSE(shaftOverlapsTriangle(slanted, {0.5f, 0.9f, 0.1f}, {0.5f, 0.95f, 0.1f}, {0.5f, 0.9f, 0.15f}));
    EXPECT_FALSE(shaftOverlapsTriangle(slanted, {0.1f, 0.9f, 0.9f}, {0.2f, 0.95f, 0.95f}, {0.15f, 0.9f, 0.99f}));
    EXPECT_TRUE(shaftOverlapsBox(slanted, {0.4, 0.4, 0.4}, {0.45, 0.45, 0.45}));
    EXPECT_FALSE(shaftOverlapsBox(slanted, {0.0, 0.8, 0.0}, {1.0, 1.0, 0.2}));

    // Random: whenever a segment between the patches hits a triangle, the exact test must say "overlaps".
    Rng rng{7};
    int hits = 0, overlaps = 0, trials = 0;
    for (int i = 0; i < 3000; ++i) {
        const uint32_t n = 1 + rng.below(4);
        const Aabb box{glm::vec3(-1.0f), glm::vec3(1.0f, 0.5f, 2.0f)};
        const uint32_t f1 = rng.below(6), f2 = (f1 + 1 + rng.below(5)) % 6;
        const uint32_t p1 = rng.below(n * n), p2 = rng.below(n * n);
        const ShaftVolume shaft(patchRegion(box, n, PatchRect{f1, p1 % n, p1 % n + 1, p1 / n, p1 / n + 1}, 0.0),
                                patchRegion(box, n, PatchRect{f2, p2 % n, p2 % n + 1, p2 / n, p2 / n + 1}, 0.0));
        // Half the triangles are centred on a segment of the shaft, half anywhere in the box.
        const glm::vec3 c = i % 2 == 0 ? glm::mix(randomPointOnPatch(rng, box, n, f1, p1), randomPointOnPatch(rng, box, n, f2, p2),
                                                  rng.uniform(0.0f, 1.0f))
                                       : rng.uniform3(box.lower, box.upper);
        // Even cases: a vertex on a segment of the shaft, so the triangle must overlap.
        const glm::vec3 v0 = i % 2 == 0 ? c : c + rng.uniform3(-0.8f, 0.8f), v1 = c + rng.uniform3(-0.8f, 0.8f), v2 = c + rng.uniform3(-0.8f, 0.8f);
        const bool overlap = shaftOverlapsTriangle(shaft, v0, v1, v2);
        overlaps += overlap ? 1 : 0;
        if (i % 2 == 0) {
            ASSERT_TRUE(overlap) << "a triangle with a vertex inside the shaft is rejected, case " << i;
        }
        for (int k = 0; k < 64; ++k) {
            const glm::vec3 p = randomPointOnPatch(rng, box, n, f1, p1), q = randomPointOnPatch(rng, box, n, f2, p2);
            const float th = gpu::intersectRayTriangle(p, q - p, v0, v1, v2).x;
            ++trials;
            if (th >= 0.0f && th <= 1.0f) {
                ++hits;
                ASSERT_TRUE(overlap) << "segment hits a triangle the exact test rejects, case " << i;
                break;
            }
        }
    }
    std::printf("[ geometry ] %d segment hits, %d exact overlaps of 3000 shaft/triangle pairs\n", hits, overlaps);
    EXPECT_GT(hits, 600);          // the comparison is not vacuous
    EXPECT_GT(overlaps, hits);     // and sampling misses overlaps that the exact test finds
    EXPECT_LT(overlaps, 2900);
}

struct NodeCase {
    Bvh bvh;
    std::vector<TriangleRange> ranges;
};

NodeCase buildSoupBvh(uint32_t triangles, uint32_t seed) {
    NodeCase c;
    c.bvh = buildBvh(test::makeScene(test::randomSoup(triangles, seed)));
    c.ranges = subtreeTriangleRanges(c.bvh);
    return c;
}

// Nodes with 50..400 triangles (and the root of a small soup): the sizes Line Spaces are built for.
std::vector<uint32_t> interestingNodes(const NodeCase& c, size_t maxNodes) {
    std::vector<uint32_t> nodes;
    for (uint32_t i = 0; i < c.bvh.nodes.size() && nodes.size() < maxNodes; ++i) {
        if (c.ranges[i].count >= 50 && c.ranges[i].count <= 400) {
            nodes.push_back(i);
        }
    }
    return nodes;
}

TEST(BinaryLineSpace, NoEmptyShaftContainsGeometryRandomSegments) {
    const NodeCase c = buildSoupBvh(1500, 1);
    const double dilation = shaftDilationForScene(c.bvh.rootBounds());
    Rng rng{11};
    uint64_t emptyShafts = 0, filledShafts = 0, segments = 0, filledSegmentHits = 0;
    for (const uint32_t node : interestingNodes(c, 3)) {
        for (const uint32_t n : {3u, 5u}) {
            const std::vector<uint32_t> words = computeBinaryLineSpace(c.bvh, node, n, dilation);
            const Aabb box = nodeBox(c.bvh, node);
            for (uint32_t s = 0; s < lsShaftCount(n, true); ++s) {
                const bool filled = ((words[s / 32] >> (s % 32)) & 1u) != 0u;
                const ShaftPatches p = decodeShaft(s, n, true);
                (filled ? filledShafts : emptyShafts)++;
                for (int k = 0; k < (filled ? 4 : 24); ++k) {
                    const glm::vec3 a = randomPointOnPatch(rng, box, n, p.startFace, p.startPatch);
                    const glm::vec3 b = randomPointOnPatch(rng, box, n, p.endFace, p.endPatch);
                    const bool hit = segmentHitsTriangles(c.bvh, c.ranges[node], a, b);
                    ++segments;
                    if (!filled) {
                        ASSERT_FALSE(hit) << "empty shaft " << s << " of node " << node << " (N=" << n << ") contains geometry";
                    }
                    filledSegmentHits += hit ? 1 : 0;
                }
            }
        }
    }
    std::printf("[ binary   ] %llu empty, %llu filled shafts; %llu segments\n", (unsigned long long)emptyShafts,
                (unsigned long long)filledShafts, (unsigned long long)segments);
    EXPECT_GT(emptyShafts, 1000u);
    EXPECT_GT(filledShafts, 1000u);
    EXPECT_GT(filledSegmentHits, filledShafts); // filled shafts really hold geometry the segments find
}

TEST(BinaryLineSpace, RaysInEmptyShaftsHitNothingInTheNode) {
    const NodeCase c = buildSoupBvh(1500, 2);
    const double dilation = shaftDilationForScene(c.bvh.rootBounds());
    Rng rng{12};
    uint64_t raysInEmpty = 0, raysHitting = 0;
    for (const uint32_t node : interestingNodes(c, 3)) {
        const uint32_t n = 4;
        const std::vector<uint32_t> words = computeBinaryLineSpace(c.bvh, node, n, dilation);
        const Aabb box = nodeBox(c.bvh, node);
        const glm::vec3 size = box.extent();
        for (int i = 0; i < 20000; ++i) {
            // Origins inside and around the node, directions at random points of it (many graze edges).
            const glm::vec3 origin = rng.uniform3(box.lower - size, box.upper + size);
            const glm::vec3 direction = rng.uniform3(box.lower, box.upper) - origin;
            const glm::vec3 invDir = gpu::safeInverseDirection(direction);
            const uint32_t shaft = gpu::lsShaftIndex(origin, direction, invDir, box.lower, box.upper, n, true);
            if (shaft == CHCRT_LS_NO_SHAFT) {
                continue;
            }
            const glm::vec2 entryExit = gpu::intersectRayAabb(origin, invDir, box.lower, box.upper);
            float t = 0.0f;
            const bool hit = subtreeClosestHit(c.bvh, node, origin, direction, std::max(0.0f, entryExit.x),
                                               entryExit.y, &t) != kNoTriangle;
            raysHitting += hit ? 1 : 0;
            if (((words[shaft / 32] >> (shaft % 32)) & 1u) == 0u) {
                ++raysInEmpty;
                ASSERT_FALSE(hit) << "ray " << i << " classified into empty shaft " << shaft << " hits node " << node;
            }
        }
    }
    EXPECT_GT(raysInEmpty, 2000u);
    EXPECT_GT(raysHitting, 2000u);
}

TEST(BinaryLineSpace, ExactForBoxGeometry) {
    Rng rng{21};
    for (int sceneIndex = 0; sceneIndex < 4; ++sceneIndex) {
        test::TriangleList triangles;
        std::vector<std::pair<glm::vec3, glm::vec3>> boxes;
        for (int b = 0; b < 3; ++b) {
            const glm::vec3 lo = rng.uniform3(-4.0f, 3.0f);
            const glm::vec3 hi = lo + rng.uniform3(0.2f, 1.5f);
            boxes.push_back({lo, hi});
            test::appendBox(triangles, lo, hi);
        }
        const Bvh bvh = buildBvh(test::makeScene(triangles));
        const Aabb root = bvh.rootBounds();
        const double dilation = shaftDilationForScene(root);
        for (const uint32_t n : {2u, 4u, 6u}) {
            const std::vector<uint32_t> words = computeBinaryLineSpace(bvh, 0, n, dilation);
            int filled = 0, empty = 0;
            for (uint32_t s = 0; s < lsShaftCount(n, true); ++s) {
                const ShaftPatches p = decodeShaft(s, n, true);
                auto region = [&](uint32_t face, uint32_t patch, double grow) {
                    return patchRegion(root, n, PatchRect{face, patch % n, patch % n + 1, patch / n, patch / n + 1}, grow);
                };
                bool exact = false, dilated = false;
                for (const auto& [lo, hi] : boxes) {
                    exact = exact || test::hullMeetsBox(region(p.startFace, p.startPatch, 0.0), region(p.endFace, p.endPatch, 0.0),
                                                  glm::dvec3(lo), glm::dvec3(hi));
                    dilated = dilated || test::hullMeetsBox(region(p.startFace, p.startPatch, dilation),
                                                      region(p.endFace, p.endPatch, dilation), glm::dvec3(lo), glm::dvec3(hi));
                }
                const bool bit = ((words[s / 32] >> (s % 32)) & 1u) != 0u;
                (bit ? filled : empty)++;
                // Conservative: geometry in the exact shaft => bit set. Tight: bit set => geometry in the dilated shaft.
                ASSERT_TRUE(!exact || bit) << "scene " << sceneIndex << " N=" << n << " shaft " << s;
                ASSERT_TRUE(!bit || dilated) << "scene " << sceneIndex << " N=" << n << " shaft " << s;
            }
            EXPECT_GT(filled, 0);
            EXPECT_GT(empty, 0);
        }
    }
}

TEST(BinaryLineSpace, SubtreeRangesAreContiguous) {
    const NodeCase c = buildSoupBvh(800, 3);
    EXPECT_EQ(c.ranges[0].first, 0u);
    EXPECT_EQ(c.ranges[0].count, c.bvh.triangles.size());
    for (uint32_t i = 0; i < c.bvh.nodes.size(); ++i) {
        if (!c.bvh.isLeaf(i)) {
            const uint32_t l = c.bvh.nodes[i].leftFirst;
            EXPECT_EQ(c.ranges[l].count + c.ranges[l + 1].count, c.ranges[i].count);
        }
    }
}

} // namespace
} // namespace chcrt::ls
