#include "tests/linespace/linespace_test_util.h"

#include <algorithm>

namespace chcrt::test {

Scene makeScene(const TriangleList& triangles) {
    Scene scene;
    scene.name = "linespace-test";
    for (const auto& t : triangles) {
        const uint32_t base = static_cast<uint32_t>(scene.positions.size());
        glm::vec3 normal = glm::cross(t[1] - t[0], t[2] - t[0]);
        normal = glm::length(normal) > 0.0f ? glm::normalize(normal) : glm::vec3(0.0f, 1.0f, 0.0f);
        for (const glm::vec3& p : t) {
            scene.positions.push_back(p);
            scene.normals.push_back(normal);
        }
        scene.triangles.emplace_back(base, base + 1, base + 2);
        scene.triangleMaterials.push_back(0);
    }
    scene.materials.emplace_back();
    scene.stats.uniqueTriangles = scene.stats.instancedTriangles = triangles.size();
    scene.stats.meshCount = scene.stats.instanceCount = 1;
    return scene;
}

TriangleList randomSoup(uint32_t count, uint32_t seed) {
    Rng rng{seed * 7919ull + 17ull};
    TriangleList triangles;
    for (uint32_t i = 0; i < count; ++i) {
        const float size = i % 50 == 0 ? 0.8f : 0.08f;
        const glm::vec3 centre = rng.uniform3(-1.0f, 1.0f);
        triangles.push_back({centre + rng.uniform3(-size, size), centre + rng.uniform3(-size, size),
                             centre + rng.uniform3(-size, size)});
    }
    return triangles;
}

void appendBox(TriangleList& triangles, const glm::vec3& lo, const glm::vec3& hi) {
    const glm::vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z},
                            {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}};
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        triangles.push_back({c[q[0]], c[q[1]], c[q[2]]});
        triangles.push_back({c[q[0]], c[q[2]], c[q[3]]});
    }
}

bool hullMeetsBox(const ls::BoxD& a, const ls::BoxD& b, const glm::dvec3& glo, const glm::dvec3& ghi) {
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 3; ++k) {
        // lower(s) = a.lower + s (b.lower - a.lower) <= ghi ; upper(s) = a.upper + s (b.upper - a.upper) >= glo
        const double l0 = a.lower[k], l1 = b.lower[k] - a.lower[k];
        const double u0 = a.upper[k], u1 = b.upper[k] - a.upper[k];
        if (l1 == 0.0) {
            if (l0 > ghi[k]) {
                return false;
            }
        } else if (l1 > 0.0) {
            hi = std::min(hi, (ghi[k] - l0) / l1);
        } else {
            lo = std::max(lo, (ghi[k] - l0) / l1);
        }
        if (u1 == 0.0) {
            if (u0 < glo[k]) {
                return false;
            }
        } else if (u1 > 0.0) {
            lo = std::max(lo, (glo[k] - u0) / u1);
        } else {
            hi = std::min(hi, (glo[k] - u0) / u1);
        }
    }
    return lo <= hi;
}

} // namespace chcrt::test
