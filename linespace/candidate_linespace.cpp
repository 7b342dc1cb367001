#include "linespace/candidate_linespace.h"

#include "linespace/binary_linespace.h"
#include "linespace/shaft_geometry.h"
#include "linespace/shaft_index.h"
#include "linespace/subtree_query.h"
#include "shaders/shared/intersect.h"

#include <cmath>

namespace chcrt::ls {

void centroidRay(const Aabb& box, uint32_t n, uint32_t shaft, glm::vec3& origin, glm::vec3& direction) {
    const ShaftPatches p = decodeShaft(shaft, n, false);
    origin = patchCentroid(box, n, p.startFace, p.startPatch % n, p.startPatch / n);
    direction = patchCentroid(box, n, p.endFace, p.endPatch % n, p.endPatch / n) - origin;
}

void fillCandidateFacePair(const Bvh& bvh, uint32_t node, const Aabb& box, uint32_t n, uint32_t pair,
                           std::span<const uint8_t> binaryFilled, std::span<uint32_t> candidates) {
    uint32_t f1 = 0, f2 = 0;
    facePairFaces(pair, f1, f2);
    const uint32_t nn = n * n;
    for (uint32_t p1 = 0; p1 < nn; ++p1) {
        for (uint32_t p2 = 0; p2 < nn; ++p2) {
            if (binaryFilled[lsShaftIndexFromPatches(f1, p1, f2, p2, n, true)] == 0) {
                continue; // no geometry in the volume: the centroid ray cannot hit any
            }
            for (const uint32_t shaft :
                 {lsShaftIndexFromPatches(f1, p1, f2, p2, n, false), lsShaftIndexFromPatches(f2, p2, f1, p1, n, false)}) {
                glm::vec3 origin, direction;
                centroidRay(box, n, shaft, origin, direction);
                const uint32_t hit = subtreeClosestHit(bvh, node, origin, direction, 0.0f, 1.0f);
                if (hit != kNoTriangle) {
                    candidates[shaft] = hit;
                }
            }
        }
    }
}

ApproximateHit intersectCandidatePlane(const Bvh& bvh, const Scene& scene, uint32_t triangle, const Ray& ray,
                                       float tLo, float tHi, float cosMaxAngle, bool frontOnly) {
    ApproximateHit result;
    const TriangleGpu& tri = bvh.triangles[triangle];
    // Moeller-Trumbore without the barycentric bounds: the hit with the triangle's plane (extrapolation).
    const glm::vec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
    const glm::vec3 p = glm::cross(ray.direction, e2);
    const float det = gpu::dotOrdered(e1, p);
    if (det == 0.0f || (frontOnly && !(det > 0.0f))) {
        return result; // ray parallel to the plane, or (frontOnly) meeting its back side: det = -dot(d, e1 x e2)
    }
    const float invDet = 1.0f / det;
    const glm::vec3 s = ray.origin - tri.v0;
    const glm::vec3 q = glm::cross(s, e1);
    const float u = gpu::dotOrdered(s, p) * invDet;
    const float v = gpu::dotOrdered(ray.direction, q) * invDet;
    const float t = gpu::dotOrdered(e2, q) * invDet;
    if (!(t >= tLo && t <= tHi)) {
        return result;
    }
    const glm::uvec3 indices = scene.triangles[tri.originalId];
    const glm::vec3 n0 = scene.normals[indices.x], n1 = scene.normals[indices.y], n2 = scene.normals[indices.z];
    const glm::vec3 interpolated = (1.0f - u - v) * n0 + u * n1 + v * n2;
    const glm::vec3 mean = n0 + n1 + n2;
    const float lengths = glm::length(interpolated) * glm::length(mean);
    // §3.1: an extrapolated normal far from the triangle's mean normal marks a surface edge: discard.
    if (!(lengths > 0.0f) || glm::dot(interpolated, mean) < cosMaxAngle * lengths) {
        return result;
    }
    result.hit = true;
    result.t = t;
    result.triangle = triangle;
    result.u = u;
    result.v = v;
    result.normal = glm::normalize(interpolated);
    return result;
}

ApproximateHit approximateHit(const Bvh& bvh, const Scene& scene, const SparseShaftStore& store, uint32_t space,
                              const Aabb& box, uint32_t n, const Ray& ray, float maxNormalAngleDegrees,
                              bool frontOnly) {
    const glm::vec3 invDir = gpu::safeInverseDirection(ray.direction);
    const glm::vec2 entryExit = gpu::intersectRayAabb(ray.origin, invDir, box.lower, box.upper);
    if (!gpu::rayHitsAabb(entryExit, ray.tmin, ray.tmax)) {
        return {};
    }
    const uint32_t shaft = gpu::lsShaftIndex(ray.origin, ray.direction, invDir, box.lower, box.upper, n, false);
    if (shaft == CHCRT_LS_NO_SHAFT) {
        return {};
    }
    const uint32_t candidate = store.lookup(space, shaft);
    if (candidate == kEmptyShaft) {
        return {};
    }
    const float cosMaxAngle = std::cos(glm::radians(maxNormalAngleDegrees));
    return intersectCandidatePlane(bvh, scene, candidate, ray, std::max(ray.tmin, entryExit.x),
                                   std::min(ray.tmax, entryExit.y), cosMaxAngle, frontOnly);
}

} // namespace chcrt::ls
