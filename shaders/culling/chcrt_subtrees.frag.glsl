#version 450 core
// CHC+RT §5.2 subtree intersection with by-tile batching: the viewport is one screen tile; the uniforms list up
// to CHCRT_CULLING_MAX_BATCH termination-subtree roots (approximately front to back). Each ray continues from
// the nearest hit stored so far (image load/store on the hit buffer) and traverses every subtree whose box it
// meets with the project's exact hit rule (render/bvh_nodes.glsl), so the final hits are those of pure BVH
// tracing. Changed rays store their hit and write depthFromDistance(t) for later occlusion queries.
// Host defines: TRACE_ANY_HIT (0 | 1), CHCRT_CULLING_SINGLE_SUBTREE (0 | 1: the variant for batches of one),
// CHCRT_CULLING_MERGED_BATCH (0 | 1: the batch as one traversal, culling/subtree_batch_traverse.glsl),
// CHCRT_CULLING_LEAF_CACHE (0 | 1: §5.2 2-entry leaf cache,
// subtree_traverse_cached.glsl), CHCRT_SUBTREE_STACK (traversal stack entries: the partition's maximum
// subtree height + 1, §5.2; on llvmpipe 25 vs 64 entries measured no difference, see culling/README.md),
// CHCRT_CULLING_DEBUG_SUBTREES / CHCRT_CULLING_DEBUG_BATCHES / CHCRT_CULLING_DEBUG_COST (debug image: 1 + id of
// the subtree that changed the pixel's hit last, Figure 5 left / subtrees traversed per pixel, Figure 5 right /
// traversal steps per pixel summed over all passes, bit 31 = capped, layout in culling/culling_layout.h),
// CHCRT_HIT_TRIANGLE_INDEX (with the subtree ids: also the hit triangle's buffer index, CHCRT_CULLING_IMAGE_HIT_TRIANGLE).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/culling_layout.h"
// The traversals size their stacks with CHCRT_MAX_BVH_DEPTH; subtrees are bounded by the termination height.
#ifdef CHCRT_SUBTREE_STACK
#undef CHCRT_MAX_BVH_DEPTH
#define CHCRT_MAX_BVH_DEPTH CHCRT_SUBTREE_STACK
#endif
#include "render/bvh_nodes.glsl"
// traverseBvh: the pure traversal, or the one the host names (Line Space traversal, methods chcrt+ls*; the host
// then turns the leaf cache and merged batches off, which have only a pure form).
#ifndef CHCRT_BVH_TRAVERSAL
#define CHCRT_BVH_TRAVERSAL "render/bvh_traverse.glsl"
#endif
#include CHCRT_BVH_TRAVERSAL
#if CHCRT_CULLING_LEAF_CACHE
#include "culling/subtree_traverse_cached.glsl"
#endif
// One traversal for the whole batch (default, ChcrtOptions::mergedBatch); the loop over subtrees stays for the
// leaf cache and Line Space traversals (whose traversals take one root) and for the subtree-id debug image (which
// needs to know which subtree changed the hit).
#if defined(CHCRT_CULLING_MERGED_BATCH) && CHCRT_CULLING_MERGED_BATCH && !CHCRT_CULLING_LEAF_CACHE && \
    !defined(CHCRT_CULLING_DEBUG_SUBTREES) && !CHCRT_CULLING_SINGLE_SUBTREE
#define CHCRT_CULLING_TRAVERSE_MERGED 1
#else
#define CHCRT_CULLING_TRAVERSE_MERGED 0
#endif

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform uimage2D hitImage;
layout(binding = CHCRT_ATOMIC_BINDING_CAPPED_RAYS, offset = 0) uniform atomic_uint cappedRays;

uniform uvec4 subtreeRoots[CHCRT_CULLING_MAX_BATCH / 4];
uniform int subtreeCount;
#if CHCRT_CULLING_TRAVERSE_MERGED
#include "culling/subtree_batch_traverse.glsl"
#endif
#if defined(CHCRT_CULLING_DEBUG_SUBTREES) || defined(CHCRT_CULLING_DEBUG_BATCHES) || defined(CHCRT_CULLING_DEBUG_COST)
layout(binding = CHCRT_CULLING_IMAGE_DEBUG, r32ui) uniform coherent uimage2D debugImage;
#endif
#ifdef CHCRT_CULLING_DEBUG_SUBTREES
uniform uvec4 subtreeIds[CHCRT_CULLING_MAX_BATCH / 4]; // culling-hierarchy subtree index per slot
#ifdef CHCRT_HIT_TRIANGLE_INDEX
layout(binding = CHCRT_CULLING_IMAGE_HIT_TRIANGLE, r32ui) uniform writeonly uimage2D hitTriangleImage;
#endif
#endif

