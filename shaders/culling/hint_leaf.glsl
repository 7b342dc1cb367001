// CHC+RT hit hints (culling/README.md "Hit hints"): a ray visits the BVH leaf its ray set's previous trace hit, as
// the traversal visits a leaf — the leaf's box against the ray up to pruneLimit(best t), then its triangles with the
// project's hit rule — so that a hit found here is one pure BVH traversal finds too (a triangle hit just outside its
// leaf's box by float rounding is not taken from a hint). Needs render/bvh_nodes.glsl. Returns true when the ray
// met the box (the leaf counts as visited).
#if CHCRT_COMPACT_SUBTREES
// Hints need the in-core BVH (ChcrtTracer::hintsAvailable): out of core, where the compact layout lives, there are none.
#if CHCRT_CULLING_HINTS
#error "hit hints need the in-core BVH"
#endif
#else
bool visitHintLeaf(uint leaf, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    int texel = int(leaf) * CHCRT_BVH_TEXELS_PER_NODE;
    vec4 leaf0 = texelFetch(bvhNodes, texel);
    vec4 leaf1 = texelFetch(bvhNodes, texel + 1);
    vec2 entryExit = intersectRayAabb(origin, safeInverseDirection(direction), leaf0.xyz, leaf1.xyz);
    if (!rayHitsAabb(entryExit, tmin, pruneLimit(best.t))) {
        return false;
    }
    ++cost.leaves;
    intersectLeaf(floatBitsToUint(leaf0.w), floatBitsToUint(leaf1.w), origin, direction, tmin, best, cost);
    return true;
}
#endif
