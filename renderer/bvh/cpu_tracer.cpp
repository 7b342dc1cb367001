// Scalar CPU twin of the GLSL BVH tracer. Written so that shaders/render/bvh_traverse.glsl can mirror it line
// by line: fixed-size stack arrays instead of containers, the intersection functions of
// shaders/shared/intersect.h, the node and triangle fields of shaders/shared/bvh_layout.h, no recursion.
//
// Loop structure ("while-while", Aila & Laine 2009, as CHC+RT §5.2 uses it):
//
//   if the ray is inactive or misses the root box: return miss
//   node = root
//   loop:
//     while node is inner:                       -- inner loop: walk down, one node per iteration
//       test both children's boxes against [tmin, tLimit]
//       both hit:    push the farther child (with its entry distance), continue with the nearer
//       one hit:     continue with it
//       none hit:    node = NONE; break
//     if node != NONE: intersect the leaf's triangles, shrinking tLimit  -- leaf step
//     pop until an entry with entry <= tLimit (older entries the closest hit has overtaken are dropped)
//     nothing left: return best
//
// tLimit starts at ray.tmax and becomes the closest accepted t. Box tests and the pop compare against
// pruneLimit(tLimit) (slightly beyond tLimit, shared/intersect.h) on purpose: a box entered at (or, after rounding,
// just beyond) the closest t may hold a triangle at the same t
// with a lower original id, which wins the tie. A hit counts only where the ray meets its triangle's bounding box, at a
// t no less than that box's entry (hitRule: an ill-conditioned triangle can be hit at a computed t before its own box,
// a grazing ray can meet a triangle in a box face the slab test says it misses), so that no pruned or skipped box
// ever holds a candidate at or below tLimit and the hit depends neither on the visiting order nor on the boxes. Leaves are intersected as soon as they are
// reached (the paper's leaf postponing is a SIMD optimisation that changes nothing for a scalar loop).
#include "renderer/bvh/cpu_tracer.h"

#include "renderer/bvh/bvh_internal.h"
#include "shaders/shared/intersect.h"

#include <algorithm>
#include <cassert>

