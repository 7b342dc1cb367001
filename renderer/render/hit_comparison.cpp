#include "renderer/render/hit_comparison.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace chcrt {
namespace {

constexpr double kUnitsOfRoundoff = 16.0;

// Does the ray meet triangle `id` (within [tmin - slack, tmax + slack]) only near its border? Uses the
// barycentrics in double precision with a band of `epsilon` plus the rounding-error bound of single-precision
// barycentrics (|du| <~ k 2^-24 |s| max(|e1|, |e2|) / |det|: thin triangles widen it, as for t below).
bool meetsTriangleNearEdge(const Scene& scene, const Ray& ray, uint32_t id, float epsilon, float tSlack) {
    if (id >= scene.triangles.size()) return false;
    const ExactIntersection x = intersectInDouble(scene, ray, id);
    if (x.det == 0.0) return true; // parallel: any decision is a rounding decision
    const glm::uvec3 tri = scene.triangles[id];
    const glm::dvec3 v0 = scene.positions[tri.x];
    const double edge = std::max(glm::length(glm::dvec3(scene.positions[tri.y]) - v0),
                                 glm::length(glm::dvec3(scene.positions[tri.z]) - v0));
    const double band = epsilon + kUnitsOfRoundoff * std::ldexp(1.0, -24) * glm::length(glm::dvec3(ray.origin) - v0) *
                                      edge / std::abs(x.det);
    const double minBary = std::min({x.u, x.v, 1.0 - x.u - x.v});
    const bool nearBorder = std::abs(minBary) <= band;
    const bool tNearWindow = x.t >= ray.tmin - tSlack && x.t <= ray.tmax + tSlack;
    const bool tNearLimit = std::abs(x.t - ray.tmin) <= tSlack || std::abs(x.t - ray.tmax) <= tSlack;
    return (nearBorder && tNearWindow) || (minBary >= -band && tNearLimit);
}

// Rounding-error bound of a single-precision ray/triangle distance for triangle `id` (Higham-style, as in
// tests/gl/intersect_twin_test.cpp): t = (e2 . (s x e1)) / (e1 . (d x e2)); each dot/cross product of float
// inputs carries a relative error of a few units of 2^-24 of the magnitudes involved, so
//   |dt| <~ k 2^-24 (|s||e1||e2| + |t||e1||e2||d|) / |det|.
// Long thin triangles (small |det| against |e1||e2|, common in the plant's pipes) amplify it far beyond a
// fixed relative tolerance; two correct float implementations (ours, Embree's) may differ by up to this much.
double distanceErrorBound(const Scene& scene, const Ray& ray, uint32_t id, double t) {
    if (id >= scene.triangles.size()) return 0.0;
    const glm::uvec3 tri = scene.triangles[id];
    const glm::dvec3 v0 = scene.positions[tri.x], v1 = scene.positions[tri.y], v2 = scene.positions[tri.z];
    const glm::dvec3 d = ray.direction;
    const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0;
    const double det = std::abs(glm::dot(e1, glm::cross(d, e2)));
    if (det == 0.0) return std::numeric_limits<double>::infinity();
    const double s = glm::length(glm::dvec3(ray.origin) - v0);
    const double edges = glm::length(e1) * glm::length(e2);
    return kUnitsOfRoundoff * std::ldexp(1.0, -24) * (s * edges + std::abs(t) * edges * glm::length(d)) / det;
}

} // namespace

ExactIntersection intersectInDouble(const Scene& scene, const Ray& ray, uint32_t id) {
    ExactIntersection x;
    if (id >= scene.triangles.size()) return x;
    const glm::uvec3 tri = scene.triangles[id];
    const glm::dvec3 v0 = scene.positions[tri.x], v1 = scene.positions[tri.y], v2 = scene.positions[tri.z];
    const glm::dvec3 d = ray.direction;
    const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0;
    const glm::dvec3 p = glm::cross(d, e2);
    x.det = glm::dot(e1, p);
    if (x.det == 0.0) return x;
    const glm::dvec3 s = glm::dvec3(ray.origin) - v0;
    const glm::dvec3 q = glm::cross(s, e1);
    x.u = glm::dot(s, p) / x.det;
    x.v = glm::dot(d, q) / x.det;
    x.t = glm::dot(e2, q) / x.det;
    return x;
}

