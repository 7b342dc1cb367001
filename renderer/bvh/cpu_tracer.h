#pragma once
// Scalar CPU twin of the GLSL BVH tracer (shaders/render/bvh_traverse.glsl): same node layout, same
// intersection arithmetic (shaders/shared/intersect.h), same tie-break (lower original id wins on equal t).
// It is the naive reference that tests compare the GLSL tracer and Embree against; not optimised.
#include "renderer/bvh/bvh.h"

#include <span>

namespace chcrt {

struct Ray {
    glm::vec3 origin{0.0f};
    float tmin = 0.0f;
    glm::vec3 direction{0.0f, 0.0f, -1.0f};
    float tmax = 0.0f; // tmax <= tmin (or tmax == 0) marks an inactive ray: no traversal, reported as a miss
};

struct Hit {
    float t = CHCRT_NO_HIT_T;
    uint32_t triangleId = CHCRT_NO_HIT_ID; // original id (index into Scene::triangles)
    float u = 0.0f;
    float v = 0.0f;
    bool hit() const { return triangleId != CHCRT_NO_HIT_ID; }
};

// Closest hit in [tmin, tmax].
Hit traceClosestCpu(const Bvh& bvh, const Ray& ray);
// Any hit in [tmin, tmax] (shadow/AO rays); returns the first found (triangleId set, t valid) or a miss.
Hit traceAnyCpu(const Bvh& bvh, const Ray& ray);
// Both over many rays on all cores.
void traceCpu(const Bvh& bvh, std::span<const Ray> rays, std::span<Hit> hits, bool anyHit);

} // namespace chcrt
