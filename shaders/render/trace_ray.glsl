// The pure tracer's work for one ray, shared by its two passes so that both run the same code and write the same
// bits: the fragment pass (render/trace_bvh.frag.glsl, a full-screen pass with a fragment per ray) and the compute
// pass (render/trace_bvh.comp.glsl, an invocation per ray). Host defines: TRACE_ANY_HIT (0 | 1),
// CHCRT_BVH_TRAVERSAL (the file that defines traverseBvh; the Line Space and N-tree tracers name their own).
#include "shared/render_layout.h"
#include "render/bvh_nodes.glsl"
#ifndef CHCRT_BVH_TRAVERSAL
#define CHCRT_BVH_TRAVERSAL "render/bvh_traverse.glsl"
#endif
#include CHCRT_BVH_TRAVERSAL

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
#if CHCRT_TRACE_COUNTS_ITERATIONS
layout(binding = CHCRT_ATOMIC_BINDING_CAPPED_RAYS, offset = 0) uniform atomic_uint cappedRays;
#endif

// Traces the ray of `pixel` from the ray textures: its hit (CHCRT_TRACE_OUT_HIT layout) and cost
// (CHCRT_TRACE_OUT_COST layout). An inactive ray (tmax <= tmin) is not traversed: a miss at zero cost.
void traceRay(ivec2 pixel, out uvec4 hitOut, out uvec4 costOut) {
    vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
    vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
    TraceHit best = makeMiss(directionTmax.w);
    TraceCost cost = TraceCost(0u, 0u, 0u, 0u);
    if (directionTmax.w > originTmin.w) {
        traverseBvh(0u, originTmin.xyz, directionTmax.xyz, originTmin.w, best, cost);
    }
    bool capped = false;
#if CHCRT_TRACE_COUNTS_ITERATIONS
    capped = cost.iterations >= CHCRT_TRACE_ITERATION_CAP;
    if (capped) {
        atomicCounterIncrement(cappedRays);
    }
#endif
    float t = best.triangleId == CHCRT_NO_HIT_ID ? CHCRT_NO_HIT_T : best.t;
    hitOut = uvec4(floatBitsToUint(t), best.triangleId, floatBitsToUint(best.barycentrics));
    costOut = uvec4(cost.innerNodes, cost.leaves, cost.triangles, capped ? 1u : 0u);
}
