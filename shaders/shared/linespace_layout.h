#ifndef CHCRT_SHARED_LINESPACE_LAYOUT_H
#define CHCRT_SHARED_LINESPACE_LAYOUT_H
// Line Space shaft indexing and sparse lookup, written once in the common subset of GLSL 4.50 and C++/GLM
// so that the CPU builder, the CPU reference and the GLSL traversal classify every ray into the same shaft
// (tests/linespace/shaft_index_twin_test.cpp compares the two builds on random rays and boxes).
//
// Line Space of a box (Keul et al. 2017 §3, representative candidate paper §3): each of the 6 faces is divided
// into N x N patches; a shaft is a pair of patches on different faces; its volume is the convex hull of the
// two patches. 30 N^4 ordered (non-symmetric) shafts, 15 N^4 unordered (symmetric) ones.
//
// Faces: face = 2 * axis + side, side 0 = the box's min plane on that axis, 1 = the max plane. Patches on a
// face: the two other axes u = (axis + 1) % 3, v = (axis + 2) % 3 are cut into N equal intervals of the box's
// extent; patch = pv * N + pu. Boxes need not be cubes (BVH nodes); an axis of zero extent has one patch row
// (every point falls into patch coordinate 0).
//
// The entry and exit point are those of the ray's *line* with the box (the slab test of intersect.h, with t
// unrestricted). A ray that starts inside the box is therefore classified by where its line enters, i.e. by
// its backward extension: the ray's part inside the box lies inside that shaft's volume, so an empty shaft
// still proves that the ray hits nothing in the box (exact skipping stays exact). Whether an approximate use
// (shadow early termination, candidates) may be applied to a ray starting inside is the caller's decision;
// the soft-shadow paper (§4.1) skips the node the ray starts in.
#include "intersect.h"
#ifdef __cplusplus
#include <bit>
#endif
#include "shared_begin.h"

#ifdef __cplusplus
#define CHCRT_LS_INLINE inline
// GLSL's `precise` forbids fusing a * b + c into an fma; GCC does not contract across statements in ISO mode,
// so the C++ side needs nothing.
#define CHCRT_LS_PRECISE
using glm::clamp;
using glm::floor;
#else
#define CHCRT_LS_INLINE
#define CHCRT_LS_PRECISE precise
#endif

// Returned by lsShaftIndex when the ray's line misses the box.
#define CHCRT_LS_NO_SHAFT 0xFFFFFFFFu
// Returned by lsSparseSlot for a shaft without data (empty).
#define CHCRT_LS_EMPTY_SLOT 0xFFFFFFFFu
// Largest supported patch resolution N (30 * 10^4 shafts still fits comfortably in 32 bits).
#define CHCRT_LS_MAX_N 16u

CHCRT_LS_INLINE uint lsShaftCount(uint n, bool symmetric) {
    uint n4 = n * n * n * n;
    return symmetric ? 15u * n4 : 30u * n4;
}

CHCRT_LS_INLINE uint lsBitCount(uint x) {
#ifdef __cplusplus
    return uint(std::popcount(x));
#else
    return uint(bitCount(x));
#endif
}

// Patch coordinate (0..n-1) of coordinate x in [lo, hi] cut into n intervals; points outside (rounding at
// edges and corners) are clamped into the first or last interval.
CHCRT_LS_INLINE uint lsPatchCoordinate(float x, float lo, float hi, uint n) {
    float extent = hi - lo;
    CHCRT_LS_PRECISE float scaled = extent > 0.0f ? (x - lo) / extent * float(n) : 0.0f;
    return uint(clamp(floor(scaled), 0.0f, float(n - 1u)));
}

// Patch (pv * n + pu) of point p on face `face` of the box.
CHCRT_LS_INLINE uint lsPatchOnFace(vec3 p, uint face, vec3 boxMin, vec3 boxMax, uint n) {
    int axis = int(face >> 1u);
    int ua = (axis + 1) % 3;
    int va = (axis + 2) % 3;
    uint pu = lsPatchCoordinate(p[ua], boxMin[ua], boxMax[ua], n);
    uint pv = lsPatchCoordinate(p[va], boxMin[va], boxMax[va], n);
    return pv * n + pu;
}

// CALCSHAFT: index of the shaft from (startFace, startPatch) to (endFace, endPatch); faces must differ.
// Non-symmetric: ((startFace * N^2 + startPatch) * 5 + endFace') * N^2 + endPatch, endFace' skipping startFace.
// Symmetric: the pair is ordered by face, (facePair * N^2 + lowerFacePatch) * N^2 + higherFacePatch with
// facePair = f1 * (11 - f1) / 2 + (f2 - f1 - 1) for f1 < f2 (0..14).
CHCRT_LS_INLINE uint lsShaftIndexFromPatches(uint startFace, uint startPatch, uint endFace, uint endPatch, uint n,
                                             bool symmetric) {
    uint nn = n * n;
    if (symmetric) {
        uint f1 = min(startFace, endFace);
        uint f2 = max(startFace, endFace);
        uint p1 = startFace < endFace ? startPatch : endPatch;
        uint p2 = startFace < endFace ? endPatch : startPatch;
        uint facePair = f1 * (11u - f1) / 2u + (f2 - f1 - 1u);
        return (facePair * nn + p1) * nn + p2;
    }
    uint relativeEnd = endFace < startFace ? endFace : endFace - 1u;
    return ((startFace * nn + startPatch) * 5u + relativeEnd) * nn + endPatch;
}

