// Line Space use inside BVH traversal: a replacement of render/bvh_traverse.glsl that the Line Space methods name
// as the passes' traversal (CHCRT_BVH_TRAVERSAL, defines of linespace/linespace_gpu.h). A Line Space node is a BVH node of the cut chosen by depth D and triangle threshold T
// (linespace/linespace_build.h); traversal asks lsVisitNode() what to do when the ray reaches one.
//
// Host defines (linespace/linespace_gpu.h LineSpaceGpu::defines()):
//   CHCRT_LS_MODE                      CHCRT_LS_MODE_EXACT | _SHADOW | _CANDIDATE (linespace_bindings.h)
//   CHCRT_LS_N                         patches per face edge, e.g. 6u
//   CHCRT_LS_BINARY_WORDS_PER_SPACE    lsShaftCount(N, true) / 32 rounded up, e.g. 608u
//   CHCRT_LS_CANDIDATE_WORDS_PER_SPACE lsShaftCount(N, false) / 32 rounded up (candidate mode)
//   CHCRT_LS_COS_MAX_ANGLE             cos of the normal-angle threshold (candidate mode), e.g. 0.866
//   CHCRT_LS_CANDIDATE_START_EXACT     1: the node a candidate ray starts in is traversed exactly (default 0)
//   CHCRT_LS_CANDIDATE_FRONT_ONLY      candidate planes count only when the ray meets their front side: 0 never
//                                      (default, the paper), 1 in the node the ray starts in, 2 in every node
//   CHCRT_LS_CANDIDATE_NO_LEAVES       1: candidate traversal from the BVH root over Line Spaces none of which is a
//                                      BVH leaf, so no ray reaches a leaf and the leaf test is compiled out (default
//                                      0). Same hits; llvmpipe runs the leaf loop's body once per outer iteration
//                                      even when no ray is at a leaf (docs/architecture.md). Not for CHC+RT
//                                      subtrees, whose roots below the cut traverse down to leaves.
// Needs render/bvh_nodes.glsl (included first by the pass).
#include "shared/linespace_bindings.h"
#include "shared/linespace_layout.h"
#include "linespace/shaft_index_fast.glsl"

#ifndef CHCRT_LS_CANDIDATE_START_EXACT
#define CHCRT_LS_CANDIDATE_START_EXACT 0
#endif
#ifndef CHCRT_LS_CANDIDATE_FRONT_ONLY
#define CHCRT_LS_CANDIDATE_FRONT_ONLY 0
#endif
#ifndef CHCRT_LS_CANDIDATE_NO_LEAVES
#define CHCRT_LS_CANDIDATE_NO_LEAVES 0
#endif
#if CHCRT_LS_CANDIDATE_NO_LEAVES && (CHCRT_LS_MODE != CHCRT_LS_MODE_CANDIDATE || CHCRT_LS_CANDIDATE_START_EXACT)
#error "CHCRT_LS_CANDIDATE_NO_LEAVES needs candidate mode without exact start nodes"
#endif

layout(binding = CHCRT_UNIT_LS_SPACE_OF_NODE) uniform usamplerBuffer lsSpaceOfNode;
layout(binding = CHCRT_UNIT_LS_BINARY_WORDS) uniform usamplerBuffer lsBinaryWords;
#if CHCRT_LS_MODE == CHCRT_LS_MODE_CANDIDATE
layout(binding = CHCRT_UNIT_LS_CANDIDATE_WORDS) uniform usamplerBuffer lsCandidateWords;
layout(binding = CHCRT_UNIT_LS_CANDIDATE_OFFSETS) uniform usamplerBuffer lsCandidateOffsets;
layout(binding = CHCRT_UNIT_LS_CANDIDATE_DATA) uniform usamplerBuffer lsCandidateData;
layout(binding = CHCRT_UNIT_LS_VERTEX_NORMALS) uniform usamplerBuffer lsVertexNormals;
#endif

