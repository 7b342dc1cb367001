#pragma once
// Axis-aligned bounding box used by scenes, the BVH builder and the tracers.
#include <glm/glm.hpp>

#include <algorithm>
#include <limits>

namespace chcrt {

struct Aabb {
    glm::vec3 lower{std::numeric_limits<float>::infinity()};
    glm::vec3 upper{-std::numeric_limits<float>::infinity()};

    bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
    void grow(const glm::vec3& p) {
        lower = glm::min(lower, p);
        upper = glm::max(upper, p);
    }
    void grow(const Aabb& b) {
        lower = glm::min(lower, b.lower);
        upper = glm::max(upper, b.upper);
    }
    glm::vec3 extent() const { return empty() ? glm::vec3(0.0f) : upper - lower; }
    glm::vec3 center() const { return 0.5f * (lower + upper); }
    // Surface area; 0 for an empty box (SAH cost weights).
    float area() const {
        const glm::vec3 e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    bool contains(const Aabb& b) const {
        return glm::all(glm::lessThanEqual(lower, b.lower)) && glm::all(glm::greaterThanEqual(upper, b.upper));
    }
    float diagonal() const { return glm::length(extent()); }
};

// Squared distance from `point` to the nearest point of the box [lower, upper]; 0 inside it. Orders subtrees near
// to far (CHC+RT scheduling, prefetch) and bounds a proxy's projected error (LOD).
inline float squaredDistanceToBox(const glm::vec3& point, const glm::vec3& lower, const glm::vec3& upper) {
    const glm::vec3 d = glm::clamp(point, lower, upper) - point;
    return glm::dot(d, d);
}

} // namespace chcrt