namespace chcrt {

namespace {

using gpu::intersectRayAabb;
using gpu::intersectRayTriangle;
using gpu::rayHitsAabb;

constexpr uint32_t kNoNode = 0xFFFFFFFFu;
constexpr uint32_t kRaysPerItem = 256; // traceCpu work item

// The acceptance rule shared by every tracer: t inside [tmin, tmax] (both inclusive), closer than the best
// hit, or equally close with a lower original id (deterministic tie-break). Rays need tmin >= 0:
// intersectRayTriangle reports a miss as t = -1.
bool acceptsHit(float t, uint32_t originalId, float tmin, float tmax, const Hit& best) {
    return t >= tmin && t <= tmax && (t < best.t || (t == best.t && originalId < best.triangleId));
}

template <bool kAnyHit>
Hit traverse(const Bvh& bvh, const Ray& ray) {
    Hit best;
    // Inactive rays (tmax <= tmin, tmax == 0, or NaN) are misses without traversal.
    if (!(ray.tmax > ray.tmin) || ray.tmax == 0.0f || bvh.nodes.empty()) {
        return best;
    }
    const glm::vec3 origin = ray.origin;
    const glm::vec3 direction = ray.direction;
    const glm::vec3 invDir = gpu::safeInverseDirection(direction); // as the GLSL tracer: no 0 * inf
    const float tmin = ray.tmin;
    float tLimit = ray.tmax;

    uint32_t stackNode[CHCRT_MAX_BVH_DEPTH];
    float stackEntry[CHCRT_MAX_BVH_DEPTH];
    int stackSize = 0;

    // The root's box is tested once here; every other box is tested by its parent, two at a time.
    const BvhNodeGpu& root = bvh.nodes[0];
    const glm::vec2 rootEntryExit = intersectRayAabb(origin, invDir, root.boundsMin, root.boundsMax);
    if (!rayHitsAabb(rootEntryExit, tmin, gpu::pruneLimit(tLimit))) {
        return best;
    }
    uint32_t node = 0;
    while (true) {
        // Inner loop: descend through inner nodes until a leaf is reached or no child is hit.
        while (bvh.nodes[node].triCount == 0) {
            const uint32_t left = bvh.nodes[node].leftFirst;
            const BvhNodeGpu& c0 = bvh.nodes[left];
            const BvhNodeGpu& c1 = bvh.nodes[left + 1];
            const glm::vec2 e0 = intersectRayAabb(origin, invDir, c0.boundsMin, c0.boundsMax);
            const glm::vec2 e1 = intersectRayAabb(origin, invDir, c1.boundsMin, c1.boundsMax);
            const float limit = gpu::pruneLimit(tLimit);
            const bool hit0 = rayHitsAabb(e0, tmin, limit);
            const bool hit1 = rayHitsAabb(e1, tmin, limit);
            if (hit0 && hit1) {
                // Nearer child first (ties: left), the farther one waits with its entry distance.
                const bool rightFirst = e1.x < e0.x;
                assert(stackSize < CHCRT_MAX_BVH_DEPTH && "the builder guarantees depth < CHCRT_MAX_BVH_DEPTH");
                stackNode[stackSize] = rightFirst ? left : left + 1;
                stackEntry[stackSize] = rightFirst ? e0.x : e1.x;
                ++stackSize;
                node = rightFirst ? left + 1 : left;
            } else if (hit0 || hit1) {
                node = hit0 ? left : left + 1;
            } else {
                node = kNoNode;
                break;
            }
        }
        // Leaf step: intersect its triangles; every accepted hit shrinks tLimit.
        if (node != kNoNode) {
            const uint32_t first = bvh.nodes[node].leftFirst;
            const uint32_t last = first + bvh.nodes[node].triCount;
            for (uint32_t i = first; i < last; ++i) {
                const TriangleGpu& tri = bvh.triangles[i];
                const glm::vec3 tuv = intersectRayTriangle(origin, direction, tri.v0, tri.v1, tri.v2);
                if (!(tuv.x >= tmin && tuv.x <= best.t)) continue;
                // The hit rule, as the GLSL tracers: the hit depends neither on visiting order nor on the boxes.
                const glm::vec2 rule = gpu::hitRule(tuv.x, tmin, origin, invDir, tri.v0, tri.v1, tri.v2);
                const float t = rule.x;
                if (rule.y != 0.0f && acceptsHit(t, tri.originalId, tmin, ray.tmax, best)) {
                    best.t = t;
                    best.triangleId = tri.originalId;
                    best.u = tuv.y;
                    best.v = tuv.z;
                    tLimit = t;
                    if (kAnyHit) {
                        return best;
                    }
                }
            }
        }
        // Pop the next waiting node, dropping those the closest hit has overtaken since they were pushed.
        node = kNoNode;
        while (stackSize > 0) {
            --stackSize;
            if (stackEntry[stackSize] <= gpu::pruneLimit(tLimit)) {
                node = stackNode[stackSize];
                break;
            }
        }
        if (node == kNoNode) {
            return best;
        }
    }
}

} // namespace

Hit traceClosestCpu(const Bvh& bvh, const Ray& ray) { return traverse<false>(bvh, ray); }

Hit traceAnyCpu(const Bvh& bvh, const Ray& ray) { return traverse<true>(bvh, ray); }

void traceCpu(const Bvh& bvh, std::span<const Ray> rays, std::span<Hit> hits, bool anyHit) {
    assert(rays.size() == hits.size());
    const size_t count = std::min(rays.size(), hits.size());
    const auto items = uint32_t((count + kRaysPerItem - 1) / kRaysPerItem);
    detail::parallelFor(detail::resolveThreadCount(0), items, [&](uint32_t, uint32_t item) {
        const size_t end = std::min(count, size_t(item + 1) * kRaysPerItem);
        for (size_t i = size_t(item) * kRaysPerItem; i < end; ++i) {
            hits[i] = anyHit ? traceAnyCpu(bvh, rays[i]) : traceClosestCpu(bvh, rays[i]);
        }
    });
}

} // namespace chcrt
