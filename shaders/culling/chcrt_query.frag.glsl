#version 450 core
// CHC+RT §4.1 generalized occlusion query (the viewport is the screen tile): every active ray of the tile that
// meets one of the boxes (with entry <= pruneLimit(tmax)) writes its nearest entry distance as depth; the GL_LEQUAL
// depth test against depthFromDistance(pruneLimit(nearest t so far)), 1 while the ray has no hit, lets exactly the rays through that the BVH traversal would not prune
// (rayHitsAabb with best t) for at least one box, and GL_SAMPLES_PASSED counts them. The boxes are one pair's
// node box, or with §5.1 tighter bounds its two children's boxes, or those of several pairs of the same tile
// (§5.1 multi-query): the nearest entry among the boxes a ray meets passes iff any of them would.
// Host defines: TRACE_ANY_HIT (0 | 1: rays that already hit are finished and never pass),
// CHCRT_CULLING_DEBUG_OVERDRAW (count query fragments per pixel into the debug image, Figure 4 left).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/intersect.h"
#include "shared/culling_layout.h"

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
#if TRACE_ANY_HIT
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform readonly uimage2D hitImage;
#endif
#ifdef CHCRT_CULLING_DEBUG_OVERDRAW
layout(binding = CHCRT_CULLING_IMAGE_DEBUG, r32ui) uniform coherent uimage2D debugImage;
#endif

uniform vec4 boxMin[CHCRT_CULLING_MAX_QUERY_BOXES];
uniform vec4 boxMax[CHCRT_CULLING_MAX_QUERY_BOXES];
uniform int boxCount;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
#ifdef CHCRT_CULLING_DEBUG_OVERDRAW
    imageAtomicAdd(debugImage, pixel, 1u);
#endif
    vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
    vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
    if (!(directionTmax.w > originTmin.w)) {
        discard;
    }
#if TRACE_ANY_HIT
    if (imageLoad(hitImage, pixel).y != CHCRT_NO_HIT_ID) {
        discard;
    }
#endif
    vec3 invDir = safeInverseDirection(directionTmax.xyz);
    float tmaxLimit = pruneLimit(directionTmax.w);
    bool any = false;
    float entry = 0.0f;
    for (int i = 0; i < boxCount && i < CHCRT_CULLING_MAX_QUERY_BOXES; ++i) {
        vec2 entryExit = intersectRayAabb(originTmin.xyz, invDir, boxMin[i].xyz, boxMax[i].xyz);
        // The part of rayHitsAabb that does not involve best t; the entry <= best t part is the depth test.
        // The ray's own tmax is tested here (the depth buffer starts at 1, not at depth(tmax)): the same
        // entry <= pruneLimit(best t) rule as traversal, with best t = tmax before any hit.
        if (entryExit.x <= entryExit.y && entryExit.y >= originTmin.w && entryExit.x <= tmaxLimit) {
            entry = any ? min(entry, entryExit.x) : entryExit.x;
            any = true;
        }
    }
    if (!any) {
        discard;
    }
    gl_FragDepth = depthFromDistance(entry);
}
