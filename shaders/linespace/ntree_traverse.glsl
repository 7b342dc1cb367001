// Shadow-ray traversal of the N-tree with binary Line Spaces (soft-shadow paper "SS", Algorithm 1 and §4.1),
// made iterative: a 3D-DDA over the N^3 children of the current node and a stack of (node, cell) per level.
//
// At a subdivided node the ray reaches, the bit of the shaft of the ray's line decides (Algorithm 1, line 2):
//   - empty shaft: no geometry of the node lies on the line: the node is skipped (exact, also when the ray
//     starts inside: the ray is part of its line);
//   - occupied shaft at the shadow level (SS: "deep enough" = level d - 1, all children are leaves): the ray is
//     occluded (line 4; the approximation: it only adds occlusion) - unless the ray starts or ends inside the
//     node. SS §4.1: "the node where the ray starts has to be skipped"; the same holds where a ray ends (a light
//     inside the tree): the shaft's geometry may lie beyond the segment. CHCRT_NT_START_EXACT = 0 skips such a
//     node as the paper does (losing contact shadows); 1 traverses it exactly (its leaves' triangles), our
//     addition, which keeps every occluder the exact tracer finds;
//   - otherwise the ray's cells of the node are visited front to back (lines 6-7), empty cells skipped (line 8).
// Leaves (non-empty cells of level d) reached by exact traversal test their triangles for [tmin, tmax].
// CHCRT_NT_SHADOW_LEVEL >= d never terminates: the traversal is then an exact any-hit tracer (tests compare it
// with the BVH).
//
// Host defines (linespace/ntree_gpu.h NTreeGpu::defines()):
//   CHCRT_NT_N                       children per axis, e.g. 6u
//   CHCRT_NT_BINARY_WORDS_PER_SPACE  lsWordCount(N, true), e.g. 608u
//   CHCRT_NT_SHADOW_LEVEL            level whose occupied shafts terminate (paper: d - 1)
//   CHCRT_NT_START_EXACT             0 | 1, see above
//   CHCRT_NT_NEAR                    float: shadow-level nodes entered closer than NEAR node edges to the origin
//                                    are handled like the start node (default 0.0f = the paper)
// Needs triangleTexel, TraceHit, TraceCost and intersectRayTriangle from render/bvh_nodes.glsl (include it first).
#include "shared/linespace_bindings.h"
#include "shared/ntree_layout.h"
#include "linespace/shaft_index_fast.glsl"

#ifndef CHCRT_NT_START_EXACT
#define CHCRT_NT_START_EXACT 0
#endif
#ifndef CHCRT_NT_NEAR
#define CHCRT_NT_NEAR 0.0f
#endif

layout(binding = CHCRT_UNIT_NT_NODES) uniform samplerBuffer ntNodes;
layout(binding = CHCRT_UNIT_NT_TREE) uniform usamplerBuffer ntTree;
layout(binding = CHCRT_UNIT_NT_BINARY_WORDS) uniform usamplerBuffer ntBinaryWords;
layout(binding = CHCRT_UNIT_NT_LEAVES) uniform usamplerBuffer ntLeaves;
layout(binding = CHCRT_UNIT_NT_TRIANGLE_REFS) uniform usamplerBuffer ntTriangleRefs;

// Bit of the shaft of the ray's line in the Line Space of node `node` (a line missing the box counts as
// occupied: conservative).
bool ntShaftOccupied(uint node, vec3 origin, vec3 direction, vec3 invDir, vec3 boxMin, vec3 boxMax) {
    uint shaft = lsShaftIndexFast(origin, direction, invDir, boxMin, boxMax, CHCRT_NT_N, true);
    if (shaft == CHCRT_LS_NO_SHAFT) {
        return true;
    }
    uint word = texelFetch(ntBinaryWords, int(node * CHCRT_NT_BINARY_WORDS_PER_SPACE + shaft / 32u)).x;
    return ((word >> (shaft & 31u)) & 1u) != 0u;
}

// Parameter t at which the ray leaves cell `cell` of a node (lower corner, child edge) along each axis.
vec3 ntCellExits(ivec3 cell, vec3 lower, float childSize, vec3 origin, vec3 direction, vec3 invDir) {
    vec3 far = lower + vec3(cell + ivec3(greaterThan(direction, vec3(0.0f)))) * childSize;
    // An axis the ray does not move along is never left (safeInverse's 1e30 could give -1e30 here).
    return mix((far - origin) * invDir, vec3(3.0e38f), equal(direction, vec3(0.0f)));
}

