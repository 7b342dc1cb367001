#pragma once
// Queries restricted to the subtree of one BVH node, used to build that node's Line Space: "does anything in
// this shaft volume exist" (exact, pruned by the exact shaft/box test on the subtree's boxes) and the closest
// hit of a segment (the candidate's centroid ray). Scalar and recursive-free, like renderer/bvh/cpu_tracer.
#include "linespace/shaft_geometry.h"
#include "renderer/bvh/bvh.h"

#include <cstdint>

namespace chcrt::ls {

// True when a triangle of node's subtree intersects the shaft volume.
bool subtreeOverlapsShaft(const Bvh& bvh, uint32_t node, const ShaftVolume& shaft);

// Closest triangle of node's subtree hit by origin + t * direction, tmin <= t <= tmax (intersect.h's
// Moeller-Trumbore, ties to the lower original id as every tracer here). Returns the triangle's index in
// bvh.triangles (BVH order), or kNoTriangle; `tHit` receives its t.
inline constexpr uint32_t kNoTriangle = 0xFFFFFFFFu;
uint32_t subtreeClosestHit(const Bvh& bvh, uint32_t node, const glm::vec3& origin, const glm::vec3& direction,
                           float tmin, float tmax, float* tHit = nullptr);

// Triangles of node's subtree: a BVH built by in-place partitioning stores them contiguously.
struct TriangleRange {
    uint32_t first = 0;
    uint32_t count = 0;
};
// Per node, its subtree's triangle range. Throws std::logic_error if a subtree is not contiguous.
std::vector<TriangleRange> subtreeTriangleRanges(const Bvh& bvh);

} // namespace chcrt::ls
