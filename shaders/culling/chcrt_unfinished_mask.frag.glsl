#version 450 core
// The mask of rays CHC+RT's later intersection rounds still trace (culling/chcrt_tracer_bounds.cpp): depth 1 where
// the ray is active and, for any-hit rays, has no hit yet; 0 elsewhere. The cell passes test it early, so finished
// shadow and AO rays cost nothing there (llvmpipe skips only fragment groups that fail an early depth test).
// Host define: TRACE_ANY_HIT (0 | 1).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/culling_layout.h"

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform readonly uimage2D hitImage;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    bool traced = texelFetch(rayDirections, pixel, 0).w > texelFetch(rayOrigins, pixel, 0).w;
#if TRACE_ANY_HIT
    traced = traced && imageLoad(hitImage, pixel).y == CHCRT_NO_HIT_ID;
#endif
    gl_FragDepth = traced ? 1.0f : 0.0f;
}
