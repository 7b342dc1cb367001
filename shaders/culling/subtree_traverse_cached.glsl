// CHC+RT §5.2 subtree traversal with a 2-entry leaf cache: the loop of traverseBvh (render/bvh_traverse_loop.glsl)
// whose leaf hook only remembers a reached leaf; its triangles are intersected when two leaves have collected or
// nothing is left to traverse (delayed, more coherent triangle tests; the paper found 2 entries best and ~30% lost
// without the cache). The cache holds two (first, count) pairs in scalars, not an array: local arrays are the
// expensive part of traversal on llvmpipe (see render/bvh_traverse.glsl).
//
// Exactness: a node is pruned only when its entry is beyond pruneLimit(best t), and delaying leaf tests only
// leaves best t larger for longer, so fewer nodes are pruned; every triangle the immediate traversal tests is
// still tested, with the same hit rule (tmin <= t <= best t, lower id on equal t), so the result is the same.
// Host defines: as render/bvh_nodes.glsl. Requires render/bvh_nodes.glsl to be included first.

struct LeafCache {
    uint cached;
    uint first0, count0, first1, count1;
};

// Tests the cached leaves and empties the cache; true when an any-hit query can stop.
bool flushLeafCache(inout LeafCache cache, vec3 origin, vec3 direction, float tmin, inout TraceHit best,
                    inout TraceCost cost) {
    bool done = cache.cached >= 1u &&
                intersectLeaf(cache.first0, cache.count0, origin, direction, tmin, best, cost);
    if (!done && cache.cached >= 2u) {
        done = intersectLeaf(cache.first1, cache.count1, origin, direction, tmin, best, cost);
    }
    cache.cached = 0u;
    return done;
}

// Remembers a reached leaf; tests both once two have collected. True when an any-hit query can stop.
bool cacheLeaf(inout LeafCache cache, uint first, uint count, vec3 origin, vec3 direction, float tmin,
               inout TraceHit best, inout TraceCost cost) {
    if (cache.cached == 0u) {
        cache.first0 = first;
        cache.count0 = count;
    } else {
        cache.first1 = first;
        cache.count1 = count;
    }
    ++cache.cached;
    return cache.cached == 2u && flushLeafCache(cache, origin, direction, tmin, best, cost);
}

void traverseSubtreeCached(uint root, vec3 origin, vec3 direction, float tmin, inout TraceHit best,
                           inout TraceCost cost) {
    vec3 invDir = safeInverseDirection(direction);
    uint nodeFirst, nodeCount;
    float nodeEntry;
    if (!enterRoot(root, origin, invDir, tmin, best.t, nodeFirst, nodeCount, nodeEntry)) {
        return;
    }
    uint stackNode[CHCRT_MAX_BVH_DEPTH];
    float stackEntry[CHCRT_MAX_BVH_DEPTH];
    int stackSize = 0;
    bool traversing = true;
    LeafCache cache = LeafCache(0u, 0u, 0u, 0u, 0u);
#define TRAVERSE_VISIT_LEAF cacheLeaf(cache, nodeFirst, nodeCount, origin, direction, tmin, best, cost)
#include "render/bvh_traverse_loop.glsl"
    // Nothing left (or the loop cap was reached): test what the cache still holds.
    flushLeafCache(cache, origin, direction, tmin, best, cost);
}
