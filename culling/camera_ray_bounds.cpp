#include "culling/camera_ray_bounds.h"

#include "culling/interval.h"
#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/culling_layout.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace chcrt {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Widening for the shader's float arithmetic (ndc, the unnormalised direction, normalize: a few ulps each): far
// above it, and far below what the grid's padding adds anyway.
constexpr double kDirectionRounding = 1e-5;
constexpr double kRelativeRounding = 1e-4; // for distances: the slab test's divisions and the points' products
constexpr int kMaxPoints = CHCRT_CULLING_BOUNDS_MAX_PIECES + 1; // a piece's end points p_0 .. p_P

// Rounded outwards by kRelativeRounding of each end's magnitude.
Interval widened(Interval a) {
    return {a.lo - std::fabs(a.lo) * kRelativeRounding, a.hi + std::fabs(a.hi) * kRelativeRounding};
}

// The smallest |F + aR + bU| over the rectangle [a0, a1] × [b0, b1]: the squared length is a convex quadratic, so
// its minimum is the unconstrained one where that lies inside, else on an edge (each a convex parabola).
double smallestLength(const glm::dvec3& f, const glm::dvec3& r, const glm::dvec3& u, double a0, double a1, double b0,
                      double b1) {
    const auto length = [&](double a, double b) { return glm::length(f + a * r + b * u); };
    const double rr = glm::dot(r, r), uu = glm::dot(u, u), ru = glm::dot(r, u);
    double best = kInfinity;
    const double det = rr * uu - ru * ru;
    if (det > 0.0) {
        const double a = (-glm::dot(r, f) * uu + glm::dot(u, f) * ru) / det;
        const double b = (-glm::dot(u, f) * rr + glm::dot(r, f) * ru) / det;
        if (a >= a0 && a <= a1 && b >= b0 && b <= b1) best = length(a, b);
    }
    for (double a : {a0, a1}) { // edges of constant a: minimise over b
        const double b = uu > 0.0 ? std::clamp(-glm::dot(u, f + a * r) / uu, b0, b1) : b0;
        best = std::min(best, length(a, b));
    }
    for (double b : {b0, b1}) {
        const double a = rr > 0.0 ? std::clamp(-glm::dot(r, f + b * u) / rr, a0, a1) : a0;
        best = std::min(best, length(a, b));
    }
    return best;
}

// Where a ray with direction component d in [lo, hi] meets the slab [c0, c1] (the slab's bounds minus the origin):
// the intervals of its entry and exit distances, over the rays that meet it (the others cannot hit anything).
// Mirrors intersectRayAabb (shaders/shared/intersect.h), where a zero component meets the slab at ±infinity.
void slabInterval(double lo, double hi, double c0, double c1, Interval& entry, Interval& exit) {
    if (lo > 0.0 || hi < 0.0) { // one sign: 1/d in [1/hi, 1/lo], monotone
        const Interval inverse{1.0 / hi, 1.0 / lo};
        const Interval a = times({c0, c0}, inverse), b = times({c1, c1}, inverse);
        // d > 0: entry c0/d, exit c1/d; d < 0: the other way round.
        entry = lo > 0.0 ? a : b;
        exit = lo > 0.0 ? b : a;
        return;
    }
    if (c0 <= 0.0 && c1 >= 0.0) { // the origin inside the slab: entered behind it, left ahead
        entry = {-kInfinity, 0.0};
        const double viaTop = hi > 0.0 ? c1 / hi : kInfinity, viaBottom = lo < 0.0 ? c0 / lo : kInfinity;
        exit = {std::min(viaTop, viaBottom), kInfinity};
        return;
    }
    // Outside the slab, directions of both signs: only those towards it meet it, the nearer the more parallel.
    if (c0 > 0.0) {
        entry = {hi > 0.0 ? c0 / hi : kInfinity, kInfinity};
        exit = {hi > 0.0 ? c1 / hi : kInfinity, kInfinity};
    } else {
        entry = {lo < 0.0 ? c1 / lo : kInfinity, kInfinity};
        exit = {lo < 0.0 ? c0 / lo : kInfinity, kInfinity};
    }
}