// The Line Space of BVH node `node`, or CHCRT_LS_NO_SPACE when the node is not on the cut.
uint lsSpaceOf(uint node) {
    return texelFetch(lsSpaceOfNode, int(node)).x;
}

// Binary bit of the ray's shaft in Line Space `space` (box = the node's bounds). A line that misses the box
// (impossible after a box hit, kept for safety) counts as filled: skipping must stay conservative.
bool lsBinaryBit(uint space, vec3 origin, vec3 direction, vec3 invDir, vec3 boxMin, vec3 boxMax) {
    uint shaft = lsShaftIndexFast(origin, direction, invDir, boxMin, boxMax, CHCRT_LS_N, true);
    if (shaft == CHCRT_LS_NO_SHAFT) {
        return true;
    }
    uint word = texelFetch(lsBinaryWords, int(space * CHCRT_LS_BINARY_WORDS_PER_SPACE + shaft / 32u)).x;
    return ((word >> (shaft & 31u)) & 1u) != 0u;
}

#if CHCRT_LS_MODE == CHCRT_LS_MODE_CANDIDATE
vec3 lsDecodeNormal(uint encoded) {
    // Octahedral encoding in two snorm16 (linespace_gpu.cpp encodeOctahedral).
    vec2 e = unpackSnorm2x16(encoded);
    vec3 n = vec3(e, 1.0f - abs(e.x) - abs(e.y));
    if (n.z < 0.0f) {
        n.xy = (1.0f - abs(n.yx)) * vec2(n.x >= 0.0f ? 1.0f : -1.0f, n.y >= 0.0f ? 1.0f : -1.0f);
    }
    return normalize(n);
}

// RC Algorithm 1 at one Line Space node: the candidate of the ray's (non-symmetric) shaft is intersected as an
// infinite plane within [max(tmin, tEntry), min(best.t, tExit)]; the hit is discarded when the normal
// interpolated with the (extrapolated) barycentrics deviates from the triangle's mean normal by more than the
// threshold angle (§3.1, edge detection). Twin of linespace/candidate_linespace.cpp intersectCandidatePlane.
bool lsCandidateHit(uint space, vec3 origin, vec3 direction, vec3 invDir, vec3 boxMin, vec3 boxMax, vec2 entryExit,
                    float tmin, inout TraceHit best) {
    uint shaft = lsShaftIndexFast(origin, direction, invDir, boxMin, boxMax, CHCRT_LS_N, false);
    if (shaft == CHCRT_LS_NO_SHAFT) {
        return false;
    }
    int w = int(space * CHCRT_LS_CANDIDATE_WORDS_PER_SPACE + shaft / 32u);
    uint slot = lsSparseSlot(texelFetch(lsCandidateWords, w).x, texelFetch(lsCandidateOffsets, w).x, shaft);
    if (slot == CHCRT_LS_EMPTY_SLOT) {
        return false;
    }
    uint triangle = texelFetch(lsCandidateData, int(slot)).x;
    int texel = int(triangle) * CHCRT_TRI_TEXELS_PER_TRIANGLE;
    vec4 v0 = triangleTexel(texel);
    vec3 v1 = triangleTexel(texel + 1).xyz;
    vec3 v2 = triangleTexel(texel + 2).xyz;
    vec3 e1 = v1 - v0.xyz;
    vec3 e2 = v2 - v0.xyz;
    vec3 p = cross(direction, e2);
    float det = dotOrdered(e1, p);
    // det = -dot(direction, cross(e1, e2)): positive when the ray meets the plane's front (counter-clockwise)
    // side. CHCRT_LS_CANDIDATE_FRONT_ONLY rejects back sides (our addition): a ray leaving a convex surface
    // crosses the extended planes of its neighbouring triangles from behind, which is the self-occlusion of
    // `candidate` mode; a ray coming from outside a closed surface meets front sides only.
#if CHCRT_LS_CANDIDATE_FRONT_ONLY == 2
    bool frontOnly = true;
#elif CHCRT_LS_CANDIDATE_FRONT_ONLY == 1
    bool frontOnly = entryExit.x <= tmin; // the node the ray starts in: where the self-occlusion is (measured)
#else
    bool frontOnly = false;
#endif
    if (det == 0.0f || (frontOnly && !(det > 0.0f))) {
        return false;
    }
    float invDet = 1.0f / det;
    vec3 s = origin - v0.xyz;
    vec3 q = cross(s, e1);
    float u = dotOrdered(s, p) * invDet;
    float v = dotOrdered(direction, q) * invDet;
    float t = dotOrdered(e2, q) * invDet;
    uint id = floatBitsToUint(v0.w);
    if (!(t >= max(tmin, entryExit.x) && t <= min(best.t, entryExit.y)) || (t == best.t && id >= best.triangleId)) {
        return false;
    }
    uvec4 normals = texelFetch(lsVertexNormals, int(triangle));
    vec3 interpolated = (1.0f - u - v) * lsDecodeNormal(normals.x) + u * lsDecodeNormal(normals.y) +
                        v * lsDecodeNormal(normals.z);
    vec3 mean = lsDecodeNormal(normals.w);
    float len = length(interpolated);
    if (!(len > 0.0f) || dot(interpolated, mean) < CHCRT_LS_COS_MAX_ANGLE * len) {
        return false;
    }
    best.t = t;
    best.triangleId = id;
    best.barycentrics = vec2(u, v);
    return true;
}
#endif

