// CHC+RT §5.2 batch traversal over a cell's list of termination-subtree roots (culling/cell_traversal.h): the loop of
// render/bvh_traverse_loop.glsl, which takes the next root of the list whenever its stack runs empty, so one
// traversal with one stack of a subtree's height visits any number of roots. Roots are listed by a lower bound of the
// distance at which the cell's rays can enter them: a root whose box the ray does not meet before its current hit is
// skipped after one box test, and once the bound passes the current hit the rest of the list is (a closest-hit ray
// that found a near hit is done). A ray's hinted leaf (culling/README.md, "Hit hints") is its first root: the loop
// visits it with the leaf code every other leaf goes through, because llvmpipe runs a separate visit's code for every
// SIMD group whether or not a lane has a hint (docs/architecture.md). Same hits as traversing the subtrees one after
// another (the hit rule does not depend on the order). Needs render/bvh_nodes.glsl and culling/hint_leaf.glsl; with
// CHCRT_CELL_TRACK_LEAF defined, also visitLeafTracked(entry, leaf node, first, count, ...) (chcrt_cells.frag.glsl),
// which is told the list entry (CHCRT_CELL_HINT_ENTRY for the hinted leaf) and the node of every leaf it tests.

layout(binding = CHCRT_UNIT_CULLING_CELL_ROOTS) uniform usamplerBuffer cellRoots;

#ifdef CHCRT_CELL_TRACK_LEAF
uint currentNode = 0u;  // the node the traversal is at (its leaf, when a leaf is visited)
uint currentEntry = 0u; // the list entry of the root it is in
#endif

// Moves to the next root of [next, end) whose box the ray meets; false when none is left. The first root's test
// is free, every further one counts as a step (an inner node's visit tests two boxes; the pure tracer tests its
// one root box for free), so that with one root the count is exactly the pure tracer's.
bool nextListRoot(inout uint next, uint first, uint end, vec3 origin, vec3 invDir, float tmin, float bestT,
                  inout uint nodeFirst, inout uint nodeCount, inout float nodeEntry, inout TraceCost cost) {
    while (next < end && cost.iterations < CHCRT_TRACE_ITERATION_CAP) {
        ++cost.iterations;
        if (next != first) {
            ++cost.innerNodes;
        }
        uvec2 entry = texelFetch(cellRoots, int(next)).xy;
        if (uintBitsToFloat(entry.y) > pruneLimit(bestT)) {
            next = end; // this root and every later one start beyond the current hit
            return false;
        }
        ++next;
        if (enterRoot(entry.x, origin, invDir, tmin, bestT, nodeFirst, nodeCount, nodeEntry)) {
#ifdef CHCRT_CELL_TRACK_LEAF
            currentNode = entry.x;
            currentEntry = next - 1u;
#endif
            return true;
        }
    }
    return false;
}

// Traverses the list [first, end), after the leaf `hint` (CHCRT_NO_HIT_ID: none), whose box test is free as the
// first root's is: the step counts are those of visiting the hint before the list.
void traverseCellList(uint hint, uint first, uint end, vec3 origin, vec3 direction, float tmin, inout TraceHit best,
                      inout TraceCost cost) {
    vec3 invDir = safeInverseDirection(direction);
    uint stackNode[CHCRT_MAX_BVH_DEPTH];
    float stackEntry[CHCRT_MAX_BVH_DEPTH];
    int stackSize = 0;
    uint nodeFirst = 0u;
    uint nodeCount = 0u;
    float nodeEntry = 0.0f;
    uint next = first;
    bool traversing = hint != CHCRT_NO_HIT_ID &&
                      enterHintLeaf(hint, origin, invDir, tmin, best.t, nodeFirst, nodeCount, nodeEntry);
#ifdef CHCRT_CELL_TRACK_LEAF
    currentNode = hint;
    currentEntry = CHCRT_CELL_HINT_ENTRY;
#endif
    if (!traversing) {
        traversing =
            nextListRoot(next, first, end, origin, invDir, tmin, best.t, nodeFirst, nodeCount, nodeEntry, cost);
    }
#ifdef CHCRT_CELL_TRACK_LEAF
#define TRAVERSE_ENTER(node) currentNode = (node);
#define TRAVERSE_POP(word) currentNode = (word);
#define TRAVERSE_VISIT_LEAF \
    visitLeafTracked(currentEntry, currentNode, nodeFirst, nodeCount, origin, direction, tmin, best, cost)
#endif
#define TRAVERSE_NEXT_ROOT \
    traversing = nextListRoot(next, first, end, origin, invDir, tmin, best.t, nodeFirst, nodeCount, nodeEntry, cost);
#include "render/bvh_traverse_loop.glsl"
}