HitComparison compareHitsExactly(std::span<const Ray> rays, std::span<const Hit> a, std::span<const Hit> b,
                                 bool anyHit, std::vector<size_t>* differing) {
    HitComparison result;
    result.rays = rays.size();
    for (size_t i = 0; i < rays.size(); ++i) {
        result.activeRays += rays[i].tmax > rays[i].tmin;
        result.hitsA += a[i].hit();
        result.hitsB += b[i].hit();
        const bool differs = anyHit ? a[i].hit() != b[i].hit()
                                    : a[i].triangleId != b[i].triangleId || std::memcmp(&a[i].t, &b[i].t, sizeof(float)) != 0;
        result.differing += differs;
        if (differs && differing) differing->push_back(i);
    }
    return result;
}

void HitComparison::add(const HitComparison& o) {
    rays += o.rays;
    activeRays += o.activeRays;
    hitsA += o.hitsA;
    hitsB += o.hitsB;
    ties += o.ties;
    edgeCases += o.edgeCases;
    differing += o.differing;
    maxRelativeTError = std::max(maxRelativeTError, o.maxRelativeTError);
}

HitComparison compareHits(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> a,
                          std::span<const Hit> b, bool anyHit, const HitTolerance& tol,
                          std::vector<size_t>* differingPixels) {
    HitComparison result;
    auto differ = [&](size_t pixel) {
        ++result.differing;
        if (differingPixels) differingPixels->push_back(pixel);
    };
    result.rays = rays.size();
    for (size_t i = 0; i < rays.size(); ++i) {
        const Ray& ray = rays[i];
        const Hit& ha = a[i];
        const Hit& hb = b[i];
        if (!(ray.tmax > ray.tmin)) {
            if (ha.hit() || hb.hit()) differ(i); // inactive rays must report misses
            continue;
        }
        ++result.activeRays;
        result.hitsA += ha.hit();
        result.hitsB += hb.hit();
        if (!ha.hit() && !hb.hit()) continue;
        const float tSlack = tol.relativeT * std::max(std::abs(ray.tmax) < 1e30f ? ray.tmax : 0.0f, 1.0f) + tol.absoluteT;
        if (ha.hit() && hb.hit()) {
            if (anyHit) continue;
            const double allowed =
                tol.relativeT * std::max(ha.t, hb.t) + tol.absoluteT +
                std::max(distanceErrorBound(scene, ray, ha.triangleId, ha.t), distanceErrorBound(scene, ray, hb.triangleId, hb.t));
            const float error = std::abs(ha.t - hb.t);
            if (ha.triangleId == hb.triangleId) {
                result.maxRelativeTError = std::max(result.maxRelativeTError, double(error) / std::max(ha.t, 1e-30f));
                if (error <= allowed) continue;
            } else if (error <= allowed) {
                ++result.ties;
                continue;
            }
            // Different surfaces at different distances: the nearer one was missed by the other tracer.
            const Hit& nearer = ha.t < hb.t ? ha : hb;
            if (meetsTriangleNearEdge(scene, ray, nearer.triangleId, tol.barycentricEpsilon, tSlack)) {
                ++result.edgeCases;
            } else {
                differ(i);
            }
            continue;
        }
        // One hit, one miss.
        const Hit& only = ha.hit() ? ha : hb;
        if (meetsTriangleNearEdge(scene, ray, only.triangleId, tol.barycentricEpsilon, tSlack)) {
            ++result.edgeCases;
        } else {
            differ(i);
        }
    }
    return result;
}

} // namespace chcrt
