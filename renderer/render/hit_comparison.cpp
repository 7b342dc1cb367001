#include "renderer/render/hit_comparison.h"

#include <algorithm>
#include <cmath>

namespace chcrt {
namespace {

// Does the ray meet triangle `id` (within [tmin - slack, tmax + slack]) only near its border? Uses the
// Möller-Trumbore barycentrics with an epsilon band: inside the band on the outside or inside of an edge.
bool meetsTriangleNearEdge(const Scene& scene, const Ray& ray, uint32_t id, float epsilon, float tSlack) {
    if (id >= scene.triangles.size()) return false;
    const glm::uvec3 tri = scene.triangles[id];
    const glm::dvec3 v0 = scene.positions[tri.x], v1 = scene.positions[tri.y], v2 = scene.positions[tri.z];
    const glm::dvec3 o = ray.origin, d = ray.direction;
    const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0;
    const glm::dvec3 p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) return true; // parallel: any decision is a rounding decision
    const glm::dvec3 s = o - v0;
    const double u = glm::dot(s, p) / det;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(d, q) / det;
    const double t = glm::dot(e2, q) / det;
    const double w = 1.0 - u - v;
    const double minBary = std::min({u, v, w});
    const bool nearBorder = std::abs(minBary) <= epsilon;
    const bool tNearWindow = t >= ray.tmin - tSlack && t <= ray.tmax + tSlack;
    const bool tNearLimit = std::abs(t - ray.tmin) <= tSlack || std::abs(t - ray.tmax) <= tSlack;
    return (nearBorder && tNearWindow) || (minBary >= -epsilon && tNearLimit);
}

} // namespace

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
                          std::span<const Hit> b, bool anyHit, const HitTolerance& tol) {
    HitComparison result;
    result.rays = rays.size();
    for (size_t i = 0; i < rays.size(); ++i) {
        const Ray& ray = rays[i];
        const Hit& ha = a[i];
        const Hit& hb = b[i];
        if (!(ray.tmax > ray.tmin)) {
            if (ha.hit() || hb.hit()) ++result.differing; // inactive rays must report misses
            continue;
        }
        ++result.activeRays;
        result.hitsA += ha.hit();
        result.hitsB += hb.hit();
        if (!ha.hit() && !hb.hit()) continue;
        const float tSlack = tol.relativeT * std::max(std::abs(ray.tmax) < 1e30f ? ray.tmax : 0.0f, 1.0f) + tol.absoluteT;
        if (ha.hit() && hb.hit()) {
            if (anyHit) continue;
            const float allowed = tol.relativeT * std::max(ha.t, hb.t) + tol.absoluteT;
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
                ++result.differing;
            }
            continue;
        }
        // One hit, one miss.
        const Hit& only = ha.hit() ? ha : hb;
        if (meetsTriangleNearEdge(scene, ray, only.triangleId, tol.barycentricEpsilon, tSlack)) {
            ++result.edgeCases;
        } else {
            ++result.differing;
        }
    }
    return result;
}

} // namespace chcrt
