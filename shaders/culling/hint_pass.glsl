// CHC+RT hint pass (culling/hint_pass.h), the part shared by its compute pass (chcrt_hints.comp.glsl) and its
// fragment pass (chcrt_hints.frag.glsl): every active ray visits the leaf of its hit hint (culling/README.md,
// "Hit hints") before anything else of the trace, and a hit there is stored.
//  - Any-hit rays: that hit finishes the ray, and the ray bounds reduction that follows leaves it out. Every other
//    active ray drops its hint (it no longer hits) and is appended to the compaction buffer, so that the cell lists
//    are traversed by a dispatch over exactly those rays (chcrt_cells_compact.comp.glsl): when a few rays of a cell
//    miss their hints, the others no longer wait for them in every loop of the traversal, as SIMD lanes do in a
//    pass over all rays. The cell of every listed ray is marked and listed once, so that the reduction runs over
//    the cells left with a ray to trace and no others.
//  - Closest-hit rays: the hit bounds the ray (a nearer one may still exist), so the reduction that follows ends
//    its segment there — the "hit-bounded ray bounds" a primary ray otherwise gets only after its cell lists were
//    traced — and the cell lists hold only the subtrees the shortened segments reach. Every ray is traced by the
//    cell pass; the buffer only counts the rays whose hint missed (for the tracer's record of the pass).
// Host defines: TRACE_ANY_HIT (0 | 1), CHCRT_CULLING_DEBUG_COST (add the hint visits' steps to the cost debug image),
// CHCRT_CULLING_HINT_MARKS (0 | 1: mark and list the cells of the rays left, for a reduction over those cells; a
// trace whose lists are made without that reduction, e.g. shared shadow lists, leaves the atomics out).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/culling_layout.h"
#include "render/bvh_nodes.glsl"
#ifndef CHCRT_CULLING_HINT_MARKS
#define CHCRT_CULLING_HINT_MARKS 1
#endif

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform writeonly uimage2D hitImage;
layout(binding = CHCRT_CULLING_IMAGE_HINT, r32ui) uniform uimage2D hintImage;
#ifdef CHCRT_CULLING_DEBUG_COST
layout(binding = CHCRT_CULLING_IMAGE_DEBUG, r32ui) uniform coherent uimage2D debugImage;
#endif
layout(std430, binding = CHCRT_CULLING_COMPACT_BUFFER) buffer Compaction {
    uint dispatchGroups; // the indirect dispatch command: (dispatchGroups, 1, 1)
    uint dispatchY;
    uint dispatchZ;
    uint listed; // rays listed in pixels[]
    uint pixels[];
};
layout(std430, binding = CHCRT_CULLING_COMPACT_CELLS) buffer CellMarks {
    uint cellMarks[]; // CHCRT_CULLING_COMPACT_CELLS layout: marks, dispatch command and count, marked cells
};

uniform int cellsX;   // the ray bounds grid's cells per row
uniform int cellCount; // and all of them
uniform int cellSize; // and their edge in pixels

#include "culling/hint_leaf.glsl"
#include "culling/debug_cost.glsl"

// The hint visit of the ray of `pixel`: stores a hit found there, or drops the hint and lists the ray.
void visitHintOfPixel(ivec2 pixel) {
    vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
    vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
    if (!(directionTmax.w > originTmin.w)) {
        return; // inactive (NaN counts as inactive, as in every tracer)
    }
    TraceHit best = makeMiss(directionTmax.w);
    TraceCost cost = TraceCost(0u, 0u, 0u, 0u);
    uint hintLeaf = imageLoad(hintImage, pixel).x;
#if CHCRT_CULLING_HINT_SLOTS
    // Out of core: a hint whose cache slot changed since is dropped unvisited (its node may hold another subtree).
    bool valid = hintLeaf != CHCRT_NO_HIT_ID && !hintSlotReplaced(hintLeaf);
#else
    bool valid = hintLeaf != CHCRT_NO_HIT_ID;
#endif
    if (valid) {
        visitHintLeaf(hintLeaf, originTmin.xyz, directionTmax.xyz, originTmin.w, best, cost);
    }
#ifdef CHCRT_CULLING_DEBUG_COST
    addCostSteps(pixel, cost);
#endif
    if (best.triangleId != CHCRT_NO_HIT_ID) {
        imageStore(hitImage, pixel, uvec4(floatBitsToUint(best.t), best.triangleId, floatBitsToUint(best.barycentrics)));
        return; // any-hit: finished; closest-hit: bounded. The hint stays
    }
    if (hintLeaf != CHCRT_NO_HIT_ID) {
        imageStore(hintImage, pixel, uvec4(CHCRT_NO_HIT_ID)); // a hint that no longer hits (or is stale) is dropped
    }
    uint slot = atomicAdd(listed, 1u);
    if (slot % uint(CHCRT_CULLING_COMPACT_GROUP) == 0u) {
        atomicAdd(dispatchGroups, 1u);
    }
    pixels[slot] = uint(pixel.x) | (uint(pixel.y) << 16);
#if CHCRT_CULLING_HINT_MARKS
    ivec2 cell = pixel / cellSize;
    uint index = uint(cell.y * cellsX + cell.x);
    if (atomicExchange(cellMarks[index], 1u) == 0u) { // the cell's first listed ray lists the cell
        uint header = uint(CHCRT_CULLING_MARKED_HEADER(cellCount));
        uint marked = atomicAdd(cellMarks[header + 3u], 1u);
        if (marked % uint(CHCRT_CULLING_MARKED_GROUP) == 0u) {
            atomicAdd(cellMarks[header], 1u);
        }
        cellMarks[uint(CHCRT_CULLING_MARKED_LIST(cellCount)) + marked] = index;
    }
#endif
}
