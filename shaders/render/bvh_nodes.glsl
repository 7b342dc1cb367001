// BVH node and triangle access for every traversal (pure, CHC+RT subtrees, Line Space, N-tree): the texture
// buffers (layout: shared/bvh_layout.h), the hit and cost records, and the leaf test with the project's hit rule.
// The traversals themselves: render/bvh_traverse.glsl (pure), linespace/linespace_traverse.glsl, culling/*.
// The C++ twin is renderer/bvh/cpu_tracer.cpp.
//
// Host defines: TRACE_ANY_HIT (1: return the first hit in [tmin, tmax], for shadow and AO rays),
// CHCRT_HIT_TRIANGLE_INDEX (TraceHit also carries the hit triangle's index in the BVH-ordered buffer: the
// out-of-core primary trace records it, culling/outofcore/primary_resolve.h).
//
// Determinism: a hit is accepted when tmin <= t <= best t, and on equal t the lower original triangle id
// wins; nodes are pruned only when their entry distance is beyond pruneLimit(best t) (shared/intersect.h), so a
// tie in a later subtree is still found, whatever the traversal order. Every tracer of the project (GLSL, CPU,
// CHC+RT subtrees) applies the same rule.
//
// llvmpipe ends all loops of an invocation after 65,535 iterations in total: where the renderer needs it
// (CHCRT_TRACE_LOOP_CAP, shared/render_layout.h) every traversal loop counts into cost.iterations and stops at
// CHCRT_TRACE_ITERATION_CAP; the caller reports capped rays.
#ifndef CHCRT_BVH_NODES_GLSL
#define CHCRT_BVH_NODES_GLSL
#include "shared/bvh_layout.h"
#include "shared/intersect.h"
#include "render/bvh_triangles.glsl"

layout(binding = CHCRT_UNIT_BVH_NODES) uniform samplerBuffer bvhNodes;

struct TraceHit {
    float t;
    uint triangleId; // original id, CHCRT_NO_HIT_ID for a miss
    vec2 barycentrics;
#ifdef CHCRT_HIT_TRIANGLE_INDEX
    uint triangleIndex; // in the BVH-ordered triangle buffer; 0 for a miss
#endif
};

struct TraceCost {
    uint innerNodes;
    uint leaves;
    uint triangles;
    uint iterations;
};

TraceHit makeMiss(float tmax) {
    TraceHit hit;
    hit.t = tmax;
    hit.triangleId = CHCRT_NO_HIT_ID;
    hit.barycentrics = vec2(0.0f);
#ifdef CHCRT_HIT_TRIANGLE_INDEX
    hit.triangleIndex = 0u;
#endif
    return hit;
}

// Tests the triangles [first, first + count) of the BVH-ordered buffer against the ray, updating `best`.
// Returns true when an any-hit query can stop.
// `leafEntry`: the computed entry distance of the leaf's box (as the traversal computed it when it reached the leaf).
// A hit's t is clamped to it: an ill-conditioned triangle can be hit at a computed t before its own leaf's box (seen on
// the 1M plant: 224.27803 against a double-precision 224.283014, beyond pruneLimit's margin), and a leaf that one
// traversal order prunes would then hold a hit nearer than the best t another order keeps. With the clamp no pruned
// leaf holds a candidate at or below best t, so the hit never depends on the order (culling/README.md, "Exactness").
bool intersectLeaf(uint first, uint count, vec3 origin, vec3 direction, float tmin, float leafEntry,
                   inout TraceHit best, inout TraceCost cost) {
    for (uint i = 0u; i < count && CHCRT_BELOW_ITERATION_CAP(cost); ++i) {
        CHCRT_COUNT_ITERATION(cost);
        ++cost.triangles;
        int texel = int(first + i) * CHCRT_TRI_TEXELS_PER_TRIANGLE;
        vec4 v0 = triangleTexel(texel);
        vec4 v1 = triangleTexel(texel + 1);
        vec4 v2 = triangleTexel(texel + 2);
        vec3 tuv = intersectRayTriangle(origin, direction, v0.xyz, v1.xyz, v2.xyz);
        uint id = floatBitsToUint(v0.w);
        float t = max(tuv.x, leafEntry);
        if (tuv.x >= tmin && t <= best.t && (t < best.t || id < best.triangleId)) {
            best.t = t;
            best.triangleId = id;
            best.barycentrics = tuv.yz;
#ifdef CHCRT_HIT_TRIANGLE_INDEX
            best.triangleIndex = first + i;
#endif
#if TRACE_ANY_HIT
            return true;
#endif
        }
    }
    return false;
}
// Starts a traversal at `root`: its header (nodeFirst, nodeCount) when the ray meets its box within
// [tmin, pruneLimit(bestT)], else false (nothing below it can change the hit).
bool enterRoot(uint root, vec3 origin, vec3 invDir, float tmin, float bestT, out uint nodeFirst, out uint nodeCount,
               out float entry) {
    vec4 root0 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE);
    vec4 root1 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE + 1);
    nodeFirst = floatBitsToUint(root0.w);
    nodeCount = floatBitsToUint(root1.w);
    vec2 entryExit = intersectRayAabb(origin, invDir, root0.xyz, root1.xyz);
    entry = entryExit.x;
    return rayHitsAabb(entryExit, tmin, pruneLimit(bestT));
}
#endif
