#version 450 core
// CHC+RT: resets the hit buffer to misses and the depth buffer to each ray's tmax (inactive rays: 0) before
// the first pass of a trace, so depth always holds depthFromDistance(nearest t so far) (§4.1).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "culling/culling_layout.h"
#include "shared/intersect.h"

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform writeonly uimage2D hitImage;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float tmin = texelFetch(rayOrigins, pixel, 0).w;
    float tmax = texelFetch(rayDirections, pixel, 0).w;
    imageStore(hitImage, pixel, uvec4(floatBitsToUint(CHCRT_NO_HIT_T), CHCRT_NO_HIT_ID, 0u, 0u));
    gl_FragDepth = tmax > tmin ? depthFromDistance(pruneLimit(tmax)) : 0.0f;
}