#include "culling/debug_cost.glsl"

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
    vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
    if (!(directionTmax.w > originTmin.w)) {
        discard;
    }
#ifdef CHCRT_CULLING_DEBUG_BATCHES
    imageAtomicAdd(debugImage, pixel, uint(subtreeCount));
#endif
    uvec4 stored = imageLoad(hitImage, pixel);
#if TRACE_ANY_HIT
    if (stored.y != CHCRT_NO_HIT_ID) {
        discard; // finished
    }
#endif
    TraceHit best = makeMiss(directionTmax.w);
    if (stored.y != CHCRT_NO_HIT_ID) {
        best.t = uintBitsToFloat(stored.x);
        best.triangleId = stored.y;
        best.barycentrics = uintBitsToFloat(stored.zw);
    }
    uint previousId = best.triangleId;
    float previousT = best.t;
    TraceCost cost = TraceCost(0u, 0u, 0u, 0u);
#ifdef CHCRT_CULLING_DEBUG_SUBTREES
    uint changedBy = 0u;
#endif
#if CHCRT_CULLING_SINGLE_SUBTREE
    // Batches of one subtree (e.g. the whole BVH is one termination subtree): a constant trip count lets the
    // compiler drop the batch loop around the traversal (culling/README.md, performance).
    const int batchCount = 1;
#else
    int batchCount = subtreeCount;
#endif
#if CHCRT_CULLING_TRAVERSE_MERGED
    traverseSubtreeBatch(min(batchCount, CHCRT_CULLING_MAX_BATCH), originTmin.xyz, directionTmax.xyz, originTmin.w,
                         best, cost);
#else
    // batchCount <= CHCRT_CULLING_MAX_BATCH; the iterations still count towards the cap (llvmpipe's
    // 65,535-iteration limit is per invocation, shared by all its loops).
    for (int i = 0; i < batchCount && i < CHCRT_CULLING_MAX_BATCH && cost.iterations < CHCRT_TRACE_ITERATION_CAP;
         ++i) {
        ++cost.iterations;
#ifdef CHCRT_CULLING_DEBUG_SUBTREES
        uint idBefore = best.triangleId;
        float tBefore = best.t;
#endif
#if CHCRT_CULLING_LEAF_CACHE
        traverseSubtreeCached(subtreeRoots[i >> 2][i & 3], originTmin.xyz, directionTmax.xyz, originTmin.w, best, cost);
#else
        traverseBvh(subtreeRoots[i >> 2][i & 3], originTmin.xyz, directionTmax.xyz, originTmin.w, best, cost);
#endif
#ifdef CHCRT_CULLING_DEBUG_SUBTREES
        if (best.triangleId != idBefore || best.t != tBefore) {
            changedBy = subtreeIds[i >> 2][i & 3] + 1u;
        }
#endif
#if TRACE_ANY_HIT
        if (best.triangleId != CHCRT_NO_HIT_ID) {
            break;
        }
#endif
    }
#endif
    if (cost.iterations >= CHCRT_TRACE_ITERATION_CAP) {
        atomicCounterIncrement(cappedRays);
    }
#ifdef CHCRT_CULLING_DEBUG_COST
    // Before the discard below: a pass that finds nothing nearer still did its traversal. (The discards above
    // come before any traversal: inactive rays and finished any-hit rays add nothing.)
    addCostSteps(pixel, cost);
#endif
    if (best.triangleId == previousId && best.t == previousT) {
        discard; // nothing nearer in these subtrees: hit and depth stay
    }
#ifdef CHCRT_CULLING_DEBUG_SUBTREES
    imageStore(debugImage, pixel, uvec4(changedBy));
#ifdef CHCRT_HIT_TRIANGLE_INDEX
    imageStore(hitTriangleImage, pixel, uvec4(best.triangleIndex));
#endif
#endif
    imageStore(hitImage, pixel, uvec4(floatBitsToUint(best.t), best.triangleId, floatBitsToUint(best.barycentrics)));
    gl_FragDepth = depthFromDistance(pruneLimit(best.t)); // boxes up to pruneLimit(t) stay visible, as in traversal
}
