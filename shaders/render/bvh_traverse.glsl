// Pure stack-based while-while BVH traversal (Aila & Laine 2009, as used by CHC+RT §5.2): the inner loop descends
// inner nodes testing both children, visiting the nearer first and pushing the farther with its entry distance; a
// reached leaf's triangles are tested (render/bvh_traverse_loop.glsl). The default traversal of the full-screen
// tracer and of CHC+RT's subtree passes: they include the file their CHCRT_BVH_TRAVERSAL names, this one unless
// the host names another (Line Space traversal: linespace/linespace_traverse.glsl). Needs render/bvh_nodes.glsl.

// Traverses the subtree rooted at `root` (its box is tested first). `best` carries the closest hit so far
// (initialise with makeMiss(tmax)), so several subtrees can be traced one after another into one result.
void traverseBvh(uint root, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    vec3 invDir = safeInverseDirection(direction);
    uint nodeFirst, nodeCount;
    float nodeEntry;
    if (!enterRoot(root, origin, invDir, tmin, best.t, nodeFirst, nodeCount, nodeEntry)) {
        return;
    }
    // The stack holds node indices and entry distances only; a popped node's header is fetched again. Keeping
    // the child's (first, count) on the stack instead costs a third local array, and local arrays are the
    // expensive part on llvmpipe (measured: 2x slower for primary rays on the 1M city, docs/benchmarks.md).
    uint stackNode[CHCRT_MAX_BVH_DEPTH];
    float stackEntry[CHCRT_MAX_BVH_DEPTH];
    int stackSize = 0;
    bool traversing = true;
#include "render/bvh_traverse_loop.glsl"
}
