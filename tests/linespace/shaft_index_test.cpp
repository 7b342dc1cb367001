// Shaft indexing (shaders/shared/linespace_layout.h, C++ build): index layouts are bijections with the paper's
// counts, decoding inverts them, and rays are classified into the patches where their line really enters and
// leaves the box (checked against a double-precision computation), also for rays starting inside the box.
#include "linespace/shaft_geometry.h"
#include "linespace/shaft_index.h"
#include "tests/linespace/linespace_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace chcrt::ls {
namespace {

using test::Rng;

TEST(ShaftIndex, CountsFollowThePaper) {
    EXPECT_EQ(lsShaftCount(1, false), 30u);
    EXPECT_EQ(lsShaftCount(1, true), 15u);
    EXPECT_EQ(lsShaftCount(6, false), 30u * 1296u);
    EXPECT_EQ(lsShaftCount(6, true), 15u * 1296u);
    EXPECT_EQ(lsShaftCount(10, false), 300000u);
    EXPECT_EQ(lsWordCount(4, true), (15u * 256u + 31u) / 32u);
}

TEST(ShaftIndex, LayoutsAreBijectionsAndDecode) {
    for (uint32_t n = 1; n <= 6; ++n) {
        const uint32_t nn = n * n;
        std::vector<int> nonSymmetricHits(lsShaftCount(n, false), 0), symmetricHits(lsShaftCount(n, true), 0);
        for (uint32_t f1 = 0; f1 < 6; ++f1) {
            for (uint32_t f2 = 0; f2 < 6; ++f2) {
                if (f1 == f2) {
                    continue;
                }
                for (uint32_t p1 = 0; p1 < nn; ++p1) {
                    for (uint32_t p2 = 0; p2 < nn; ++p2) {
                        const uint32_t a = lsShaftIndexFromPatches(f1, p1, f2, p2, n, false);
                        const uint32_t s = lsShaftIndexFromPatches(f1, p1, f2, p2, n, true);
                        ASSERT_LT(a, nonSymmetricHits.size());
                        ASSERT_LT(s, symmetricHits.size());
                        ++nonSymmetricHits[a];
                        ++symmetricHits[s];
                        EXPECT_EQ(s, lsShaftIndexFromPatches(f2, p2, f1, p1, n, true));
                        const ShaftPatches d = decodeShaft(a, n, false);
                        EXPECT_TRUE(d.startFace == f1 && d.startPatch == p1 && d.endFace == f2 && d.endPatch == p2);
                        const ShaftPatches ds = decodeShaft(s, n, true);
                        EXPECT_EQ(lsShaftIndexFromPatches(ds.startFace, ds.startPatch, ds.endFace, ds.endPatch, n, true), s);
                        EXPECT_LT(ds.startFace, ds.endFace);
                    }
                }
            }
        }
        // Every ordered shaft exactly once; every unordered one from both orders.
        EXPECT_TRUE(std::all_of(nonSymmetricHits.begin(), nonSymmetricHits.end(), [](int c) { return c == 1; }));
        EXPECT_TRUE(std::all_of(symmetricHits.begin(), symmetricHits.end(), [](int c) { return c == 2; }));
    }
}

// Entry/exit face and point of a line with a box, in double precision (the oracle).
struct LineHit {
    bool hit = false;
    int entryFace = -1, exitFace = -1;
    glm::dvec3 entry{0.0}, exit{0.0};
    double entryFaceMargin = 0.0, exitFaceMargin = 0.0; // gap between the winning and the second axis (in t)
};

LineHit lineBoxDouble(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi) {
    LineHit h;
    double tNear[3], tFar[3];
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < lo[a] || o[a] > hi[a]) {
                return h;
            }
            tNear[a] = -INFINITY;
            tFar[a] = INFINITY;
            continue;
        }
        const double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
        tNear[a] = std::min(t0, t1);
        tFar[a] = std::max(t0, t1);
    }
    const int ea = int(std::max_element(tNear, tNear + 3) - tNear), xa = int(std::min_element(tFar, tFar + 3) - tFar);
    if (tNear[ea] > tFar[xa]) {
        return h;
    }
    h.hit = true;
    h.entryFace = 2 * ea + (d[ea] > 0.0 ? 0 : 1);
    h.exitFace = 2 * xa + (d[xa] > 0.0 ? 1 : 0);
    h.entry = o + tNear[ea] * d;
    h.exit = o + tFar[xa] * d;
    double secondNear = -INFINITY, secondFar = INFINITY;
    for (int a = 0; a < 3; ++a) {
        if (a != ea) {
            secondNear = std::max(secondNear, tNear[a]);
        }
        if (a != xa) {
            secondFar = std::min(secondFar, tFar[a]);
        }
    }
    h.entryFaceMargin = (tNear[ea] - secondNear) * glm::length(d);
    h.exitFaceMargin = (secondFar - tFar[xa]) * glm::length(d);
    return h;
}

// Distance (in the face plane) from p to the boundary of patch `patch` of `face`; negative when outside.
double insidePatchMargin(const Aabb& box, uint32_t n, uint32_t face, uint32_t patch, const glm::dvec3& p) {
    const BoxD r = patchRegion(box, n, PatchRect{face, patch % n, patch % n + 1, patch / n, patch / n + 1}, 0.0);
    const int axis = int(face >> 1u);
    double margin = INFINITY;
    for (int a = 0; a < 3; ++a) {
        if (a != axis) {
            margin = std::min({margin, p[a] - r.lower[a], r.upper[a] - p[a]});
        }
    }
    return margin;
}

