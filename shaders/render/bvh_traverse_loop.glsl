// The while-while loop of traverseBvh (bvh_traverse.glsl), pasted into the body of every function that traverses
// BVH nodes this way, so that there is one copy of it: traverseBvh (one root) and the CHC+RT batch traversal
// (culling/subtree_batch_traverse.glsl, several roots on one stack). Not a function: GLSL passes arrays by value,
// and the stack arrays are the expensive part on llvmpipe (docs/benchmarks.md).
// Expects in scope: vec3 origin, direction, invDir; float tmin; inout TraceHit best; inout TraceCost cost;
// uint stackNode[]; float stackEntry[]; int stackSize; and the current node: uint nodeFirst, nodeCount (its
// header: children's index for an inner node with nodeCount 0, else the leaf's triangles) with bool traversing
// (false: nothing to visit). Pending nodes wait on the stack with their entry distance and are popped only when
// that entry is not beyond pruneLimit(best t). Returns from the enclosing function when an any-hit query can stop.
    while (traversing && cost.iterations < CHCRT_TRACE_ITERATION_CAP) {
        // Inner loop: descend until a leaf is reached or nothing is left.
        while (nodeCount == 0u && cost.iterations < CHCRT_TRACE_ITERATION_CAP) {
            ++cost.iterations;
            ++cost.innerNodes;
            int texel = int(nodeFirst) * CHCRT_BVH_TEXELS_PER_NODE;
            vec4 a0 = texelFetch(bvhNodes, texel);
            vec4 a1 = texelFetch(bvhNodes, texel + 1);
            vec4 b0 = texelFetch(bvhNodes, texel + 2);
            vec4 b1 = texelFetch(bvhNodes, texel + 3);
            vec2 entryExitA = intersectRayAabb(origin, invDir, a0.xyz, a1.xyz);
            vec2 entryExitB = intersectRayAabb(origin, invDir, b0.xyz, b1.xyz);
            float limit = pruneLimit(best.t);
            bool hitA = rayHitsAabb(entryExitA, tmin, limit);
            bool hitB = rayHitsAabb(entryExitB, tmin, limit);
            if (hitA && hitB) {
                // Nearer child first (exploits occlusion); the farther one waits with its entry distance.
                bool aFirst = entryExitA.x <= entryExitB.x;
                stackNode[stackSize] = aFirst ? nodeFirst + 1u : nodeFirst;
                stackEntry[stackSize] = aFirst ? entryExitB.x : entryExitA.x;
                ++stackSize;
                nodeFirst = floatBitsToUint(aFirst ? a0.w : b0.w);
                nodeCount = floatBitsToUint(aFirst ? a1.w : b1.w);
            } else if (hitA || hitB) {
                nodeFirst = floatBitsToUint(hitA ? a0.w : b0.w);
                nodeCount = floatBitsToUint(hitA ? a1.w : b1.w);
            } else {
                traversing = false;
                break;
            }
        }
        if (traversing && nodeCount != 0u) {
            ++cost.leaves;
            if (intersectLeaf(nodeFirst, nodeCount, origin, direction, tmin, best, cost)) {
                return;
            }
        }
        // Pop the next node whose entry is not beyond the closest hit found so far.
        traversing = false;
        while (stackSize > 0 && cost.iterations < CHCRT_TRACE_ITERATION_CAP) {
            ++cost.iterations;
            --stackSize;
            if (stackEntry[stackSize] <= pruneLimit(best.t)) {
                int popped = int(stackNode[stackSize]) * CHCRT_BVH_TEXELS_PER_NODE;
                nodeFirst = floatBitsToUint(texelFetch(bvhNodes, popped).w);
                nodeCount = floatBitsToUint(texelFetch(bvhNodes, popped + 1).w);
                traversing = true;
                break;
            }
        }
    }
