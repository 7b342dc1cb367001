// CHC+RT hit hints (culling/README.md "Hit hints"): a ray visits the BVH leaf its ray set's previous trace hit, as
// the traversal visits a leaf — the leaf's box against the ray up to pruneLimit(best t), then its triangles with the
// project's hit rule — so that a hit found here is one pure BVH traversal finds too (a triangle hit just outside its
// leaf's box by float rounding is not taken from a hint). Needs render/bvh_nodes.glsl. Returns true when the ray
// met the box (the leaf counts as visited).
#if CHCRT_COMPACT_SUBTREES
// Out of core, compact layout: a hint is a node of the cache's buffers, whose slot still holds the subtree the hint
// was recorded in (the tracer drops its hints once a slot changed: SubtreeSource::contentEpoch). Slots start at
// multiples of hintSlotNodes node texels, so the node's subtree root — the frame its box and triangles decode in —
// is found from the node alone. The leaf's box is read as the traversal reads it: from its own texel, decoded in
// that frame, or the root's full-precision box when the subtree is one leaf.
uniform uint hintSlotNodes;

bool visitHintLeaf(uint leaf, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    uint root = leaf - leaf % hintSlotNodes;
    uvec4 root0 = texelFetch(bvhNodes, int(root));
    uvec4 root1 = texelFetch(bvhNodes, int(root) + 1);
    setNodeFrame(root, root0, root1);
    vec3 lower, upper;
    uint header;
    if (leaf == root) {
        lower = uintBitsToFloat(root0.xyz);
        upper = uintBitsToFloat(root1.xyz);
        header = root0.w;
    } else {
        uvec4 node = texelFetch(bvhNodes, int(leaf));
        lower = compactLower(node);
        upper = compactUpper(node);
        header = node.w;
    }
    vec2 entryExit = intersectRayAabb(origin, safeInverseDirection(direction), lower, upper);
    if (!rayHitsAabb(entryExit, tmin, pruneLimit(best.t))) {
        return false;
    }
    ++cost.leaves;
    intersectLeaf(compactFirst(header), compactCount(header), origin, direction, tmin, best, cost);
    return true;
}
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