TEST(ShaftIndex, RaysAreClassifiedWhereTheirLineEntersAndLeaves) {
    Rng rng{99};
    int checked = 0, inside = 0, unambiguous = 0, degenerate = 0;
    for (int i = 0; i < 40000; ++i) {
        const uint32_t n = 1 + rng.below(10);
        const glm::vec3 centre = rng.uniform3(-50.0f, 50.0f);
        glm::vec3 half = rng.uniform3(0.1f, 5.0f);
        if (i % 7 == 0) {
            half[static_cast<int>(rng.below(3))] = 0.0f; // flat box (planar geometry in a BVH node)
        }
        const Aabb box{centre - half, centre + half};
        // Origins inside (a third) or around the box; directions towards a random point of the box.
        const glm::vec3 origin = i % 3 == 0 ? rng.uniform3(box.lower, box.upper) : centre + rng.uniform3(-20.0f, 20.0f);
        glm::vec3 direction = rng.uniform3(box.lower, box.upper) - origin;
        if (i % 11 == 0) {
            direction[static_cast<int>(rng.below(3))] = 0.0f;
        }
        if (direction == glm::vec3(0.0f)) {
            continue;
        }
        const glm::uvec4 p = gpu::lsEntryExitPatches(origin, direction, gpu::safeInverseDirection(direction), box.lower,
                                                     box.upper, n);
        const LineHit h = lineBoxDouble(glm::dvec3(origin), glm::dvec3(direction), glm::dvec3(box.lower),
                                        glm::dvec3(box.upper));
        if (!h.hit) {
            continue;
        }
        ASSERT_NE(p.x, CHCRT_LS_NO_SHAFT) << "case " << i;
        ASSERT_NE(p.x, p.z) << "entry and exit faces must differ, case " << i;
        ASSERT_LT(p.y, n * n);
        ASSERT_LT(p.w, n * n);
        // A line inside a face's plane (zero direction component, origin on that plane; every ray in a flat
        // box's plane) touches the box, for the slab test, only at t = 0 (safeInverse: 0 * 1e30 = 0), which is
        // where the tracer's box test puts it too; the double oracle sees the whole segment. Only validity above.
        bool inFacePlane = false;
        for (int a = 0; a < 3; ++a) {
            inFacePlane = inFacePlane || (direction[a] == 0.0f && (origin[a] == box.lower[a] || origin[a] == box.upper[a]));
        }
        if (inFacePlane) {
            ++degenerate;
            continue;
        }
        ++checked;
        inside += i % 3 == 0 ? 1 : 0;
        // Float rounding can move the point across a patch boundary or (near edges) onto the other face, by far
        // less than this tolerance; the Line Space builders dilate shafts by more (shaftDilationForScene).
        const double tolerance = 1e-5 * (glm::length(glm::dvec3(centre)) + glm::length(glm::dvec3(origin)) + 20.0);
        const bool entryClear = h.entryFaceMargin > tolerance, exitClear = h.exitFaceMargin > tolerance;
        if (entryClear) {
            EXPECT_EQ(int(p.x), h.entryFace) << "case " << i;
        }
        if (exitClear) {
            EXPECT_EQ(int(p.z), h.exitFace) << "case " << i;
        }
        // The classified patch contains the true point, up to the tolerance (clamping at edges included).
        const glm::dvec3 entryOnFace = h.entry, exitOnFace = h.exit;
        EXPECT_GT(insidePatchMargin(box, n, p.x, p.y, entryOnFace), -tolerance) << "case " << i;
        EXPECT_GT(insidePatchMargin(box, n, p.z, p.w, exitOnFace), -tolerance) << "case " << i;
        unambiguous += entryClear && exitClear ? 1 : 0;
    }
    EXPECT_GT(degenerate, 100);
    EXPECT_GT(checked, 20000);
    EXPECT_GT(inside, 8000);
    EXPECT_GT(unambiguous, checked * 9 / 10);
}

TEST(ShaftIndex, MissesAndEdgeRays) {
    const Aabb box{glm::vec3(0.0f), glm::vec3(1.0f)};
    // A line that misses.
    EXPECT_EQ(shaftIndexForRay(box, 4, false, glm::vec3(2.0f, 2.0f, -1.0f), glm::vec3(0.0f, 0.0f, 1.0f)),
              CHCRT_LS_NO_SHAFT);
    // Exactly through the edge x = 0, y = 0 along +z: a valid shaft between the two z faces, corner patches.
    const glm::uvec4 p = gpu::lsEntryExitPatches(glm::vec3(0.0f, 0.0f, -1.0f), glm::vec3(0.0f, 0.0f, 1.0f),
                                                 gpu::safeInverseDirection(glm::vec3(0.0f, 0.0f, 1.0f)), box.lower,
                                                 box.upper, 4);
    EXPECT_EQ(p, glm::uvec4(4u, 0u, 5u, 0u));
    // Through the far corner (1,1,1) along the diagonal: clamped into the last patch, not out of range.
    const glm::uvec4 q = gpu::lsEntryExitPatches(glm::vec3(-1.0f), glm::vec3(1.0f), glm::vec3(1.0f), box.lower,
                                                 box.upper, 4);
    EXPECT_EQ(q.x, 0u);          // ties go to the lower axis: enters through x min
    EXPECT_EQ(q.y, 0u);
    EXPECT_EQ(q.z, 1u);          // leaves through x max
    EXPECT_EQ(q.w, 15u);         // corner (1,1) of that face -> patch (3,3)
    // A ray starting inside is classified by its line: same shaft as the same line started outside.
    const glm::vec3 d(0.3f, 0.5f, 0.8f);
    EXPECT_EQ(shaftIndexForRay(box, 6, false, glm::vec3(0.5f) - d, d), shaftIndexForRay(box, 6, false, glm::vec3(0.5f), d));
}

} // namespace
} // namespace chcrt::ls