// Any hit of the ray [tmin, tmax] among the leaf's triangles.
bool ntLeafHit(uint leaf, vec3 origin, vec3 direction, float tmin, float tmax, inout TraceHit best,
               inout TraceCost cost) {
    uvec2 range = texelFetch(ntLeaves, int(leaf)).xy;
    ++cost.leaves;
    for (uint i = 0u; i < range.y && CHCRT_BELOW_ITERATION_CAP(cost); ++i) {
        CHCRT_COUNT_ITERATION(cost);
        ++cost.triangles;
        int texel = int(texelFetch(ntTriangleRefs, int(range.x + i)).x) * CHCRT_TRI_TEXELS_PER_TRIANGLE;
        vec4 v0 = triangleTexel(texel);
        vec4 v1 = triangleTexel(texel + 1);
        vec4 v2 = triangleTexel(texel + 2);
        vec3 tuv = intersectRayTriangle(origin, direction, v0.xyz, v1.xyz, v2.xyz);
        if (tuv.x >= tmin && tuv.x <= tmax) {
            best.t = tuv.x;
            best.triangleId = floatBitsToUint(v0.w);
            best.barycentrics = tuv.yz;
            return true;
        }
    }
    return false;
}

// What the traversal does at subdivided node `node` of `level` (SS Algorithm 1, lines 2-5).
#define CHCRT_NT_SKIP 0     // missed, or empty shaft (exact), or the start/end node skipped (SS §4.1)
#define CHCRT_NT_OCCLUDED 1 // occupied shaft at the shadow level
#define CHCRT_NT_DESCEND 2  // visit its cells
int ntDecide(uint node, int level, vec3 origin, vec3 direction, vec3 invDir, float tmin, float tmax,
             out vec4 record, out vec2 entryExit) {
    record = texelFetch(ntNodes, int(node));
    vec3 boxMax = record.xyz + vec3(record.w);
    entryExit = intersectRayAabb(origin, invDir, record.xyz, boxMax);
    if (!rayHitsAabb(entryExit, tmin, tmax) || !ntShaftOccupied(node, origin, direction, invDir, record.xyz, boxMax)) {
        return CHCRT_NT_SKIP;
    }
    if (level == CHCRT_NT_SHADOW_LEVEL) {
        // CHCRT_NT_NEAR: nodes entered within this many node edges of the origin count as the start node too
        // (our addition against self-occlusion by the surface the ray leaves; 0 = the paper).
        if (entryExit.x > tmin + CHCRT_NT_NEAR * record.w && entryExit.y < tmax) {
            return CHCRT_NT_OCCLUDED;
        }
        return CHCRT_NT_START_EXACT != 0 ? CHCRT_NT_DESCEND : CHCRT_NT_SKIP; // SS §4.1: says nothing here
    }
    return CHCRT_NT_DESCEND;
}

