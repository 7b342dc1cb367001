// The while-while loop of every BVH traversal (Aila & Laine 2009), pasted into the body of the function that
// traverses: the pure traverseBvh (render/bvh_traverse.glsl), CHC+RT's batch and leaf-cache traversals
// (culling/), the Line Space traversal (linespace/linespace_traverse.glsl). Not a function: GLSL passes arrays by
// value, and the stack arrays are the expensive part on llvmpipe (docs/benchmarks.md). One copy, with hooks: a
// traversal that needs more defines the hooks below before the #include; the loop's defaults give the pure
// traversal, and the hooks are undefined again at the end of this file.
//
// Expects in scope: vec3 origin, direction, invDir; float tmin; inout TraceHit best; inout TraceCost cost;
// uint stackNode[]; float stackEntry[]; int stackSize; and the current node: uint nodeFirst, nodeCount (its
// header: children's index for an inner node with nodeCount 0, else the leaf's triangles) and float nodeEntry (its
// box's computed entry distance, with which a traversal of several roots pushes the current one) with bool traversing
// (false: nothing to visit). Pending nodes wait on the stack with their entry distance and are popped only when
// that entry is not beyond pruneLimit(best t). Returns from the enclosing function when an any-hit query can stop.
//
// Hooks (all optional):
//   TRAVERSE_DESCEND_WHILE        condition that must also hold to descend further (default true)
//   TRAVERSE_ENTER(node)          statement run when the descent moves to child `node`, before its header is read
//   TRAVERSE_AFTER_DESCEND        statement run after each step of the descent
//   TRAVERSE_PUSH(node)           the stack word pushed for node `node` (default: the index itself)
//   TRAVERSE_STOP_NODE            condition: the descent stopped at a node that is neither inner nor leaf, to be
//   TRAVERSE_VISIT_STOP_NODE      visited with this int expression: TRAVERSE_ACTION_RETURN (the ray is done),
//                                 TRAVERSE_ACTION_DESCEND (go on below it), TRAVERSE_ACTION_POP (skip it)
//   TRAVERSE_VISIT_LEAF           bool expression, true when the ray is done (default: intersectLeaf)
//   TRAVERSE_NO_LEAVES            1: no ray reaches a leaf (the leaf test is compiled out)
//   TRAVERSE_POPPED_NODE(word)    node index of a stack word (default: the word)
//   TRAVERSE_POP(word)            statement run for a popped stack word, before the node's header is read
//   TRAVERSE_NEXT_ROOT            statement run when the stack is empty: may set a new current node
//                                 (nodeFirst, nodeCount, traversing = true), e.g. the next root of a list
#define TRAVERSE_ACTION_RETURN 0
#define TRAVERSE_ACTION_DESCEND 1
#define TRAVERSE_ACTION_POP 2
#ifndef TRAVERSE_DESCEND_WHILE
#define TRAVERSE_DESCEND_WHILE true
#endif
#ifndef TRAVERSE_ENTER
#define TRAVERSE_ENTER(node)
#endif
#ifndef TRAVERSE_AFTER_DESCEND
#define TRAVERSE_AFTER_DESCEND
#endif
#ifndef TRAVERSE_PUSH
#define TRAVERSE_PUSH(node) (node)
#endif
#ifndef TRAVERSE_VISIT_LEAF
#define TRAVERSE_VISIT_LEAF intersectLeaf(nodeFirst, nodeCount, origin, direction, tmin, best, cost)
#endif
#ifndef TRAVERSE_NO_LEAVES
#define TRAVERSE_NO_LEAVES 0
#endif
#ifndef TRAVERSE_POPPED_NODE
#define TRAVERSE_POPPED_NODE(word) (word)
#endif
#ifndef TRAVERSE_POP
#define TRAVERSE_POP(word)
#endif
    while (traversing && CHCRT_BELOW_ITERATION_CAP(cost)) {
        // Inner loop: descend until a leaf is reached or nothing is left.
        while (nodeCount == 0u && TRAVERSE_DESCEND_WHILE && CHCRT_BELOW_ITERATION_CAP(cost)) {
            CHCRT_COUNT_ITERATION(cost);
            ++cost.innerNodes;
#if CHCRT_COMPACT_SUBTREES
            // Both children in one texel each, decoded in the subtree's frame (render/bvh_nodes.glsl).
            uvec4 a = texelFetch(bvhNodes, int(nodeFirst));
            uvec4 b = texelFetch(bvhNodes, int(nodeFirst) + 1);
            vec2 entryExitA = intersectRayAabb(origin, invDir, compactLower(a), compactUpper(a));
            vec2 entryExitB = intersectRayAabb(origin, invDir, compactLower(b), compactUpper(b));
            uint firstA = compactFirst(a.w), countA = compactCount(a.w);
            uint firstB = compactFirst(b.w), countB = compactCount(b.w);
#else
            int texel = int(nodeFirst) * CHCRT_BVH_TEXELS_PER_NODE;
            vec4 a0 = texelFetch(bvhNodes, texel);
            vec4 a1 = texelFetch(bvhNodes, texel + 1);
            vec4 b0 = texelFetch(bvhNodes, texel + 2);
            vec4 b1 = texelFetch(bvhNodes, texel + 3);
            vec2 entryExitA = intersectRayAabb(origin, invDir, a0.xyz, a1.xyz);
            vec2 entryExitB = intersectRayAabb(origin, invDir, b0.xyz, b1.xyz);
            uint firstA = floatBitsToUint(a0.w), countA = floatBitsToUint(a1.w);
            uint firstB = floatBitsToUint(b0.w), countB = floatBitsToUint(b1.w);
#endif
            float limit = pruneLimit(best.t);
            bool hitA = rayHitsAabb(entryExitA, tmin, limit);
            bool hitB = rayHitsAabb(entryExitB, tmin, limit);
            if (hitA && hitB) {
                // Nearer child first (exploits occlusion); the farther one waits with its entry distance.
                bool aFirst = entryExitA.x <= entryExitB.x;
                stackNode[stackSize] = TRAVERSE_PUSH(aFirst ? nodeFirst + 1u : nodeFirst);
                stackEntry[stackSize] = aFirst ? entryExitB.x : entryExitA.x;
                ++stackSize;
                TRAVERSE_ENTER(aFirst ? nodeFirst : nodeFirst + 1u)
                nodeEntry = aFirst ? entryExitA.x : entryExitB.x;
                nodeFirst = aFirst ? firstA : firstB;
                nodeCount = aFirst ? countA : countB;
            } else if (hitA || hitB) {
                TRAVERSE_ENTER(hitA ? nodeFirst : nodeFirst + 1u)
                nodeEntry = hitA ? entryExitA.x : entryExitB.x;
                nodeFirst = hitA ? firstA : firstB;
                nodeCount = hitA ? countA : countB;
            } else {
                traversing = false;
                break;
            }
            TRAVERSE_AFTER_DESCEND
        }
#ifdef TRAVERSE_STOP_NODE
        if (traversing && (TRAVERSE_STOP_NODE)) {
            int action = TRAVERSE_VISIT_STOP_NODE;
            if (action == TRAVERSE_ACTION_RETURN) {
                return;
            }
            if (action == TRAVERSE_ACTION_DESCEND) {
                continue; // back into the inner loop with this node's children (or to its leaf)
            }
            nodeCount = 0u; // nothing to test here: pop
        }
#endif
#if !TRAVERSE_NO_LEAVES
        if (traversing && nodeCount != 0u) {
            ++cost.leaves;
            if (TRAVERSE_VISIT_LEAF) {
                return;
            }
        }
#endif
        // Pop the next node whose entry is not beyond the closest hit found so far.
        traversing = false;
        while (stackSize > 0 && CHCRT_BELOW_ITERATION_CAP(cost)) {
            CHCRT_COUNT_ITERATION(cost);
            --stackSize;
            if (stackEntry[stackSize] <= pruneLimit(best.t)) {
                TRAVERSE_POP(stackNode[stackSize])
#if CHCRT_COMPACT_SUBTREES
                uint popped = texelFetch(bvhNodes, int(TRAVERSE_POPPED_NODE(stackNode[stackSize]))).w;
                nodeFirst = compactFirst(popped);
                nodeCount = compactCount(popped);
#else
                int popped = int(TRAVERSE_POPPED_NODE(stackNode[stackSize])) * CHCRT_BVH_TEXELS_PER_NODE;
                nodeFirst = floatBitsToUint(texelFetch(bvhNodes, popped).w);
                nodeCount = floatBitsToUint(texelFetch(bvhNodes, popped + 1).w);
#endif
                nodeEntry = stackEntry[stackSize];
                traversing = true;
                break;
            }
        }
#ifdef TRAVERSE_NEXT_ROOT
        if (!traversing) {
            TRAVERSE_NEXT_ROOT
        }
#endif
    }
#undef TRAVERSE_DESCEND_WHILE
#undef TRAVERSE_ENTER
#undef TRAVERSE_AFTER_DESCEND
#undef TRAVERSE_PUSH
#undef TRAVERSE_STOP_NODE
#undef TRAVERSE_VISIT_STOP_NODE
#undef TRAVERSE_VISIT_LEAF
#undef TRAVERSE_NO_LEAVES
#undef TRAVERSE_POPPED_NODE
#undef TRAVERSE_POP
#undef TRAVERSE_NEXT_ROOT
#undef TRAVERSE_ACTION_RETURN
#undef TRAVERSE_ACTION_DESCEND
#undef TRAVERSE_ACTION_POP
