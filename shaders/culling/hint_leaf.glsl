// CHC+RT hit hints (culling/README.md "Hit hints"): a ray visits the BVH leaf its ray set's previous trace hit, as
// the traversal visits a leaf — the leaf's box against the ray up to pruneLimit(best t), then its triangles with the
// project's hit rule — so that a hit found here is one pure BVH traversal finds too (a triangle hit just outside its
// leaf's box by float rounding is not taken from a hint). Needs render/bvh_nodes.glsl. Returns true when the ray
// met the box (the leaf counts as visited).
#ifndef CHCRT_CULLING_HINT_SLOTS
#define CHCRT_CULLING_HINT_SLOTS 0
#endif
#if CHCRT_CULLING_HINT_SLOTS
// Out of core (culling/README.md "Hit hints out of core"): a hint is a node of the GPU cache's buffers, valid while
// its slot holds the subtree the hint was recorded in. Slots start at multiples of hintSlotNodes node records; each
// slot's epoch (shared/culling_layout.h) says when it was last given to another subtree.
uniform uint hintSlotNodes;
uniform uint hintEpoch;     // low 32 bits of the cache's contentEpoch when the ray set's hints were last validated
uniform uint hintEpochSpan; // the epoch now minus hintEpoch (below 2^31: the tracer empties older hint images)
layout(binding = CHCRT_UNIT_CULLING_HINT_SLOTS) uniform usamplerBuffer hintSlotEpochs;

// Whether the slot holding `node` was given to another subtree since the hints were validated (modular arithmetic:
// a replacement at or before hintEpoch gives 0 or a difference above the span).
bool hintSlotReplaced(uint node) {
    uint since = texelFetch(hintSlotEpochs, int(node / hintSlotNodes)).x - hintEpoch;
    return since != 0u && since <= hintEpochSpan;
}
#endif

// The visit of a leaf whose box and triangle range the layout has read: the box against the ray up to
// pruneLimit(best t), then the triangles with the hit rule — one rule for both layouts.
bool visitLeafInBox(vec3 lower, vec3 upper, uint first, uint count, vec3 origin, vec3 direction, float tmin,
                    inout TraceHit best, inout TraceCost cost) {
    vec2 entryExit = intersectRayAabb(origin, safeInverseDirection(direction), lower, upper);
    if (!rayHitsAabb(entryExit, tmin, pruneLimit(best.t))) {
        return false;
    }
    ++cost.leaves;
    intersectLeaf(first, count, origin, direction, tmin, best, cost);
    return true;
}

#if CHCRT_COMPACT_SUBTREES
// Out of core, compact layout: the node's subtree root — the frame its box and triangles decode in — is the first node
// of its slot. The leaf's box is read as the traversal reads it: from its own texel, decoded in that frame, or the
// root's full-precision box when the subtree is one leaf.
#if !CHCRT_CULLING_HINT_SLOTS
#error "compact hints need the cache's slots (CHCRT_CULLING_HINT_SLOTS)"
#endif
bool visitHintLeaf(uint leaf, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    uint root = leaf - leaf % hintSlotNodes;
    uvec4 root0 = texelFetch(bvhNodes, int(root));
    uvec4 root1 = texelFetch(bvhNodes, int(root) + 1);
    setNodeFrame(root, root0, root1);
    if (leaf == root) {
        return visitLeafInBox(uintBitsToFloat(root0.xyz), uintBitsToFloat(root1.xyz), compactFirst(root0.w),
                              compactCount(root0.w), origin, direction, tmin, best, cost);
    }
    uvec4 node = texelFetch(bvhNodes, int(leaf));
    return visitLeafInBox(compactLower(node), compactUpper(node), compactFirst(node.w), compactCount(node.w), origin,
                          direction, tmin, best, cost);
}
#else
bool visitHintLeaf(uint leaf, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    int texel = int(leaf) * CHCRT_BVH_TEXELS_PER_NODE;
    vec4 leaf0 = texelFetch(bvhNodes, texel);
    vec4 leaf1 = texelFetch(bvhNodes, texel + 1);
    return visitLeafInBox(leaf0.xyz, leaf1.xyz, floatBitsToUint(leaf0.w), floatBitsToUint(leaf1.w), origin, direction,
                          tmin, best, cost);
}
#endif
