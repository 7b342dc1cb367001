#version 450 core
// CHC+RT §4.1 generalized occlusion queries, batched (culling/batched_queries.h): one dispatch tests every pair of a
// round. A work group takes CHCRT_CULLING_BATCH_ITEM pixels of one pair's tile; each active ray of them that meets one
// of the pair's boxes with entry <= pruneLimit(nearest t so far) — pruneLimit(tmax) before any hit, the rule traversal
// prunes with (rayHitsAabb) — adds 1 to the pair's count. The GL query (chcrt_query.frag.glsl) tests the same rule
// through the depth buffer; here the nearest t is read from the hit image directly, so no depth is needed.
// Host defines: TRACE_ANY_HIT (0 | 1: rays that already hit are finished and never count),
// CHCRT_CULLING_DEBUG_OVERDRAW (count tested rays per pixel into the debug image, Figure 4 left).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/intersect.h"
#include "shared/culling_layout.h"

layout(local_size_x = CHCRT_CULLING_BATCH_GROUP) in;

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform readonly uimage2D hitImage;
#ifdef CHCRT_CULLING_DEBUG_OVERDRAW
layout(binding = CHCRT_CULLING_IMAGE_DEBUG, r32ui) uniform coherent uimage2D debugImage;
#endif

layout(std430, binding = CHCRT_CULLING_BATCH_INPUT_BUFFER) readonly buffer BatchInput {
    uvec4 batchInput[];
};
layout(std430, binding = CHCRT_CULLING_BATCH_COUNTS_BUFFER) coherent buffer BatchCounts {
    uint pairCounts[];
};

uniform uint itemBase;         // uvec4 index of the first work item in batchInput
uniform uint visibleThreshold; // a count above it decides the pair: counting further changes nothing

vec3 boxCorner(uint pairBase, uint texel) {
    return uintBitsToFloat(batchInput[pairBase + texel].xyz);
}

void main() {
    uvec4 item = batchInput[itemBase + gl_WorkGroupID.x];
    uint pair = item.x;
    uint pairBase = pair * uint(CHCRT_CULLING_BATCH_PAIR_TEXELS);
    ivec4 tile = ivec4(batchInput[pairBase]);
    uint boxCount = min(batchInput[pairBase + 1u].x, 2u);
    uint tilePixels = uint(tile.z * tile.w);
    uint end = min(item.y + uint(CHCRT_CULLING_BATCH_ITEM), tilePixels);
    for (uint i = item.y + gl_LocalInvocationID.x; i < end; i += uint(CHCRT_CULLING_BATCH_GROUP)) {
        if (pairCounts[pair] > visibleThreshold) {
            return; // decided: the pair is visible
        }
        ivec2 pixel = tile.xy + ivec2(int(i % uint(tile.z)), int(i / uint(tile.z)));
#ifdef CHCRT_CULLING_DEBUG_OVERDRAW
        imageAtomicAdd(debugImage, pixel, 1u);
#endif
        vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
        vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
        if (!(directionTmax.w > originTmin.w)) {
            continue; // inactive
        }
        uvec4 stored = imageLoad(hitImage, pixel);
#if TRACE_ANY_HIT
        if (stored.y != CHCRT_NO_HIT_ID) {
            continue; // finished
        }
#endif
        float limit = pruneLimit(stored.y != CHCRT_NO_HIT_ID ? uintBitsToFloat(stored.x) : directionTmax.w);
        vec3 invDir = safeInverseDirection(directionTmax.xyz);
        bool reaches = false;
        for (uint b = 0u; b < boxCount; ++b) {
            vec2 entryExit = intersectRayAabb(originTmin.xyz, invDir, boxCorner(pairBase, 2u + 2u * b),
                                              boxCorner(pairBase, 3u + 2u * b));
            reaches = reaches || rayHitsAabb(entryExit, originTmin.w, limit);
        }
        if (reaches) {
            atomicAdd(pairCounts[pair], 1u);
        }
    }
}
