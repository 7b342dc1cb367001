#version 450 core
// Pure BVH tracing, compute stage: one invocation per ray in work groups of CHCRT_TRACE_GROUP_SIZE² pixels, the
// same per-ray code as the fragment stage (render/trace_ray.glsl), results stored into the same hit and cost
// targets through images, so everything downstream is unchanged and the bits are those of the fragment stage.
// Inactive rays are not traversed (a miss at zero cost is stored, as the fragment stage's mask clear leaves).
// Why a compute stage: data-centre GPUs run fragment work on few graphics-capable units (docs/architecture.md).
// Host defines: those of render/trace_ray.glsl.
#include "render/trace_ray.glsl"
#include "render/group_pixels.glsl"

layout(local_size_x = CHCRT_TRACE_GROUP_SIZE, local_size_y = CHCRT_TRACE_GROUP_SIZE) in;

layout(binding = CHCRT_IMAGE_TRACE_HIT, rgba32ui) uniform writeonly uimage2D hitImage;
layout(binding = CHCRT_IMAGE_TRACE_COST, rgba32ui) uniform writeonly uimage2D costImage;

uniform ivec2 regionOrigin; // the traced pixels: the scissor box when the scissor test is on, else the whole frame
uniform ivec2 regionSize;

void main() {
    ivec2 offset = ivec2(gl_WorkGroupID.xy) * CHCRT_TRACE_GROUP_SIZE +
                   groupPixel(gl_LocalInvocationIndex, uint(CHCRT_TRACE_GROUP_SIZE));
    if (any(greaterThanEqual(offset, regionSize))) {
        return;
    }
    ivec2 pixel = regionOrigin + offset;
    uvec4 hit, cost;
    traceRay(pixel, hit, cost);
    imageStore(hitImage, pixel, hit);
    imageStore(costImage, pixel, cost);
}
