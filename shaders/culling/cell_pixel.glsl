// CHC+RT cell passes (culling/cell_traversal.h), the part shared by the fragment pass (chcrt_cells.frag.glsl) and the
// compute pass (chcrt_cells.comp.glsl): the bindings, and what one ray of a cell does — continue from the nearest hit
// stored so far (image load/store on the hit buffer: one invocation per pixel per pass, so no other invocation
// touches it), visit its hinted leaf (with hit hints), traverse its cell's list of termination subtrees
// with the project's exact hit rule (render/bvh_nodes.glsl), store a nearer hit. The final hits are those of pure
// BVH tracing.
// Host defines: TRACE_ANY_HIT (0 | 1), CHCRT_SUBTREE_STACK (traversal stack entries: the partition's maximum
// subtree height + 1, §5.2), CHCRT_CULLING_DEBUG_SUBTREES / _BATCHES / _COST (debug images, as the subtree pass
// of culling/chcrt_subtrees.frag.glsl: 1 + id of the subtree that changed the hit last / subtrees listed for the
// pixel / traversal steps, bit 31 = capped; with the subtree ids also the hit triangle's buffer index, as there),
// CHCRT_CULLING_HINTS (1: visit the ray's hinted leaf first, and record
// the leaf of every hit this pass finds in the ray set's hint image: for closest-hit rays the leaf of the nearest),
// CHCRT_CULLING_HINTS_VISITED (1: the hint pass visited every ray's hint before this pass, so the visit is not
// compiled: a variant, not a uniform, because llvmpipe runs both sides of every branch for each SIMD group —
// docs/architecture.md — and a visit skipped by a uniform cost each group a leaf test),
// CHCRT_CELL_PASS_WRITES_ALL (1: the first pass of a trace over every cell, after no clear of the hit image: each ray
// starts from a miss without loading its stored hit and stores its result, a miss too; ChcrtTracer::beginTrace).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/culling_layout.h"
#ifdef CHCRT_SUBTREE_STACK
#undef CHCRT_MAX_BVH_DEPTH
#define CHCRT_MAX_BVH_DEPTH CHCRT_SUBTREE_STACK
#endif
#ifndef CHCRT_CULLING_HINTS
#define CHCRT_CULLING_HINTS 0
#endif
#ifndef CHCRT_CULLING_HINTS_VISITED
#define CHCRT_CULLING_HINTS_VISITED 0
#endif
#ifndef CHCRT_CELL_PASS_WRITES_ALL
#define CHCRT_CELL_PASS_WRITES_ALL 0
#endif
#include "render/bvh_nodes.glsl"
#include "culling/hint_leaf.glsl"

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform uimage2D hitImage;
#if CHCRT_CULLING_HINTS
layout(binding = CHCRT_CULLING_IMAGE_HINT, r32ui) uniform uimage2D hintImage;
#endif

layout(binding = CHCRT_UNIT_CULLING_CELL_HEADERS) uniform usamplerBuffer cellHeaders;
layout(binding = CHCRT_ATOMIC_BINDING_CAPPED_RAYS, offset = 0) uniform atomic_uint cappedRays;
#if defined(CHCRT_CULLING_DEBUG_SUBTREES) || defined(CHCRT_CULLING_DEBUG_BATCHES) || defined(CHCRT_CULLING_DEBUG_COST)
layout(binding = CHCRT_CULLING_IMAGE_DEBUG, r32ui) uniform coherent uimage2D debugImage;
#endif

uniform int cellsX;
uniform int cellSize;

