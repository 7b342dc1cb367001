#pragma once
// Shared pieces of the Line Space tests: a deterministic generator, small scenes with known geometry, and the
// brute-force oracles.
#include "linespace/shaft_geometry.h"
#include "renderer/bvh/bvh.h"
#include "renderer/scene/scene.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace chcrt::test {

// Small deterministic generator (std distributions differ between standard libraries).
struct Rng {
    uint64_t state;
    uint32_t next() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<uint32_t>(state >> 33);
    }
    float uniform(float lo, float hi) { return lo + (hi - lo) * static_cast<float>(next() >> 8) * 0x1p-24f; }
    glm::vec3 uniform3(float lo, float hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
    glm::vec3 uniform3(const glm::vec3& lo, const glm::vec3& hi) {
        return {uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z)};
    }
    uint32_t below(uint32_t n) { return next() % n; }
};

using TriangleList = std::vector<std::array<glm::vec3, 3>>;

// A valid scene over the triangles (flat normals, one material).
Scene makeScene(const TriangleList& triangles);

// Random small triangles in [-1, 1]^3 with a few large ones; different `seed`s give different soups.
TriangleList randomSoup(uint32_t count, uint32_t seed);

// The 12 triangles of an axis-aligned box surface.
void appendBox(TriangleList& triangles, const glm::vec3& lower, const glm::vec3& upper);

// Exact oracle for box geometry, written independently of shaft_geometry.cpp: the convex hull of patch boxes
// A and B meets box G iff some s in [0, 1] has (1 - s) A + s B overlapping G on all three axes; per axis the
// bounds are linear in s, so each axis allows an interval of s, computed here by solving the two inequalities.
bool hullMeetsBox(const ls::BoxD& a, const ls::BoxD& b, const glm::dvec3& glo, const glm::dvec3& ghi);

} // namespace chcrt::test
