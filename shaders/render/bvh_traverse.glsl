// Stack-based while-while BVH traversal (Aila & Laine 2009, as used by CHC+RT §5.2): the inner loop descends
// inner nodes testing both children, visiting the nearer first and pushing the farther with its entry
// distance; the leaf loop tests the leaf's triangles. Node and triangle data come from texture buffers
// (layout: shared/bvh_layout.h). The C++ twin is renderer/bvh/cpu_tracer.cpp.
//
// Host defines: TRACE_ANY_HIT (1: return the first hit in [tmin, tmax], for shadow and AO rays).
// CHCRT_LS_MODE (default 0 = off): a nonzero mode replaces traverseBvh by the Line Space traversal of
// linespace/linespace_traverse.glsl (exact empty-space skipping, shadow termination, representative candidates;
// defines and bindings from linespace/linespace_gpu.h). Off, this file is the pure tracer, unchanged.
//
// Determinism: a hit is accepted when tmin <= t <= best t, and on equal t the lower original triangle id
// wins; nodes are pruned only when their entry distance is beyond pruneLimit(best t) (shared/intersect.h), so a
// tie in a later subtree is still found, whatever the traversal order. Every tracer of the project (GLSL, CPU, CHC+RT subtrees) applies the same rule.
//
// llvmpipe ends all loops of an invocation after 65,535 iterations in total (PLATFORM.md): every loop here
// counts into traceIterations and stops at CHCRT_TRACE_ITERATION_CAP; the caller reports capped rays.
#include "shared/bvh_layout.h"
#include "shared/intersect.h"

layout(binding = CHCRT_UNIT_BVH_NODES) uniform samplerBuffer bvhNodes;
layout(binding = CHCRT_UNIT_BVH_TRIANGLES) uniform samplerBuffer bvhTriangles;

struct TraceHit {
    float t;
    uint triangleId; // original id, CHCRT_NO_HIT_ID for a miss
    vec2 barycentrics;
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
    return hit;
}

// Tests the triangles [first, first + count) of the BVH-ordered buffer against the ray, updating `best`.
// Returns true when an any-hit query can stop.
bool intersectLeaf(uint first, uint count, vec3 origin, vec3 direction, float tmin, inout TraceHit best,
                   inout TraceCost cost) {
    for (uint i = 0u; i < count && cost.iterations < CHCRT_TRACE_ITERATION_CAP; ++i) {
        ++cost.iterations;
        ++cost.triangles;
        int texel = int(first + i) * CHCRT_TRI_TEXELS_PER_TRIANGLE;
        vec4 v0 = texelFetch(bvhTriangles, texel);
        vec4 v1 = texelFetch(bvhTriangles, texel + 1);
        vec4 v2 = texelFetch(bvhTriangles, texel + 2);
        vec3 tuv = intersectRayTriangle(origin, direction, v0.xyz, v1.xyz, v2.xyz);
        uint id = floatBitsToUint(v0.w);
        if (tuv.x >= tmin && tuv.x <= best.t && (tuv.x < best.t || id < best.triangleId)) {
            best.t = tuv.x;
            best.triangleId = id;
            best.barycentrics = tuv.yz;
#if TRACE_ANY_HIT
            return true;
#endif
        }
    }
    return false;
}

#if defined(CHCRT_LS_MODE) && CHCRT_LS_MODE != 0
#include "linespace/linespace_traverse.glsl"
#else
// Traverses the subtree rooted at `root` (its box is tested first). `best` carries the closest hit so far
// (initialise with makeMiss(tmax)), so several subtrees can be traced one after another into one result.
void traverseBvh(uint root, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    vec3 invDir = safeInverseDirection(direction);
    vec4 root0 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE);
    vec4 root1 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE + 1);
    if (!rayHitsAabb(intersectRayAabb(origin, invDir, root0.xyz, root1.xyz), tmin, pruneLimit(best.t))) {
        return;
    }
    uint nodeFirst = floatBitsToUint(root0.w);
    uint nodeCount = floatBitsToUint(root1.w);
    // The stack holds node indices and entry distances only; a popped node's header is fetched again. Keeping
    // the child's (first, count) on the stack instead costs a third local array, and local arrays are the
    // expensive part on llvmpipe (measured: 2x slower for primary rays on the 1M city, docs/benchmarks.md).
    uint stackNode[CHCRT_MAX_BVH_DEPTH];
    float stackEntry[CHCRT_MAX_BVH_DEPTH];
    int stackSize = 0;
    bool traversing = true;
#include "render/bvh_traverse_loop.glsl"
}
#endif