// What the traversal does at Line Space node `space` (bounds boxMin/boxMax, `isLeaf`, entry/exit of the ray's
// line in entryExit) that the ray [tmin, best.t] hits. Returns true when the node must be traversed exactly;
// sets `stop` when the ray is finished (shadow termination, or an any-hit candidate).
bool lsVisitNode(uint space, vec3 boxMin, vec3 boxMax, bool isLeaf, vec2 entryExit, vec3 origin, vec3 direction,
                 vec3 invDir, float tmin, inout TraceHit best, inout bool stop) {
#if CHCRT_LS_MODE == CHCRT_LS_MODE_EXACT
    // The ray lies in the shaft of its line; an empty shaft holds no geometry of the subtree (conservative
    // build), so skipping is exact, also for rays starting inside the node.
    return lsBinaryBit(space, origin, direction, invDir, boxMin, boxMax);
#elif CHCRT_LS_MODE == CHCRT_LS_MODE_SHADOW
    if (!lsBinaryBit(space, origin, direction, invDir, boxMin, boxMax)) {
        return false; // empty: exact skip
    }
    // SS §4.1: the shaft of the node the ray starts in says nothing about the ray (its geometry may lie behind
    // the origin): traverse that node exactly. Leaves (< T triangles) are cheaper to test than to guess.
    if (entryExit.x <= tmin || isLeaf) {
        return true;
    }
    best.t = max(entryExit.x, tmin);
    best.triangleId = CHCRT_LS_OCCLUDED_ID;
    best.barycentrics = vec2(0.0f);
    stop = true;
    return false;
#else // CHCRT_LS_MODE_CANDIDATE
    // RC §3.2: Line Space nodes act as leaves for indirect rays, also the one the ray starts in (its own surface
    // is excluded by tmin and the plane's t). CHCRT_LS_CANDIDATE_START_EXACT = 1 traverses that node exactly
    // instead (SS §4.1 applied to candidates: fewer self-occlusion errors, slower). Small leaves (< T triangles)
    // are cheaper to test exactly than to approximate.
#if CHCRT_LS_CANDIDATE_START_EXACT
    if (entryExit.x <= tmin) {
        return true;
    }
#endif
    if (isLeaf) {
        return true;
    }
    if (lsCandidateHit(space, origin, direction, invDir, boxMin, boxMax, entryExit, tmin, best)) {
#if TRACE_ANY_HIT
        stop = true;
#endif
    }
    return false;
#endif
}

// Stack entries of nodes below the Line Space cut carry this bit (node indices stay below 2^31).
#define CHCRT_LS_BELOW_CUT_BIT 0x80000000u

