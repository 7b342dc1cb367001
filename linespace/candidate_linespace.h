#pragma once
// Representative candidate Line Space (Keul, Koss, Mueller §3.1): per non-empty shaft the triangle hit first by
// the ray from the start patch's centroid to the end patch's centroid (searched in the node's subtree); when
// that ray hits nothing the shaft is empty in the candidate Line Space (so its filled shafts are a subset of
// the binary Line Space's). Non-symmetric (30 N^4 shafts): the first hit depends on the direction.
// Candidates are indices into Bvh::triangles (BVH order; the GPU triangle buffer), kept in sparse storage.
//
// approximateHit() is the use at trace time (Algorithm 1): the candidate's triangle is taken as an infinite
// plane; the hit's barycentrics (extrapolated outside the triangle) interpolate the vertex normals, and the hit
// is discarded when that normal deviates from the triangle's mean normal by more than a threshold angle (edge
// detection for shafts the surface does not cover).
#include "linespace/sparse_storage.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/cpu_tracer.h"
#include "renderer/scene/scene.h"

#include <cstdint>
#include <span>

namespace chcrt::ls {

// Fills candidates[nonSymmetricShaft] for both directions of every shaft of face pair `pair` that is marked in
// `binaryFilled` (15 N^4 bytes, symmetric layout); others are left untouched (callers initialise to
// kEmptyShaft). `candidates` holds 30 N^4 entries.
void fillCandidateFacePair(const Bvh& bvh, uint32_t node, const Aabb& box, uint32_t n, uint32_t pair,
                           std::span<const uint8_t> binaryFilled, std::span<uint32_t> candidates);

// The centroid ray of a (non-symmetric) shaft: origin at the start patch centroid, direction to the end patch
// centroid, so t in [0, 1] spans the box.
void centroidRay(const Aabb& box, uint32_t n, uint32_t shaft, glm::vec3& origin, glm::vec3& direction);

struct ApproximateHit {
    bool hit = false;
    float t = 0.0f;
    uint32_t triangle = kEmptyShaft; // index into Bvh::triangles
    float u = 0.0f, v = 0.0f;        // barycentrics on the candidate's plane (may lie outside [0, 1])
    glm::vec3 normal{0.0f};          // interpolated (extrapolated) vertex normal, normalised
};

// Intersects the ray with the plane of BVH triangle `triangle` within [tLo, tHi] and applies the normal-angle
// rejection with cos(threshold) = cosMaxAngle. Vertex normals come from the scene (by original id).
// frontOnly: a plane met from its back side (counter-clockwise = front) is no hit (`--ls-modes faces=front`).
ApproximateHit intersectCandidatePlane(const Bvh& bvh, const Scene& scene, uint32_t triangle, const Ray& ray,
                                       float tLo, float tHi, float cosMaxAngle, bool frontOnly = false);

// Algorithm 1 on one Line Space node: shaft of the ray's line in `box`, its candidate from `store` (Line Space
// `space`), and the plane hit restricted to the ray's [tmin, tmax] and to the box's [tEntry, tExit] (a plane
// hit outside the node's box is not that node's geometry). A miss when the shaft is empty.
ApproximateHit approximateHit(const Bvh& bvh, const Scene& scene, const SparseShaftStore& store, uint32_t space,
                              const Aabb& box, uint32_t n, const Ray& ray, float maxNormalAngleDegrees,
                              bool frontOnly = false);

} // namespace chcrt::ls
