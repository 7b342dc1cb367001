// Exact shaft overlap tests: separating axes over the moving box Box(s) = (1 - s) A + s B (see the header).
#include "linespace/shaft_geometry.h"

#include <algorithm>
#include <cmath>

namespace chcrt::ls {

namespace {

// The set of s in [0, 1] not yet excluded by any axis.
struct ParameterInterval {
    double lo = 0.0;
    double hi = 1.0;
    bool empty() const { return lo > hi; }
    // Keeps the s with alpha + beta * s <= gamma.
    void keepAtMost(double alpha, double beta, double gamma) {
        if (beta > 0.0) {
            hi = std::min(hi, (gamma - alpha) / beta);
        } else if (beta < 0.0) {
            lo = std::max(lo, (gamma - alpha) / beta);
        } else if (alpha > gamma) {
            lo = 1.0;
            hi = 0.0;
        }
    }
    // Keeps the s where the box's projection on `axis`, [c(s) - r(s), c(s) + r(s)], meets [pmin, pmax].
    void keepOverlapping(const ShaftVolume& shaft, const glm::dvec3& axis, double pmin, double pmax) {
        const glm::dvec3 absAxis = glm::abs(axis);
        const double cA = glm::dot(shaft.centerA, axis), cB = glm::dot(shaft.centerB, axis);
        const double rA = glm::dot(shaft.halfA, absAxis), rB = glm::dot(shaft.halfB, absAxis);
        // c(s) - r(s) <= pmax
        keepAtMost(cA - rA, (cB - cA) - (rB - rA), pmax);
        // c(s) + r(s) >= pmin  <=>  -(c(s) + r(s)) <= -pmin
        keepAtMost(-(cA + rA), -(cB - cA) - (rB - rA), -pmin);
    }
};

} // namespace

BoxD patchRegion(const Aabb& box, uint32_t n, const PatchRect& rect, double dilation) {
    const int axis = static_cast<int>(rect.face >> 1u);
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const glm::dvec3 lower(box.lower), upper(box.upper), extent = upper - lower;
    BoxD region;
    const double plane = (rect.face & 1u) != 0u ? upper[axis] : lower[axis];
    region.lower[axis] = region.upper[axis] = plane;
    region.lower[ua] = lower[ua] + extent[ua] * rect.u0 / n;
    region.upper[ua] = rect.u1 == n ? upper[ua] : lower[ua] + extent[ua] * rect.u1 / n;
    region.lower[va] = lower[va] + extent[va] * rect.v0 / n;
    region.upper[va] = rect.v1 == n ? upper[va] : lower[va] + extent[va] * rect.v1 / n;
    region.lower -= glm::dvec3(dilation);
    region.upper += glm::dvec3(dilation);
    return region;
}

glm::vec3 patchCentroid(const Aabb& box, uint32_t n, uint32_t face, uint32_t pu, uint32_t pv) {
    const int axis = static_cast<int>(face >> 1u);
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const glm::vec3 extent = box.upper - box.lower;
    glm::vec3 p;
    p[axis] = (face & 1u) != 0u ? box.upper[axis] : box.lower[axis];
    p[ua] = box.lower[ua] + extent[ua] * ((static_cast<float>(pu) + 0.5f) / static_cast<float>(n));
    p[va] = box.lower[va] + extent[va] * ((static_cast<float>(pv) + 0.5f) / static_cast<float>(n));
    return p;
}

ShaftVolume::ShaftVolume(const BoxD& a, const BoxD& b)
    : centerA(0.5 * (a.lower + a.upper)), halfA(0.5 * (a.upper - a.lower)), centerB(0.5 * (b.lower + b.upper)),
      halfB(0.5 * (b.upper - b.lower)) {}

bool shaftOverlapsTriangle(const ShaftVolume& shaft, const glm::vec3& v0f, const glm::vec3& v1f,
                           const glm::vec3& v2f) {
    const glm::dvec3 v[3] = {glm::dvec3(v0f), glm::dvec3(v1f), glm::dvec3(v2f)};
    ParameterInterval interval;
    auto testAxis = [&](const glm::dvec3& axis) {
        const double p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
        interval.keepOverlapping(shaft, axis, std::min({p0, p1, p2}), std::max({p0, p1, p2}));
        return !interval.empty();
    };
    // The box face normals first: they reject most triangles (a bounding-box test over s).
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 axis(0.0);
        axis[a] = 1.0;
        if (!testAxis(axis)) {
            return false;
        }
    }
    const glm::dvec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
    if (!testAxis(glm::cross(edges[0], edges[1]))) {
        return false;
    }
    // Edge x box-axis cross products; a zero axis (edge parallel to the box axis) keeps every s.
    for (const glm::dvec3& edge : edges) {
        for (int a = 0; a < 3; ++a) {
            glm::dvec3 unit(0.0);
            unit[a] = 1.0;
            if (!testAxis(glm::cross(edge, unit))) {
                return false;
            }
        }
    }
    return true;
}

bool shaftOverlapsBox(const ShaftVolume& shaft, const glm::dvec3& lower, const glm::dvec3& upper) {
    ParameterInterval interval;
    for (int a = 0; a < 3 && !interval.empty(); ++a) {
        glm::dvec3 axis(0.0);
        axis[a] = 1.0;
        interval.keepOverlapping(shaft, axis, lower[a], upper[a]);
    }
    return !interval.empty();
}

double shaftDilationForScene(const Aabb& sceneBounds) {
    const glm::vec3 magnitude = glm::max(glm::abs(sceneBounds.lower), glm::abs(sceneBounds.upper));
    const double largest = std::max({magnitude.x, magnitude.y, magnitude.z});
    return std::ldexp(largest + static_cast<double>(sceneBounds.diagonal()), -16);
}

} // namespace chcrt::ls