// Distances from `eye` to the nearest point and to the farthest corner of the box.
Interval boxDistances(const glm::dvec3& eye, const glm::dvec3& lower, const glm::dvec3& upper) {
    const glm::dvec3 gap = glm::max(glm::dvec3(0.0), glm::max(lower - eye, eye - upper));
    const glm::dvec3 far = glm::max(glm::abs(lower - eye), glm::abs(upper - eye));
    return {glm::length(gap), glm::length(far)};
}

// The segment of a ray that can hit, along a parameter m of the ray (the distance t, or the displacement along a
// dominant axis): from m0 = max(0, entry) to m1 = exit of the scene's box, given the intervals of the slab entries
// and exits (over the cell's rays) and the largest m any point of the box can have. Empty (lo > hi) when no ray meets
// the box.
struct Segment {
    Interval m0, m1;
};
Segment segmentOf(Interval entry, Interval exit, double nearest, double farthest) {
    entry = widened(entry);
    exit = widened(exit);
    const Interval m0{std::max({0.0, entry.lo, nearest}), std::min(std::max(0.0, entry.hi), farthest)};
    Segment s{m0, {std::max(exit.lo, m0.lo), std::min(exit.hi, farthest)}};
    if (s.m1.lo > s.m1.hi) s.m1.lo = s.m1.hi;
    return s;
}

// The segment of rays o + dir·m with each component of dir in [lo, hi] through the scene's box [boxLo, boxHi], m no
// nearer than `nearest` and no farther than `farthest`: the slab intervals of the three axes combined.
Segment boxSegment(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& eye, const glm::dvec3& boxLo,
                   const glm::dvec3& boxHi, double nearest, double farthest) {
    Interval entry{-kInfinity, -kInfinity}, exit{kInfinity, kInfinity};
    for (int i = 0; i < 3; ++i) {
        Interval axisEntry{}, axisExit{};
        slabInterval(lo[i], hi[i], boxLo[i] - eye[i], boxHi[i] - eye[i], axisEntry, axisExit);
        entry = {std::max(entry.lo, axisEntry.lo), std::max(entry.hi, axisEntry.hi)};
        exit = {std::min(exit.lo, axisExit.lo), std::min(exit.hi, axisExit.hi)};
    }
    return segmentOf(entry, exit, nearest, farthest);
}

// m_j = m0 + (m1 - m0) j / P: nonnegative weights of m0 and m1.
Interval piecePoint(const Segment& s, int j, int pieces) {
    const double w = double(j) / double(pieces);
    const double lo = (1.0 - w) * s.m0.lo + w * s.m1.lo;
    return {lo, std::max(lo, (1.0 - w) * s.m0.hi + w * s.m1.hi)};
}

using PointBoxes = std::array<glm::dvec3, kMaxPoints>;

// Narrows the boxes of the pieces' end points p_j = o + dir·m_j (j = 0 .. pieces) to those the intervals of dir and of
// the segment allow.
void narrowPoints(const glm::dvec3& lo, const glm::dvec3& hi, const Segment& segment, const glm::dvec3& eye,
                  int pieces, PointBoxes& pLo, PointBoxes& pHi) {
    for (int j = 0; j <= pieces; ++j) {
        const Interval m = piecePoint(segment, j, pieces);
        for (int i = 0; i < 3; ++i) {
            const Interval p = times({lo[i], hi[i]}, m);
            pLo[size_t(j)][i] = std::max(pLo[size_t(j)][i], eye[i] + p.lo);
            pHi[size_t(j)][i] = std::min(pHi[size_t(j)][i], eye[i] + p.hi);
        }
    }
}

} // namespace

