#version 450 core
// Pure BVH tracing (the baseline every method is compared with): one full-screen fragment pass traces the ray
// of each pixel from the ray textures through the whole BVH. Host defines: TRACE_ANY_HIT (0 | 1),
// CHCRT_BVH_TRAVERSAL (the file that defines traverseBvh; the Line Space tracer names its own).
#include "shared/render_layout.h"
#include "render/bvh_nodes.glsl"
#ifndef CHCRT_BVH_TRAVERSAL
#define CHCRT_BVH_TRAVERSAL "render/bvh_traverse.glsl"
#endif
#include CHCRT_BVH_TRAVERSAL

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;

layout(binding = CHCRT_ATOMIC_BINDING_CAPPED_RAYS, offset = 0) uniform atomic_uint cappedRays;

layout(location = CHCRT_TRACE_OUT_HIT) out uvec4 outHit;
layout(location = CHCRT_TRACE_OUT_COST) out uvec4 outCost;

// Early depth test against the active-ray mask (renderer/render/trace_pass.h); also keeps the test early although
// the shader has a side effect (the capped-ray counter).
layout(early_fragment_tests) in;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
    vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
    TraceHit best = makeMiss(directionTmax.w);
    TraceCost cost = TraceCost(0u, 0u, 0u, 0u);
    if (directionTmax.w > originTmin.w) {
        traverseBvh(0u, originTmin.xyz, directionTmax.xyz, originTmin.w, best, cost);
    }
    bool capped = cost.iterations >= CHCRT_TRACE_ITERATION_CAP;
    if (capped) {
        atomicCounterIncrement(cappedRays);
    }
    float t = best.triangleId == CHCRT_NO_HIT_ID ? CHCRT_NO_HIT_T : best.t;
    outHit = uvec4(floatBitsToUint(t), best.triangleId, floatBitsToUint(best.barycentrics));
    outCost = uvec4(cost.innerNodes, cost.leaves, cost.triangles,
                    capped ? 1u : 0u);
}
