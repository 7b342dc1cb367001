#version 450 core
// The mask of the any-hit rays a CHC+RT intersection round after the first still traces (culling/cell_traversal.h):
// drawn over the cells with work (chcrt_cells.vert.glsl) into a depth buffer cleared to 0, depth 1 where the ray
// is active and has no hit yet. The round's traversal tests it early, so rays that Phase 1 finished cost nothing
// there (llvmpipe skips only fragment groups that fail an early depth test).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/culling_layout.h"

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform readonly uimage2D hitImage;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    bool traced = texelFetch(rayDirections, pixel, 0).w > texelFetch(rayOrigins, pixel, 0).w &&
                  imageLoad(hitImage, pixel).y == CHCRT_NO_HIT_ID;
    gl_FragDepth = traced ? 1.0f : 0.0f;
}
