#pragma once
// Compares two tracers' hit buffers for the same rays (GLSL vs Embree in `verify`, GLSL vs CPU in tests,
// later CHC+RT vs pure BVH). The tolerance is stated, not tuned:
//   - closest hit: both miss, or both hit with |t_a - t_b| <= relativeT · t + absoluteT + the rounding-error bound
//     of a float ray/triangle distance for the hit triangles (k·2^-24·(|s||e1||e2| + t|e1||e2|)/|det|, k = 16:
//     thin triangles amplify rounding far beyond any fixed relative tolerance). The triangle ids
//     may then differ only when both surfaces are at that distance (a shared edge or coincident faces); such
//     pixels are counted as `ties`, not as differences.
//   - any hit (shadow, AO): only hit/miss is compared. Both buffers must carry the id of a hit triangle (trace
//     the reference with closest-hit queries: same hit/miss answer, and the id lets edge cases be recognised).
//   - a pixel where one tracer hits triangle X and the other misses it (or passes it for a farther hit) is an
//     `edgeCase`, not a difference, when the ray meets X only within `barycentricEpsilon` (plus the rounding-
//     error bound of float barycentrics for X, which thin triangles widen) of its border
//     (the two tracers' triangle tests round differently there: Möller-Trumbore vs Embree's watertight test).
// Every other mismatch is `differing`; `verify` exits non-zero when it is above zero.
#include "renderer/bvh/cpu_tracer.h"
#include "renderer/scene/scene.h"

#include <cstdint>
#include <span>
#include <vector>

namespace chcrt {

struct HitTolerance {
    float relativeT = 1e-4f;
    float absoluteT = 1e-6f; // scaled by the scene diagonal by the caller
    float barycentricEpsilon = 1e-4f;
};

struct HitComparison {
    uint64_t rays = 0;       // all pixels
    uint64_t activeRays = 0; // tmax > tmin
    uint64_t hitsA = 0;
    uint64_t hitsB = 0;
    uint64_t ties = 0;
    uint64_t edgeCases = 0;
    uint64_t differing = 0;
    double maxRelativeTError = 0.0; // over pixels where both hit the same triangle
    void add(const HitComparison& other);
};

// Exact comparison for conservative methods (CHC+RT vs pure BVH): a pixel differs unless both carry the same
// triangle id and the same bits of t. Any-hit rays (shadow, AO) only answer "occluded or not", and which occluder
// is found first depends on traversal order, so for them only hit/miss must agree. `differing` (optional) receives
// the indices of the pixels that differ.
HitComparison compareHitsExactly(std::span<const Ray> rays, std::span<const Hit> a, std::span<const Hit> b,
                                 bool anyHit, std::vector<size_t>* differing = nullptr);

// The ray/triangle intersection of triangle `id` in double precision (for reports): t and barycentrics
// (u of v1, v of v2) of the ray's line; det == 0 for a parallel ray.
struct ExactIntersection {
    double t = 0, u = 0, v = 0, det = 0;
};
ExactIntersection intersectInDouble(const Scene& scene, const Ray& ray, uint32_t id);

// `differingPixels`, when given, receives the indices of the differing pixels (for reports).
HitComparison compareHits(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> a,
                          std::span<const Hit> b, bool anyHit, const HitTolerance& tolerance,
                          std::vector<size_t>* differingPixels = nullptr);

} // namespace chcrt
