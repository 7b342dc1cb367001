#ifndef CHCRT_SHARED_INTERSECT_H
#define CHCRT_SHARED_INTERSECT_H
// Ray/box and ray/triangle tests, written once in the common subset of GLSL 4.50 and C++/GLM so that the
// GLSL tracer and the CPU tracer (its test twin) run the same arithmetic. tests/gl/intersect_twin_test.cpp
// dispatches these in a shader and compares with the C++ build of the same text.
#include "shared_begin.h"

#ifdef __cplusplus
#define CHCRT_INLINE inline
using glm::abs;
using glm::cross;
using glm::max;
using glm::min;
#else
#define CHCRT_INLINE
#endif

// Dot product with a fixed summation order. GLSL's dot() on llvmpipe sums as x + (y + z) while glm::dot sums
// left to right; spelling the order out makes the C++ twin bit-identical to the shader (measured in
// tests/gl/intersect_twin_test.cpp). Drivers that fuse multiply-adds (NVIDIA) may still differ in the last bits.
CHCRT_INLINE float dotOrdered(vec3 a, vec3 b) {
    return (a.x * b.x + a.y * b.y) + a.z * b.z;
}

// 1 / direction with zero components replaced by ±1e-30: an infinite inverse would turn (bound - origin) * invDir
// into 0 * inf = NaN for a ray starting exactly on a box face, and GLSL's min/max are undefined for NaN. 1e30 is
// still "infinitely" steep for any box in a scene, so no hit is lost.
CHCRT_INLINE float safeInverse(float d) {
    return 1.0f / (abs(d) > 1e-30f ? d : (d >= 0.0f ? 1e-30f : -1e-30f));
}
CHCRT_INLINE vec3 safeInverseDirection(vec3 d) {
    return vec3(safeInverse(d.x), safeInverse(d.y), safeInverse(d.z));
}

// Slab test. Returns (tEntry, tExit) of the ray's line with the box; the ray [tmin, tmax] hits the box when
// tEntry <= tExit && tExit >= tmin && tEntry <= tmax. invDir = safeInverseDirection(direction).
CHCRT_INLINE vec2 intersectRayAabb(vec3 origin, vec3 invDir, vec3 boundsMin, vec3 boundsMax) {
    vec3 t0 = (boundsMin - origin) * invDir;
    vec3 t1 = (boundsMax - origin) * invDir;
    vec3 tNear = min(t0, t1);
    vec3 tFar = max(t0, t1);
    float tEntry = max(max(tNear.x, tNear.y), tNear.z);
    float tExit = min(min(tFar.x, tFar.y), tFar.z);
    return vec2(tEntry, tExit);
}

// The hit rule for a triangle the ray meets at computed t `tHit` (tmin <= tHit <= best t): x = its t, at least the
// computed entry distance of the triangle's own bounding box; y = 1 when the ray meets that box by the slab test, else
// 0 (no hit). An ill-conditioned triangle can be hit at a computed t before the boxes that hold it (seen on the 1M
// plant: 224.27803 against a double-precision 224.283014, beyond pruneLimit's margin), and a grazing ray can meet a
// triangle that lies in a box face while the slab test says it misses the box (the 10M city's far path: three
// pixels). Every box on the triangle's path contains its bounding box, and the slab test is monotone in the bounds
// (a smaller box is entered no earlier and left no later), so a triangle that passes is never pruned nor skipped,
// in any order and whatever the boxes: the hit depends neither on the traversal order nor on the BVH (the compact
// layout's quantized boxes give the full layout's hits bit for bit). Only a candidate needs it: the clamp never
// lowers t.
CHCRT_INLINE vec2 hitRule(float tHit, float tmin, vec3 origin, vec3 invDir, vec3 v0, vec3 v1, vec3 v2) {
    vec2 box = intersectRayAabb(origin, invDir, min(min(v0, v1), v2), max(max(v0, v1), v2));
    return vec2(max(tHit, box.x), box.x <= box.y && box.y >= tmin ? 1.0f : 0.0f);
}

// The distance up to which boxes are still visited when the closest hit so far is at bestT. A triangle inside a
// box can be hit at a computed t a few ulps *below* the box's computed entry distance (different rounding), so
// pruning at exactly bestT could skip a box holding an equal-t triangle with a lower id, and the tie-break would
// then depend on traversal order (seen once on the 1M plant: CHC+RT and pure BVH visit subtrees in different
// orders). A relative margin of 2^-20 is far above those rounding errors and costs nothing measurable. Every
// tracer (GLSL, CPU twin, CHC+RT queries) prunes with this limit.
CHCRT_INLINE float pruneLimit(float bestT) {
    return bestT * (1.0f + 1.0f / 1048576.0f);
}

CHCRT_INLINE bool rayHitsAabb(vec2 entryExit, float tmin, float tmax) {
    return entryExit.x <= entryExit.y && entryExit.y >= tmin && entryExit.x <= tmax;
}

// Möller-Trumbore. Returns (t, u, v) with barycentrics u (of v1) and v (of v2); t = -1 when the ray's line
// misses the triangle or is parallel to it. Both faces count (the scenes are not closed).
CHCRT_INLINE vec3 intersectRayTriangle(vec3 origin, vec3 direction, vec3 v0, vec3 v1, vec3 v2) {
    vec3 e1 = v1 - v0;
    vec3 e2 = v2 - v0;
    vec3 p = cross(direction, e2);
    float det = dotOrdered(e1, p);
    // Parallel (or degenerate) triangles have det == 0 exactly; no epsilon so that thin triangles still hit.
    if (det == 0.0f) {
        return vec3(-1.0f, 0.0f, 0.0f);
    }
    float invDet = 1.0f / det;
    vec3 s = origin - v0;
    float u = dotOrdered(s, p) * invDet;
    if (u < 0.0f || u > 1.0f) {
        return vec3(-1.0f, 0.0f, 0.0f);
    }
    vec3 q = cross(s, e1);
    float v = dotOrdered(direction, q) * invDet;
    if (v < 0.0f || u + v > 1.0f) {
        return vec3(-1.0f, 0.0f, 0.0f);
    }
    float t = dotOrdered(e2, q) * invDet;
    return vec3(t, u, v);
}

#undef CHCRT_INLINE
#include "shared_end.h"
#endif
