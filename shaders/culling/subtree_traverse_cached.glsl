// CHC+RT §5.2 subtree traversal with a 2-entry leaf cache: like traverseBvh (trace/bvh_traverse.glsl, whose
// helpers and hit rule it uses), but a reached leaf is only remembered; its triangles are intersected when two
// leaves have collected or nothing is left to traverse (delayed, more coherent triangle tests; the paper found 2
// entries best and ~30% lost without the cache). The cache holds two (first, count) pairs in scalars, not an
// array: local arrays are the expensive part of traversal on llvmpipe (see bvh_traverse.glsl).
//
// Exactness: a node is pruned only when its entry is beyond pruneLimit(best t), and delaying leaf tests only
// leaves best t larger for longer, so fewer nodes are pruned; every triangle the immediate traversal tests is
// still tested, with the same hit rule (tmin <= t <= best t, lower id on equal t), so the result is the same.
// Host defines: as bvh_traverse.glsl. Requires bvh_traverse.glsl to be included first.

void flushLeafCache(inout uint cached, uint first0, uint count0, uint first1, uint count1, vec3 origin,
                    vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost, inout bool done) {
    if (cached >= 1u && intersectLeaf(first0, count0, origin, direction, tmin, best, cost)) {
        done = true; // any-hit: found
    }
    if (!done && cached >= 2u && intersectLeaf(first1, count1, origin, direction, tmin, best, cost)) {
        done = true;
    }
    cached = 0u;
}

void traverseSubtreeCached(uint root, vec3 origin, vec3 direction, float tmin, inout TraceHit best,
                           inout TraceCost cost) {
    vec3 invDir = safeInverseDirection(direction);
    vec4 root0 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE);
    vec4 root1 = texelFetch(bvhNodes, int(root) * CHCRT_BVH_TEXELS_PER_NODE + 1);
    if (!rayHitsAabb(intersectRayAabb(origin, invDir, root0.xyz, root1.xyz), tmin, pruneLimit(best.t))) {
        return;
    }
    uint nodeFirst = floatBitsToUint(root0.w);
    uint nodeCount = floatBitsToUint(root1.w);
    uint stackNode[CHCRT_MAX_BVH_DEPTH];
    float stackEntry[CHCRT_MAX_BVH_DEPTH];
    int stackSize = 0;
    uint cached = 0u, first0 = 0u, count0 = 0u, first1 = 0u, count1 = 0u;
    bool haveNode = true;
    bool done = false;

    while (!done && cost.iterations < CHCRT_TRACE_ITERATION_CAP) {
        if (haveNode) {
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
                    haveNode = false;
                    break;
                }
            }
            if (haveNode && nodeCount != 0u) {
                ++cost.leaves;
                if (cached == 0u) {
                    first0 = nodeFirst;
                    count0 = nodeCount;
                } else {
                    first1 = nodeFirst;
                    count1 = nodeCount;
                }
                ++cached;
            }
        }
        if (cached == 2u) {
            flushLeafCache(cached, first0, count0, first1, count1, origin, direction, tmin, best, cost, done);
        }
        // Pop the next node whose entry is not beyond the closest hit found so far.
        haveNode = false;
        while (!done && stackSize > 0 && cost.iterations < CHCRT_TRACE_ITERATION_CAP) {
            ++cost.iterations;
            --stackSize;
            if (stackEntry[stackSize] <= pruneLimit(best.t)) {
                int popped = int(stackNode[stackSize]) * CHCRT_BVH_TEXELS_PER_NODE;
                nodeFirst = floatBitsToUint(texelFetch(bvhNodes, popped).w);
                nodeCount = floatBitsToUint(texelFetch(bvhNodes, popped + 1).w);
                haveNode = true;
                break;
            }
        }
        if (!haveNode) {
            break;
        }
    }
    // Nothing left (or the loop cap was reached): test what the cache still holds.
    if (!done) {
        flushLeafCache(cached, first0, count0, first1, count1, origin, direction, tmin, best, cost, done);
    }
}
