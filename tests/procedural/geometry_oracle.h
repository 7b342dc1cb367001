#pragma once
// Brute-force-simple geometric queries over a Scene for the procedural tests: segment/triangle and
// ray/triangle intersection (Moller-Trumbore, no epsilon slack on the segment's ends), with a 2D uniform
// grid over x/z so that thousands of short path segments can be checked against 100k+ triangles quickly.
#include "renderer/scene/scene.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace chcrt::test {

// Distance t along `direction` to the triangle, if hit with t in [0, tMax].
inline std::optional<float> intersectTriangle(const glm::vec3& origin, const glm::vec3& direction, float tMax,
                                              const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 e1 = b - a, e2 = c - a;
    const glm::vec3 p = glm::cross(direction, e2);
    const float det = glm::dot(e1, p);
    if (std::fabs(det) < 1e-12f) return std::nullopt;
    const float inv = 1.0f / det;
    const glm::vec3 s = origin - a;
    const float u = glm::dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f) return std::nullopt;
    const glm::vec3 q = glm::cross(s, e1);
    const float v = glm::dot(direction, q) * inv;
    if (v < 0.0f || u + v > 1.0f) return std::nullopt;
    const float t = glm::dot(e2, q) * inv;
    if (t < 0.0f || t > tMax) return std::nullopt;
    return t;
}

class TriangleGrid {
public:
    explicit TriangleGrid(const Scene& scene) : scene_(scene) {
        const Aabb bounds = scene.bounds();
        lower_ = glm::vec2(bounds.lower.x, bounds.lower.z);
        const glm::vec2 extent(std::max(bounds.extent().x, 1e-3f), std::max(bounds.extent().z, 1e-3f));
        const float cells = std::max(1.0f, float(scene.triangles.size()) / 8.0f);
        cellSize_ = std::sqrt(extent.x * extent.y / cells);
        size_ = glm::ivec2(glm::max(glm::vec2(1.0f), glm::ceil(extent / cellSize_)));
        cells_.resize(size_t(size_.x) * size_t(size_.y));
        for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
            const glm::uvec3 tri = scene.triangles[t];
            const glm::vec3 a = scene.positions[tri.x], b = scene.positions[tri.y], c = scene.positions[tri.z];
            const glm::ivec2 lo = cell({std::min({a.x, b.x, c.x}), std::min({a.z, b.z, c.z})});
            const glm::ivec2 hi = cell({std::max({a.x, b.x, c.x}), std::max({a.z, b.z, c.z})});
            for (int z = lo.y; z <= hi.y; ++z)
                for (int x = lo.x; x <= hi.x; ++x) cells_[size_t(z) * size_.x + x].push_back(t);
        }
    }

    // True if the segment from p to q touches any triangle.
    bool segmentHits(const glm::vec3& p, const glm::vec3& q) const {
        const glm::ivec2 lo = cell({std::min(p.x, q.x), std::min(p.z, q.z)});
        const glm::ivec2 hi = cell({std::max(p.x, q.x), std::max(p.z, q.z)});
        for (int z = lo.y; z <= hi.y; ++z)
            for (int x = lo.x; x <= hi.x; ++x)
                for (uint32_t t : cells_[size_t(z) * size_.x + x])
                    if (hitsTriangle(p, q - p, 1.0f, t)) return true;
        return false;
    }

    // Nearest hit distance along a ray (direction normalised), brute force; infinity if none.
    float nearestHit(const glm::vec3& origin, const glm::vec3& direction) const {
        float nearest = std::numeric_limits<float>::infinity();
        for (uint32_t t = 0; t < scene_.triangles.size(); ++t)
            if (auto hit = hitsTriangle(origin, direction, nearest, t)) nearest = *hit;
        return nearest;
    }

private:
    std::optional<float> hitsTriangle(const glm::vec3& origin, const glm::vec3& direction, float tMax, uint32_t t) const {
        const glm::uvec3 tri = scene_.triangles[t];
        return intersectTriangle(origin, direction, tMax, scene_.positions[tri.x], scene_.positions[tri.y],
                                 scene_.positions[tri.z]);
    }
    glm::ivec2 cell(glm::vec2 p) const {
        const glm::ivec2 c = glm::ivec2(glm::floor((p - lower_) / cellSize_));
        return glm::clamp(c, glm::ivec2(0), size_ - 1);
    }

    const Scene& scene_;
    glm::vec2 lower_{0.0f};
    float cellSize_ = 1.0f;
    glm::ivec2 size_{1};
    std::vector<std::vector<uint32_t>> cells_;
};

} // namespace chcrt::test
