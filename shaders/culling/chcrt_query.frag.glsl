#version 450 core
// CHC+RT §4.1 generalized occlusion query for one query pair (the viewport is the screen tile, the uniforms the
// BVH node's box): every active ray of the tile that meets the box writes its entry distance as depth; the
// GL_LEQUAL depth test against depthFromDistance(nearest t so far) lets exactly the rays through that the
// BVH traversal would not prune (rayHitsAabb with best t), and GL_SAMPLES_PASSED counts them.
// Host defines: TRACE_ANY_HIT (0 | 1: rays that already hit are finished and never pass).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/intersect.h"
#include "culling/culling_layout.h"

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
#if TRACE_ANY_HIT
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform readonly uimage2D hitImage;
#endif

uniform vec3 boxMin;
uniform vec3 boxMax;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
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
    vec2 entryExit = intersectRayAabb(originTmin.xyz, safeInverseDirection(directionTmax.xyz), boxMin, boxMax);
    // The part of rayHitsAabb that does not involve best t; the entry <= best t part is the depth test.
    if (!(entryExit.x <= entryExit.y && entryExit.y >= originTmin.w)) {
        discard;
    }
    gl_FragDepth = depthFromDistance(entryExit.x);
}
