// CHC+RT §5.2 by-tile batches traversed as one: the subtree roots of a batch whose boxes the ray meets go on one
// traversal stack (the first listed, i.e. the nearest for primary and shadow rays, is visited first), and one
// while-while loop (trace/bvh_traverse_loop.glsl) visits them all. The same hits as traversing the subtrees one
// after another (the hit rule does not depend on the order, trace/bvh_traverse.glsl); the point is llvmpipe's cost
// model (docs/architecture.md, "llvmpipe executes every branch"): a loop per subtree costs every 8-pixel group at
// least one trip through each subtree's traversal, and the group then waits for its slowest ray in each of them;
// one loop costs the group only the slowest ray's total (culling/README.md, "Merged batch traversal").
// Needs bvh_traverse.glsl (node access, the hit rule) and the frag shader's `subtreeRoots` uniform. The stack
// holds the batch's other roots plus one subtree's descent (CHCRT_MAX_BVH_DEPTH = the subtree height + 1 here).

// A stack word of a waiting root (the compact layout must switch frames when it is popped; node indices stay below
// 2^CHCRT_COMPACT_INDEX_BITS).
#if CHCRT_COMPACT_SUBTREES
#define TRAVERSE_ROOT_FLAG 0x80000000u
#define TRAVERSE_ROOT_WORD(root) ((root) | TRAVERSE_ROOT_FLAG)
#else
#define TRAVERSE_ROOT_WORD(root) (root)
#endif

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
#if CHCRT_COMPACT_SUBTREES
        uvec4 root0 = texelFetch(bvhNodes, int(root));
        uvec4 root1 = texelFetch(bvhNodes, int(root) + 1);
        vec2 entryExit = intersectRayAabb(origin, invDir, uintBitsToFloat(root0.xyz), uintBitsToFloat(root1.xyz));
        // A root that is a leaf starts at its subtree's first triangle, the root's texel 2.
        uint rootCount = compactCount(root0.w);
        uint rootFirst =
            (root0.w & CHCRT_COMPACT_INDEX_MASK) + (rootCount == 0u ? root : texelFetch(bvhNodes, int(root) + 2).x);
#else
        vec4 root0 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE);
        vec4 root1 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE + 1);
        vec2 entryExit = intersectRayAabb(origin, invDir, root0.xyz, root1.xyz);
        uint rootFirst = floatBitsToUint(root0.w), rootCount = floatBitsToUint(root1.w);
#endif
        if (rayHitsAabb(entryExit, tmin, pruneLimit(best.t))) {
            if (traversing) {
                stackNode[stackSize] = TRAVERSE_ROOT_WORD(currentRoot);
                stackEntry[stackSize] = nodeEntry;
                ++stackSize;
            }
            currentRoot = root;
            nodeEntry = entryExit.x;
            nodeFirst = rootFirst;
            nodeCount = rootCount;
            traversing = true;
        }
    }
#if CHCRT_COMPACT_SUBTREES
    // The waiting roots are marked on the stack: popping one switches to its frame. The stack stays nested (a root's
    // nodes are all popped before the root below them), so the frame is always the subtree being traversed.
    if (traversing) {
        setNodeFrame(currentRoot);
    }
#define TRAVERSE_POPPED_NODE(word) ((word) & ~TRAVERSE_ROOT_FLAG)
#define TRAVERSE_POP(word)                                                                                           \
    if (((word) & TRAVERSE_ROOT_FLAG) != 0u) {                                                                       \
        setNodeFrame((word) & ~TRAVERSE_ROOT_FLAG);                                                                  \
    }
#endif
#include "render/bvh_traverse_loop.glsl"
}