// The traversal's visit of Line Space node `space` (BVH node `node`, whose header count is `nodeCount`): an action
// of render/bvh_traverse_loop.glsl. Descending goes below the cut (no further Line Space nodes).
int lsVisitCutNode(uint node, inout uint space, inout bool aboveCut, uint nodeCount, vec3 origin, vec3 direction,
                   vec3 invDir, float tmin, inout TraceHit best) {
    int texel = int(node) * CHCRT_BVH_TEXELS_PER_NODE;
    vec3 boxMin = texelFetch(bvhNodes, texel).xyz;
    vec3 boxMax = texelFetch(bvhNodes, texel + 1).xyz;
    bool stop = false;
    bool descend = lsVisitNode(space, boxMin, boxMax, nodeCount != 0u, intersectRayAabb(origin, invDir, boxMin, boxMax),
                               origin, direction, invDir, tmin, best, stop);
    space = CHCRT_LS_NO_SPACE;
    if (stop) {
        return 0; // TRAVERSE_ACTION_RETURN
    }
    if (descend) {
        aboveCut = false;
        return 1; // TRAVERSE_ACTION_DESCEND
    }
    return 2; // TRAVERSE_ACTION_POP
}

// traverseBvh of render/bvh_traverse.glsl with Line Space nodes. The while-while loop of the pure tracer
// (render/bvh_traverse_loop.glsl) with hooks: a Line Space node ends the inner (descending) loop like a leaf does,
// and its shaft is handled in one place after the loop, where the rays of a SIMD group that reached such nodes do
// it together (Aila and Laine's reason for the while-while loop; handling both children in the inner loop measured
// 1.7x slower for primary rays, docs/benchmarks.md). Same determinism rules as the pure tracer: nodes are pruned
// only beyond pruneLimit(best t), ties go to the lower original id. Above the cut, each node entered fetches its
// space.
void traverseBvh(uint root, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    vec3 invDir = safeInverseDirection(direction);
    uint nodeFirst, nodeCount;
    float nodeEntry;
    if (!enterRoot(root, origin, invDir, tmin, best.t, nodeFirst, nodeCount, nodeEntry)) {
        return;
    }
    uint currentNode = root;
    uint currentSpace = lsSpaceOf(root);
    bool aboveCut = currentSpace == CHCRT_LS_NO_SPACE;
    uint stackNode[CHCRT_MAX_BVH_DEPTH];
    float stackEntry[CHCRT_MAX_BVH_DEPTH];
    int stackSize = 0;
    bool traversing = true;
#define TRAVERSE_DESCEND_WHILE (currentSpace == CHCRT_LS_NO_SPACE)
#define TRAVERSE_ENTER(node) currentNode = (node);
#define TRAVERSE_AFTER_DESCEND if (aboveCut) { currentSpace = lsSpaceOf(currentNode); }
#define TRAVERSE_PUSH(node) ((node) | (aboveCut ? 0u : CHCRT_LS_BELOW_CUT_BIT))
#define TRAVERSE_STOP_NODE currentSpace != CHCRT_LS_NO_SPACE
#define TRAVERSE_VISIT_STOP_NODE \
    lsVisitCutNode(currentNode, currentSpace, aboveCut, nodeCount, origin, direction, invDir, tmin, best)
#define TRAVERSE_POPPED_NODE(word) ((word) & ~CHCRT_LS_BELOW_CUT_BIT)
#define TRAVERSE_POP(word) \
    currentNode = (word) & ~CHCRT_LS_BELOW_CUT_BIT; \
    aboveCut = ((word) & CHCRT_LS_BELOW_CUT_BIT) == 0u; \
    currentSpace = aboveCut ? lsSpaceOf(currentNode) : CHCRT_LS_NO_SPACE;
#define TRAVERSE_NO_LEAVES CHCRT_LS_CANDIDATE_NO_LEAVES
#include "render/bvh_traverse_loop.glsl"
}
