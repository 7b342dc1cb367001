#include "culling/hemisphere_ray_bounds.h"

#include "culling/interval.h"
#include "shaders/shared/culling_layout.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/gtc/constants.hpp>

namespace chcrt {
namespace {

constexpr double kPi = glm::pi<double>();
// Widening of the sample's cosine and sine for the shaders' sin and cos (their error is far smaller, also for the
// arguments up to 4π the rotation reaches) and of the directions for the normalisation and the products.
constexpr double kTrigRounding = 1e-3;
constexpr double kDirectionRounding = 2e-3;
constexpr double kNormalLengthTolerance = 1e-3;
constexpr int kMaxPoints = CHCRT_CULLING_BOUNDS_MAX_PIECES + 1; // a piece's end points p_0 .. p_P

// cos over the angles [a, b] (b >= a): the ends, and ±1 where a multiple of π lies inside.
Interval cosineOver(double a, double b) {
    if (b - a >= 2.0 * kPi) return {-1.0, 1.0};
    Interval c{std::min(std::cos(a), std::cos(b)), std::max(std::cos(a), std::cos(b))};
    for (double k = std::ceil(a / kPi); k * kPi <= b; k += 1.0) {
        const bool even = std::fmod(std::fabs(k), 2.0) == 0.0;
        if (even) c.hi = 1.0;
        else c.lo = -1.0;
    }
    return {c.lo - kTrigRounding, c.hi + kTrigRounding};
}

} // namespace

std::vector<glm::vec4> hemisphereRayBounds(const std::vector<glm::vec4>& frames, int cellsX, int cellsY, int pieces,
                                           const HemisphereSample& set, glm::vec3 sceneMin, glm::vec3 sceneMax) {
    const size_t stride = size_t(CHCRT_CULLING_BOUNDS_STRIDE(pieces));
    const size_t cells = size_t(cellsX) * size_t(cellsY);
    const int points = pieces + 2; // the origins, then the pieces' end points p_0 .. p_P
    std::vector<glm::vec4> out(cells * stride, glm::vec4(0.0f));
    // The sample in tangent space (cosineHemisphere, render/sampling.glsl): l = (r cos φ, r sin φ, z) with φ over
    // 2π u.y plus the pixel's rotation.
    const double u = double(set.sample.x), r = std::sqrt(std::max(0.0, u)), z = std::sqrt(std::max(0.0, 1.0 - u));
    // φ = 2π u.y + rotation, the rotation between 0 and maxRotation (a random fraction of it per pixel).
    const double rotation = std::isfinite(set.maxRotation) ? double(set.maxRotation) : 2.0 * kPi;
    const double phi0 = 2.0 * kPi * double(set.sample.y) + std::min(0.0, rotation), width = std::fabs(rotation);
    const Interval cosine = cosineOver(phi0, phi0 + width);
    const Interval sine = cosineOver(phi0 - 0.5 * kPi, phi0 - 0.5 * kPi + width); // sin φ = cos(φ - π/2)
    const Interval lx = times({r, r}, cosine), ly = times({r, r}, sine);
    const Interval lz{z * (1.0 - kTrigRounding), z * (1.0 + kTrigRounding)};
    const double length = double(set.length);
    const bool usable = std::isfinite(length) && length >= 0.0 && std::isfinite(u) && std::isfinite(set.sample.y);
    const glm::dvec3 sceneLo(sceneMin), sceneHi(sceneMax);
    for (size_t i = 0; i < cells; ++i) {
        glm::vec4* cell = &out[i * stride];
        cell[0].x = float(CHCRT_CULLING_CELL_UNBOUNDED);
        if ((i + 1) * CHCRT_CULLING_FRAMES_STRIDE > frames.size()) continue; // no frames known: nothing assumed
        const glm::vec4* in = &frames[i * CHCRT_CULLING_FRAMES_STRIDE];
        const float state = in[0].x;
        if (state == float(CHCRT_CULLING_CELL_EMPTY)) {
            cell[0].x = float(CHCRT_CULLING_CELL_EMPTY);
            continue;
        }
        if (state != float(CHCRT_CULLING_CELL_BOUNDED) || !usable) continue;
        if (!(std::fabs(double(in[0].y) - 1.0) <= kNormalLengthTolerance) ||
            !(std::fabs(double(in[0].z) - 1.0) <= kNormalLengthTolerance)) {
            continue;
        }
        // Per class of normals: the directions' box from the frames' boxes, then the pieces' end points
        // p_j = o + d s_j, s_j = j length / P >= 0 (the origins' box plus s_j times the directions' box, clamped to
        // the scene's box: clamping both ends of a piece keeps the part of it inside the box); the cell's boxes are
        // the unions over its classes.
        constexpr double kBig = 3.0e38;
        glm::dvec3 originLo(kBig), originHi(-kBig), dLo(kBig), dHi(-kBig);
        std::array<glm::dvec3, kMaxPoints> pLo, pHi;
        pLo.fill(glm::dvec3(kBig));
        pHi.fill(glm::dvec3(-kBig));
        bool finite = true;
        for (int c = 0; c < CHCRT_CULLING_FRAME_CLASSES; ++c) {
            const glm::vec4* box = &in[1 + 2 * CHCRT_CULLING_FRAME_BOXES * c]; // origins, n, T, B: lower, upper each
            if (box[0].w != 1.0f) continue; // no point of this class
            const glm::dvec3 oLo(box[0]), oHi(box[1]);
            glm::dvec3 cLo, cHi;
            for (int a = 0; a < 3; ++a) {
                const Interval n{box[2][a], box[3][a]}, t{box[4][a], box[5][a]}, b{box[6][a], box[7][a]};
                const Interval x = times(lx, t), y = times(ly, b), w = times(lz, n);
                // |v| is 1 within the normals' tolerance, so normalize(v) moves each component by at most that much.
                cLo[a] = std::max(-1.0, x.lo + y.lo + w.lo) - kDirectionRounding;
                cHi[a] = std::min(1.0, x.hi + y.hi + w.hi) + kDirectionRounding;
                finite = finite && std::isfinite(oLo[a]) && std::isfinite(oHi[a]) && oLo[a] <= oHi[a] &&
                         std::isfinite(cLo[a]) && std::isfinite(cHi[a]) && cLo[a] <= cHi[a];
            }
            originLo = glm::min(originLo, oLo);
            originHi = glm::max(originHi, oHi);
            dLo = glm::min(dLo, cLo);
            dHi = glm::max(dHi, cHi);
            for (int j = 0; j <= pieces; ++j) {
                const double s = length * double(j) / double(pieces);
                pLo[size_t(j)] = glm::min(pLo[size_t(j)], glm::clamp(oLo + s * cLo, sceneLo, sceneHi));
                pHi[size_t(j)] = glm::max(pHi[size_t(j)], glm::clamp(oHi + s * cHi, sceneLo, sceneHi));
            }
        }
        if (!finite || !(originLo.x <= originHi.x)) continue; // no class with a point: a malformed cell
        cell[1] = glm::vec4(glm::vec3(originLo), 0.0f);
        cell[2] = glm::vec4(glm::vec3(originHi), 0.0f);
        for (int j = 0; j <= pieces; ++j) {
            cell[1 + 2 * (j + 1)] = glm::vec4(glm::vec3(pLo[size_t(j)]), 0.0f);
            cell[2 + 2 * (j + 1)] = glm::vec4(glm::vec3(pHi[size_t(j)]), 0.0f);
        }
        const double origin = std::max({std::fabs(originLo.x), std::fabs(originLo.y), std::fabs(originLo.z),
                                        std::fabs(originHi.x), std::fabs(originHi.y), std::fabs(originHi.z)});
        const double direction = std::max({std::fabs(dLo.x), std::fabs(dLo.y), std::fabs(dLo.z), std::fabs(dHi.x),
                                           std::fabs(dHi.y), std::fabs(dHi.z)});
        cell[0] = glm::vec4(float(CHCRT_CULLING_CELL_BOUNDED), float(origin + direction * length),
                            float(1.0 + kDirectionRounding), 0.0f);
        cell[1 + 2 * points] = glm::vec4(glm::vec3(dLo), 0.0f);
        cell[2 + 2 * points] = glm::vec4(glm::vec3(dHi), float(length));
    }
    return out;
}

} // namespace chcrt