#ifdef CHCRT_CULLING_DEBUG_SUBTREES
layout(binding = CHCRT_UNIT_CULLING_CELL_IDS) uniform usamplerBuffer cellIds;
#ifdef CHCRT_HIT_TRIANGLE_INDEX
layout(binding = CHCRT_CULLING_IMAGE_HIT_TRIANGLE, r32ui) uniform writeonly uimage2D hitTriangleImage;
#endif
uint changedBy = 0u; // 1 + the subtree id of the listed root whose traversal last changed the hit
#endif
#if defined(CHCRT_CULLING_DEBUG_SUBTREES) || CHCRT_CULLING_HINTS
#define CHCRT_CELL_TRACK_LEAF 1
uint changedLeaf = CHCRT_NO_HIT_ID; // the BVH leaf whose triangle last changed the hit
// The leaf test, remembering which listed root (entry) and which leaf (node) changed the hit.
bool visitLeafTracked(uint entry, uint node, uint first, uint count, vec3 origin, vec3 direction,
                      float tmin, inout TraceHit best, inout TraceCost cost) {
    uint idBefore = best.triangleId;
    float tBefore = best.t;
    bool done = intersectLeaf(first, count, origin, direction, tmin, best, cost);
    if (best.triangleId != idBefore || best.t != tBefore) {
        changedLeaf = node;
#ifdef CHCRT_CULLING_DEBUG_SUBTREES
        // A hit in the hinted leaf was found by no listed subtree (0 in the image).
        changedBy = entry == CHCRT_CELL_HINT_ENTRY ? 0u : texelFetch(cellIds, int(entry)).x + 1u;
#endif
    }
    return done;
}
#endif
#include "culling/cell_list_traverse.glsl"
#include "culling/debug_cost.glsl"


// Traces the ray of `pixel` through the list of `cellIndex` (its cell), continuing from the stored hit.
void traceCellPixel(ivec2 pixel, int cellIndex) {
    vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
    vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
#if CHCRT_CELL_PASS_WRITES_ALL
    const uvec4 stored = uvec4(floatBitsToUint(CHCRT_NO_HIT_T), CHCRT_NO_HIT_ID, 0u, 0u); // = missHitTexel()
#else
    uvec4 stored = imageLoad(hitImage, pixel);
#endif
#if TRACE_ANY_HIT
    if (stored.y != CHCRT_NO_HIT_ID) {
        return; // finished (the mask keeps most such rays out already)
    }
#endif
    uvec2 header = texelFetch(cellHeaders, cellIndex).xy;
#ifdef CHCRT_CULLING_DEBUG_BATCHES
    imageAtomicAdd(debugImage, pixel, header.y);
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
    // Hit hints: the leaf of the ray's hit in the previous trace of its ray set first (once: not after the hint pass,
    // nor in a later round of a ray that has a hit), as the first root of its list traversal; a hit there finishes an
    // any-hit ray and bounds a closest-hit ray's traversal from its start.
#if CHCRT_CULLING_HINTS && !CHCRT_CULLING_HINTS_VISITED
    uint hintLeaf = imageLoad(hintImage, pixel).x;
    bool visitHint = hintLeaf != CHCRT_NO_HIT_ID && stored.y == CHCRT_NO_HIT_ID;
    if (!visitHint) {
        hintLeaf = CHCRT_NO_HIT_ID;
    }
#else
    const bool visitHint = false; // no hints, or the hint pass visited them (culling/hint_pass.h)
    const uint hintLeaf = CHCRT_NO_HIT_ID;
#endif
    traverseCellList(hintLeaf, header.x, header.x + header.y, originTmin.xyz, directionTmax.xyz, originTmin.w, best,
                     cost);
    if (cost.iterations >= CHCRT_TRACE_ITERATION_CAP) {
        atomicCounterIncrement(cappedRays);
    }
#ifdef CHCRT_CULLING_DEBUG_COST
    addCostSteps(pixel, cost);
#endif
    if (best.triangleId == previousId && best.t == previousT) {
#if CHCRT_CULLING_HINTS
        if (visitHint) {
            imageStore(hintImage, pixel, uvec4(CHCRT_NO_HIT_ID)); // a hint that no longer hits is dropped
        }
#endif
#if CHCRT_CELL_PASS_WRITES_ALL
        imageStore(hitImage, pixel, stored); // the miss, which no clear wrote
#endif
        return; // nothing nearer in these subtrees
    }
#ifdef CHCRT_CULLING_DEBUG_SUBTREES
    imageStore(debugImage, pixel, uvec4(changedBy));
#ifdef CHCRT_HIT_TRIANGLE_INDEX
    imageStore(hitTriangleImage, pixel, uvec4(best.triangleIndex));
#endif
#endif
    imageStore(hitImage, pixel, uvec4(floatBitsToUint(best.t), best.triangleId, floatBitsToUint(best.barycentrics)));
#if CHCRT_CULLING_HINTS
    imageStore(hintImage, pixel, uvec4(changedLeaf));
#endif
}