// Any hit of the shadow ray [tmin, tmax]; `best` = the occluder (CHCRT_LS_OCCLUDED_ID with t = the node's entry
// for a terminating shaft). Returns true when occluded. One loop iteration visits one cell and steps the DDA to
// the next (or descends into the cell's node, or returns to the parent): every iteration does the same work, so
// llvmpipe's SIMD lanes stay together (a three-state loop, enter/visit/advance, measured slower).
bool ntreeOccluded(vec3 origin, vec3 direction, float tmin, float tmax, inout TraceHit best, inout TraceCost cost) {
    vec3 invDir = safeInverseDirection(direction);
    ivec3 stepDir = ivec3(sign(direction));
    uint stackNode[CHCRT_NT_MAX_DEPTH];
    uint stackCell[CHCRT_NT_MAX_DEPTH];
    int level = 0;
    uint node = 0u;
    vec4 record;
    vec2 entryExit;
    ++cost.innerNodes;
    int decision = ntDecide(0u, 0, origin, direction, invDir, tmin, tmax, record, entryExit);
    if (decision == CHCRT_NT_OCCLUDED) {
        best.t = entryExit.x;
        best.triangleId = CHCRT_LS_OCCLUDED_ID;
        best.barycentrics = vec2(0.0f);
        return true;
    }
    if (decision == CHCRT_NT_SKIP) {
        return false;
    }
    vec3 lower = record.xyz;
    float childSize = record.w / float(CHCRT_NT_N);
    float segmentEnd = min(entryExit.y, tmax);
    ivec3 cell = clamp(ivec3(floor((origin + max(entryExit.x, tmin) * direction - lower) / childSize)), ivec3(0),
                       ivec3(int(CHCRT_NT_N) - 1));
    vec3 exits = ntCellExits(cell, lower, childSize, origin, direction, invDir);
    bool visited = false; // the current cell was looked at (after returning from its node)
    while (CHCRT_BELOW_ITERATION_CAP(cost)) {
        CHCRT_COUNT_ITERATION(cost);
        if (!visited) {
            uint packedCell = uint(cell.x) + CHCRT_NT_N * (uint(cell.y) + CHCRT_NT_N * uint(cell.z));
            uint entry = texelFetch(ntTree, int(node * (CHCRT_NT_N * CHCRT_NT_N * CHCRT_NT_N) + packedCell)).x;
            if (entry != CHCRT_NT_EMPTY && (entry & CHCRT_NT_LEAF_BIT) != 0u) {
                if (ntLeafHit(entry & ~CHCRT_NT_LEAF_BIT, origin, direction, tmin, tmax, best, cost)) {
                    return true;
                }
            } else if (entry != CHCRT_NT_EMPTY) {
                ++cost.innerNodes;
                decision = ntDecide(entry, level + 1, origin, direction, invDir, tmin, tmax, record, entryExit);
                if (decision == CHCRT_NT_OCCLUDED) {
                    best.t = entryExit.x;
                    best.triangleId = CHCRT_LS_OCCLUDED_ID;
                    best.barycentrics = vec2(0.0f);
                    return true;
                }
                if (decision == CHCRT_NT_DESCEND) {
                    stackNode[level] = node;
                    stackCell[level] = packedCell;
                    ++level;
                    node = entry;
                    lower = record.xyz;
                    childSize = record.w / float(CHCRT_NT_N);
                    segmentEnd = min(entryExit.y, tmax);
                    cell = clamp(ivec3(floor((origin + max(entryExit.x, tmin) * direction - lower) / childSize)),
                                 ivec3(0), ivec3(int(CHCRT_NT_N) - 1));
                    exits = ntCellExits(cell, lower, childSize, origin, direction, invDir);
                    continue; // visit the child's first cell
                }
            }
        }
        // Step to the next cell along the ray, or out of the node (then its parent continues after its cell).
        float cellExit = min(exits.x, min(exits.y, exits.z));
        if (cellExit < segmentEnd) {
            if (exits.x == cellExit) {
                cell.x += stepDir.x;
            } else if (exits.y == cellExit) {
                cell.y += stepDir.y;
            } else {
                cell.z += stepDir.z;
            }
            if (all(greaterThanEqual(cell, ivec3(0))) && all(lessThan(cell, ivec3(int(CHCRT_NT_N))))) {
                exits = ntCellExits(cell, lower, childSize, origin, direction, invDir);
                visited = false;
                continue;
            }
        }
        if (level == 0) {
            return false;
        }
        --level;
        node = stackNode[level];
        uint packedParent = stackCell[level];
        cell = ivec3(int(packedParent % CHCRT_NT_N), int((packedParent / CHCRT_NT_N) % CHCRT_NT_N),
                     int(packedParent / (CHCRT_NT_N * CHCRT_NT_N)));
        vec4 parent = texelFetch(ntNodes, int(node));
        lower = parent.xyz;
        childSize = parent.w / float(CHCRT_NT_N);
        segmentEnd = min(intersectRayAabb(origin, invDir, parent.xyz, parent.xyz + vec3(parent.w)).y, tmax);
        exits = ntCellExits(cell, lower, childSize, origin, direction, invDir);
        visited = true;
    }
    return false;
}

// The N-tree as the traversal of the full-screen tracer (render/trace_bvh.frag.glsl names this file through
// CHCRT_BVH_TRAVERSAL, linespace/ntree_gpu.h): shadow rays only, from the N-tree's root (`root` is unused).
void traverseBvh(uint root, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    ntreeOccluded(origin, direction, tmin, best.t, best, cost);
}