// Entry and exit face, patch and distance of the ray's line with the box: (entryFace, entryPatch, exitFace,
// exitPatch) in .xyzw of the returned uvec4, x = CHCRT_LS_NO_SHAFT when the line misses. The entry face is
// the axis with the largest near distance and the exit face the axis with the smallest far distance (ties go
// to the lower axis), which is exactly where intersectRayAabb's max/min came from; entry and exit can share
// an axis only on opposite sides, so the two faces always differ. invDir = safeInverseDirection(direction).
CHCRT_LS_INLINE uvec4 lsEntryExitPatches(vec3 origin, vec3 direction, vec3 invDir, vec3 boxMin, vec3 boxMax,
                                         uint n) {
    vec3 t0 = (boxMin - origin) * invDir;
    vec3 t1 = (boxMax - origin) * invDir;
    vec3 tNear = min(t0, t1);
    vec3 tFar = max(t0, t1);
    int entryAxis = 0;
    float tEntry = tNear.x;
    if (tNear.y > tEntry) {
        entryAxis = 1;
        tEntry = tNear.y;
    }
    if (tNear.z > tEntry) {
        entryAxis = 2;
        tEntry = tNear.z;
    }
    int exitAxis = 0;
    float tExit = tFar.x;
    if (tFar.y < tExit) {
        exitAxis = 1;
        tExit = tFar.y;
    }
    if (tFar.z < tExit) {
        exitAxis = 2;
        tExit = tFar.z;
    }
    if (!(tEntry <= tExit)) {
        return uvec4(CHCRT_LS_NO_SHAFT, 0u, 0u, 0u);
    }
    // A ray moving towards +axis enters through the min plane and leaves through the max plane.
    bool entryPositive = invDir[entryAxis] >= 0.0f;
    bool exitPositive = invDir[exitAxis] >= 0.0f;
    uint entryFace = uint(entryAxis) * 2u + (entryPositive ? 0u : 1u);
    uint exitFace = uint(exitAxis) * 2u + (exitPositive ? 1u : 0u);
    CHCRT_LS_PRECISE vec3 entryPoint = origin + tEntry * direction;
    CHCRT_LS_PRECISE vec3 exitPoint = origin + tExit * direction;
    return uvec4(entryFace, lsPatchOnFace(entryPoint, entryFace, boxMin, boxMax, n), exitFace,
                 lsPatchOnFace(exitPoint, exitFace, boxMin, boxMax, n));
}

// CALCPATCH + CALCSHAFT (representative candidate paper, Algorithm 1): the shaft of the ray's line in the box,
// or CHCRT_LS_NO_SHAFT when the line misses it.
CHCRT_LS_INLINE uint lsShaftIndex(vec3 origin, vec3 direction, vec3 invDir, vec3 boxMin, vec3 boxMax, uint n,
                                  bool symmetric) {
    uvec4 patches = lsEntryExitPatches(origin, direction, invDir, boxMin, boxMax, n);
    if (patches.x == CHCRT_LS_NO_SHAFT) {
        return CHCRT_LS_NO_SHAFT;
    }
    return lsShaftIndexFromPatches(patches.x, patches.y, patches.z, patches.w, n, symmetric);
}

// GETSPARSEDATA (representative candidate paper, Algorithm 2): `word` is bitset word shaft / 32 of a Line
// Space, `wordOffset` the prefix sum of the filled shafts before that word. Returns the slot of the shaft's
// entry in the data pool, or CHCRT_LS_EMPTY_SLOT when the shaft is empty. Constant time: one popcount.
CHCRT_LS_INLINE uint lsSparseSlot(uint word, uint wordOffset, uint shaft) {
    uint bit = shaft & 31u;
    if (((word >> bit) & 1u) == 0u) {
        return CHCRT_LS_EMPTY_SLOT;
    }
    return wordOffset + lsBitCount(word << (31u - bit)) - 1u;
}

// GPU records of a set of Line Spaces (texture buffers, R32UI / RGBA32F as the BVH; integration next):
// one record per Line Space node = 2 RGBA32F texels = 32 bytes:
//   texel 0: boundsMin.xyz, bvhNode     texel 1: boundsMax.xyz, wordBase
// wordBase indexes the bitset words (and, for candidate Line Spaces, the per-word offsets) of this Line Space.
#define CHCRT_LS_TEXELS_PER_NODE 2

#ifdef __cplusplus
struct LineSpaceNodeGpu {
    vec3 boundsMin;
    uint bvhNode; // 16 bytes
    vec3 boundsMax;
    uint wordBase; // 32 bytes
};
static_assert(sizeof(LineSpaceNodeGpu) == 16 * CHCRT_LS_TEXELS_PER_NODE);
#endif

#undef CHCRT_LS_INLINE
#undef CHCRT_LS_PRECISE
#include "shared_end.h"
#endif
