// CHC+RT §5.2 by-tile batches traversed as one: the subtree roots of a batch whose boxes the ray meets go on one
// traversal stack (the first listed, i.e. the nearest for primary and shadow rays, is visited first), and one
// while-while loop (trace/bvh_traverse_loop.glsl) visits them all. The same hits as traversing the subtrees one
// after another (the hit rule does not depend on the order, trace/bvh_traverse.glsl); the point is llvmpipe's cost
// model (docs/architecture.md, "llvmpipe executes every branch"): a loop per subtree costs every 8-pixel group at
// least one trip through each subtree's traversal, and the group then waits for its slowest ray in each of them;
// one loop costs the group only the slowest ray's total (culling/README.md, "Merged batch traversal").
// Needs bvh_traverse.glsl (node access, the hit rule) and the frag shader's `subtreeRoots` uniform. The stack
// holds the batch's other roots plus one subtree's descent (CHCRT_MAX_BVH_DEPTH = the subtree height + 1 here).

void traverseSubtreeBatch(int count, vec3 origin, vec3 direction, float tmin, inout TraceHit best,
                          inout TraceCost cost) {
    vec3 invDir = safeInverseDirection(direction);
    uint stackNode[CHCRT_CULLING_MAX_BATCH + CHCRT_MAX_BVH_DEPTH];
    float stackEntry[CHCRT_CULLING_MAX_BATCH + CHCRT_MAX_BVH_DEPTH];
    int stackSize = 0;
    uint nodeFirst = 0u;
    uint nodeCount = 0u;
    float nodeEntry = 0.0f;
    bool traversing = false;
    // Last listed first: each root the ray meets becomes the current node and pushes the previous current one, so
    // the first listed root ends up current and the others wait in list order.
    uint currentRoot = 0u; // its entry is nodeEntry
    for (int i = count - 1; i >= 0 && cost.iterations < CHCRT_TRACE_ITERATION_CAP; --i) {
        ++cost.iterations;
        uint root = subtreeRoots[i >> 2][i & 3];
        vec4 root0 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE);
        vec4 root1 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE + 1);
        vec2 entryExit = intersectRayAabb(origin, invDir, root0.xyz, root1.xyz);
        if (rayHitsAabb(entryExit, tmin, pruneLimit(best.t))) {
            if (traversing) {
                stackNode[stackSize] = currentRoot;
                stackEntry[stackSize] = nodeEntry;
                ++stackSize;
            }
            currentRoot = root;
            nodeEntry = entryExit.x;
            nodeFirst = floatBitsToUint(root0.w);
            nodeCount = floatBitsToUint(root1.w);
            traversing = true;
        }
    }
#include "render/bvh_traverse_loop.glsl"
}
