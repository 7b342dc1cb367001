// BVH node and triangle access for every traversal (pure, CHC+RT subtrees, Line Space, N-tree): the texture
// buffers (layout: shared/bvh_layout.h), the hit and cost records, and the leaf test with the project's hit rule.
// The traversals themselves: render/bvh_traverse.glsl (pure), linespace/linespace_traverse.glsl, culling/*.
// The C++ twin is renderer/bvh/cpu_tracer.cpp.
//
// Host defines: TRACE_ANY_HIT (1: return the first hit in [tmin, tmax], for shadow and AO rays),
// CHCRT_HIT_TRIANGLE_INDEX (TraceHit also carries the hit triangle's index in the BVH-ordered buffer: the
// out-of-core primary trace records it, culling/outofcore/primary_resolve.h), CHCRT_COMPACT_SUBTREES (1: the
// buffers hold the compact subtree layout of the out-of-core cache, shared/bvh_layout.h; every traversal then starts
// at a subtree root, whose box sets the quantization frame the nodes below it are decoded in).
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
#ifndef CHCRT_COMPACT_SUBTREES
#define CHCRT_COMPACT_SUBTREES 0
#endif
#if CHCRT_COMPACT_SUBTREES
layout(binding = CHCRT_UNIT_BVH_NODES) uniform usamplerBuffer bvhNodes;
layout(binding = CHCRT_UNIT_BVH_TRIANGLES) uniform usamplerBuffer bvhCompactTriangles;
layout(binding = CHCRT_UNIT_BVH_VERTICES) uniform samplerBuffer bvhVertices;

// The subtree being traversed (setNodeFrame): its root's boundsMin and steps (the quantization frame), and where its
// nodes (its root), triangles and vertices start in their buffers (the local indices' bases).
vec3 nodeFrameOrigin = vec3(0.0f);
vec3 nodeFrameStep = vec3(0.0f);
uint nodeFrameRoot = 0u;
uint nodeFrameTriangles = 0u;
uint nodeFrameVertices = 0u;

void setNodeFrame(uint root, uvec4 root0, uvec4 root1) {
    uvec4 root2 = texelFetch(bvhNodes, int(root) + 2);
    nodeFrameOrigin = uintBitsToFloat(root0.xyz);
    // Power-of-two steps (0 on a flat axis): q * step is exact, so origin + q * step rounds once, as on the CPU.
    nodeFrameStep = uintBitsToFloat(uvec3(root1.w, root2.zw));
    nodeFrameRoot = root;
    nodeFrameTriangles = root2.x;
    nodeFrameVertices = root2.y;
}
void setNodeFrame(uint root) {
    setNodeFrame(root, texelFetch(bvhNodes, int(root)), texelFetch(bvhNodes, int(root) + 1));
}
vec3 compactLower(uvec4 node) {
    return nodeFrameOrigin + vec3(node.x & 0xFFFFu, node.x >> 16, node.y & 0xFFFFu) * nodeFrameStep;
}
vec3 compactUpper(uvec4 node) {
    return nodeFrameOrigin + vec3(node.y >> 16, node.z & 0xFFFFu, node.z >> 16) * nodeFrameStep;
}
// A header's children (inner) or triangles (leaf) in the buffers: the local index from the current subtree's bases.
uint compactCount(uint header) { return header >> CHCRT_COMPACT_INDEX_BITS; }
uint compactFirst(uint header) {
    return (header & CHCRT_COMPACT_INDEX_MASK) + (compactCount(header) == 0u ? nodeFrameRoot : nodeFrameTriangles);
}
#else
#include "render/bvh_triangles.glsl"
layout(binding = CHCRT_UNIT_BVH_NODES) uniform samplerBuffer bvhNodes;
#endif

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

// Tests the triangles [first, first + count) of the BVH-ordered buffer against the ray, updating `best` with the
// project's hit rule (shared/intersect.h, hitRule: the triangle's bounding box met, t at least its entry; lower id on
// equal t). Returns true when an any-hit query can stop.
bool intersectLeaf(uint first, uint count, vec3 origin, vec3 direction, float tmin, inout TraceHit best,
                   inout TraceCost cost) {
    for (uint i = 0u; i < count && CHCRT_BELOW_ITERATION_CAP(cost); ++i) {
        CHCRT_COUNT_ITERATION(cost);
        ++cost.triangles;
#if CHCRT_COMPACT_SUBTREES
        uvec4 triangle = texelFetch(bvhCompactTriangles, int(first + i));
        vec3 p0 = texelFetch(bvhVertices, int(nodeFrameVertices + triangle.x)).xyz;
        vec3 p1 = texelFetch(bvhVertices, int(nodeFrameVertices + triangle.y)).xyz;
        vec3 p2 = texelFetch(bvhVertices, int(nodeFrameVertices + triangle.z)).xyz;
        uint id = triangle.w;
#else
        int texel = int(first + i) * CHCRT_TRI_TEXELS_PER_TRIANGLE;
        vec4 v0 = triangleTexel(texel);
        vec3 p0 = v0.xyz;
        vec3 p1 = triangleTexel(texel + 1).xyz;
        vec3 p2 = triangleTexel(texel + 2).xyz;
        uint id = floatBitsToUint(v0.w);
#endif
        vec3 tuv = intersectRayTriangle(origin, direction, p0, p1, p2);
        if (tuv.x >= tmin && tuv.x <= best.t) {
            vec2 rule = hitRule(tuv.x, tmin, origin, safeInverseDirection(direction), p0, p1, p2);
            float t = rule.x;
            if (rule.y != 0.0f && t <= best.t && (t < best.t || id < best.triangleId)) {
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
    }
    return false;
}
// Starts a traversal at `root`: its header (nodeFirst, nodeCount) when the ray meets its box within
// [tmin, pruneLimit(bestT)], else false (nothing below it can change the hit).
// Compact layout: also sets the root's quantization frame.
bool enterRoot(uint root, vec3 origin, vec3 invDir, float tmin, float bestT, out uint nodeFirst, out uint nodeCount,
               out float entry) {
#if CHCRT_COMPACT_SUBTREES
    uvec4 root0 = texelFetch(bvhNodes, int(root));
    uvec4 root1 = texelFetch(bvhNodes, int(root) + 1);
    setNodeFrame(root, root0, root1);
    nodeFirst = compactFirst(root0.w);
    nodeCount = compactCount(root0.w);
    vec2 entryExit = intersectRayAabb(origin, invDir, uintBitsToFloat(root0.xyz), uintBitsToFloat(root1.xyz));
    entry = entryExit.x;
#else
    vec4 root0 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE);
    vec4 root1 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE + 1);
    nodeFirst = floatBitsToUint(root0.w);
    nodeCount = floatBitsToUint(root1.w);
    vec2 entryExit = intersectRayAabb(origin, invDir, root0.xyz, root1.xyz);
#endif
    entry = entryExit.x;
    return rayHitsAabb(entryExit, tmin, pruneLimit(bestT));
}
#endif