std::vector<glm::vec4> cameraRayBounds(const PrimaryRayBasis& basis, int cellSize, int pieces, glm::vec3 sceneMin,
                                       glm::vec3 sceneMax) {
    const int width = basis.width, height = basis.height;
    const int cellsX = (width + cellSize - 1) / cellSize, cellsY = (height + cellSize - 1) / cellSize;
    const size_t stride = size_t(CHCRT_CULLING_BOUNDS_STRIDE(pieces));
    const int points = pieces + 2; // the origins, then the pieces' end points p_0 .. p_P
    std::vector<glm::vec4> out(size_t(cellsX) * size_t(cellsY) * stride, glm::vec4(0.0f));
    const glm::dvec3 eye(basis.eye), f(basis.forward), r(basis.right), u(basis.up);
    const glm::dvec3 boxLo(sceneMin), boxHi(sceneMax);
    const Interval distances = boxDistances(eye, boxLo, boxHi);
    const double nearest = distances.lo * (1.0 - kRelativeRounding), farthest = distances.hi * (1.0 + kRelativeRounding);
    const auto finite = [](const glm::dvec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    const bool finiteCamera = finite(eye) && finite(f) && finite(r) && finite(u) && finite(boxLo) && finite(boxHi);
    const auto ndc = [](int pixel, int size) { return (double(pixel) + 0.5) / double(size) * 2.0 - 1.0; };
    for (int cy = 0; cy < cellsY; ++cy) {
        for (int cx = 0; cx < cellsX; ++cx) {
            glm::vec4* cell = &out[(size_t(cy) * size_t(cellsX) + size_t(cx)) * stride];
            cell[0] = glm::vec4(float(CHCRT_CULLING_CELL_UNBOUNDED), 0.0f, 0.0f, 0.0f);
            if (!finiteCamera) continue;
            // The cell's pixel centres span [a0, a1] × [b0, b1] in ndc; the unnormalised direction v is affine in
            // them, so its components are extreme at the rectangle's corners and its length largest at one.
            const double a0 = ndc(cx * cellSize, width), a1 = ndc(std::min((cx + 1) * cellSize, width) - 1, width);
            const double b0 = ndc(cy * cellSize, height), b1 = ndc(std::min((cy + 1) * cellSize, height) - 1, height);
            std::array<glm::dvec3, 4> corners;
            glm::dvec3 vLo(kInfinity), vHi(-kInfinity);
            double longest = 0.0;
            for (int c = 0; c < 4; ++c) {
                corners[size_t(c)] = f + (c & 1 ? a1 : a0) * r + (c & 2 ? b1 : b0) * u;
                vLo = glm::min(vLo, corners[size_t(c)]);
                vHi = glm::max(vHi, corners[size_t(c)]);
                longest = std::max(longest, glm::length(corners[size_t(c)]));
            }
            const double shortest = smallestLength(f, r, u, a0, a1, b0, b1);
            if (!(shortest > 0.0) || !std::isfinite(longest)) continue;

            // (1) Along the distance t: intervals of the unit direction d = v / |v| and of t.
            glm::dvec3 dLo, dHi;
            for (int i = 0; i < 3; ++i) {
                dLo[i] = vLo[i] / (vLo[i] >= 0.0 ? longest : shortest) - kDirectionRounding;
                dHi[i] = vHi[i] / (vHi[i] >= 0.0 ? shortest : longest) + kDirectionRounding;
            }
            // A segment that can hit runs inside the scene's box, so its points lie between the box's nearest point
            // and its farthest corner (directions of length ~1).
            Segment t = boxSegment(dLo, dHi, eye, boxLo, boxHi, nearest, farthest);

            // The pieces' end points p_j from (1): o + d s_j, within the scene's box, which holds every point of a
            // segment that can hit (the grid's pad covers the rounding of the shader's points).
            PointBoxes pLo, pHi;
            pLo.fill(boxLo);
            pHi.fill(boxHi);
            narrowPoints(dLo, dHi, t, eye, pieces, pLo, pHi);
            // (2) Along the displacement m = sigma (p_k - o_k) on each axis k whose component has one sign over the
            // cell: the point is o + w m with w = sigma v / v_k, a ratio of affine functions of the pixel, extreme
            // at the corners — exact, where (1) pairs the extremes of d with those of t. Where axis k bounds the
            // segments (a view down onto the scene's top, out through a side) the points then lie on planes. Each
            // axis's boxes hold the points, so their intersection does.
            for (int k = 0; k < 3; ++k) {
                if (!(vLo[k] > 0.0 || vHi[k] < 0.0)) continue;
                const double sigma = vLo[k] > 0.0 ? 1.0 : -1.0;
                glm::dvec3 wLo(kInfinity), wHi(-kInfinity);
                for (const glm::dvec3& v : corners) {
                    wLo = glm::min(wLo, sigma * v / v[k]);
                    wHi = glm::max(wHi, sigma * v / v[k]);
                }
                for (int i = 0; i < 3; ++i) {
                    if (i == k) {
                        wLo[i] = wHi[i] = sigma;
                    } else { // the shader's float directions: a few ulps off the exact ratio
                        wLo[i] -= kDirectionRounding * (1.0 + std::fabs(wLo[i]));
                        wHi[i] += kDirectionRounding * (1.0 + std::fabs(wHi[i]));
                    }
                }
                const Segment m = boxSegment(wLo, wHi, eye, boxLo, boxHi, 0.0, farthest); // |p_k - o_k| <= |p - o|
                if (!(m.m0.lo <= m.m1.hi)) { // no ray meets the scene's box
                    t.m0.lo = kInfinity;
                    break;
                }
                narrowPoints(wLo, wHi, m, eye, pieces, pLo, pHi);
                // The same segment in t = m / |d_k| bounds the cell's segment range (the frustum test's).
                const double dkLo = std::min(std::fabs(dLo[k]), std::fabs(dHi[k]));
                const double dkHi = std::max(std::fabs(dLo[k]), std::fabs(dHi[k]));
                if ((dLo[k] > 0.0 || dHi[k] < 0.0) && dkLo > 0.0) {
                    t.m0.lo = std::max(t.m0.lo, m.m0.lo / dkHi * (1.0 - kRelativeRounding));
                    t.m1.hi = std::min(t.m1.hi, m.m1.hi / dkLo * (1.0 + kRelativeRounding));
                }
            }
            if (!(t.m0.lo <= t.m1.hi)) { // no ray meets the scene's box
                cell[0].x = float(CHCRT_CULLING_CELL_EMPTY);
                continue;
            }
            const double reach = std::max(t.m0.hi, t.m1.hi);
            const double largestComponent = std::max({std::fabs(dLo.x), std::fabs(dLo.y), std::fabs(dLo.z),
                                                      std::fabs(dHi.x), std::fabs(dHi.y), std::fabs(dHi.z)});
            const double extent = std::max({std::fabs(eye.x), std::fabs(eye.y), std::fabs(eye.z)}) +
                                  largestComponent * reach;
            // Boxes apart from the scene's or from each other by more than rounding: no ray of the cell meets the box.
            const double tolerance = extent * kRelativeRounding;
            bool empty = false;
            cell[1] = glm::vec4(basis.eye, 0.0f); // the origins: the eye
            cell[2] = glm::vec4(basis.eye, 0.0f);
            for (int j = 0; j <= pieces; ++j) {
                for (int i = 0; i < 3; ++i) empty = empty || pLo[size_t(j)][i] > pHi[size_t(j)][i] + tolerance;
                cell[1 + 2 * (j + 1)] = glm::vec4(glm::vec3(glm::min(pLo[size_t(j)], pHi[size_t(j)])), 0.0f);
                cell[2 + 2 * (j + 1)] = glm::vec4(glm::vec3(glm::max(pLo[size_t(j)], pHi[size_t(j)])), 0.0f);
            }
            if (empty) {
                cell[0].x = float(CHCRT_CULLING_CELL_EMPTY);
                continue;
            }
            cell[0] = glm::vec4(float(CHCRT_CULLING_CELL_BOUNDED), float(extent), float(1.0 + kDirectionRounding), 0.0f);
            cell[1 + 2 * points] = glm::vec4(glm::vec3(dLo), float(t.m0.lo));
            cell[2 + 2 * points] = glm::vec4(glm::vec3(dHi), float(t.m1.hi));
        }
    }
    return out;
}

} // namespace chcrt
