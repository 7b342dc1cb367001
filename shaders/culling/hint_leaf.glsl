// CHC+RT hit hints (culling/README.md "Hit hints"): a ray visits the BVH leaf its ray set's previous trace hit, as
// the traversal visits a leaf — the leaf's box against the ray up to pruneLimit(best t), then its triangles with the
// project's hit rule — so that a hit found here is one pure BVH traversal finds too (a triangle hit just outside its
// leaf's box by float rounding is not taken from a hint). The cell passes enter the leaf as the first root of their
// list traversal (enterHintLeaf), the hint pass visits it on its own (visitHintLeaf). Needs render/bvh_nodes.glsl.
#define CHCRT_CELL_HINT_ENTRY 0xFFFFFFFFu // the list entry the cell passes give a ray's hinted leaf: none of the list

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

// Enters the hinted leaf as the traversal enters a root (render/bvh_nodes.glsl, enterRoot): its box against the ray
// up to pruneLimit(bestT), and its triangle range. False for a node that is not a leaf (hint images hold leaves; a
// test writes arbitrary nodes, whose subtrees a traversal stack sized for termination subtrees could not hold).
#if CHCRT_COMPACT_SUBTREES
// Out of core, compact layout: the node's subtree root — the frame its box and triangles decode in — is the first node
// of its slot. The leaf's box is read as the traversal reads it: from its own texel, decoded in that frame, or the
// root's full-precision box when the subtree is one leaf.
#if !CHCRT_CULLING_HINT_SLOTS
#error "compact hints need the cache's slots (CHCRT_CULLING_HINT_SLOTS)"
#endif
bool enterHintLeaf(uint leaf, vec3 origin, vec3 invDir, float tmin, float bestT, out uint first, out uint count,
                   out float entry) {
    uint root = leaf - leaf % hintSlotNodes;
    if (leaf == root) {
        return enterRoot(root, origin, invDir, tmin, bestT, first, count, entry) && count != 0u;
    }
    setNodeFrame(root);
    uvec4 node = texelFetch(bvhNodes, int(leaf));
    first = compactFirst(node.w);
    count = compactCount(node.w);
    vec2 entryExit = intersectRayAabb(origin, invDir, compactLower(node), compactUpper(node));
    entry = entryExit.x;
    return rayHitsAabb(entryExit, tmin, pruneLimit(bestT)) && count != 0u;
}
#else
bool enterHintLeaf(uint leaf, vec3 origin, vec3 invDir, float tmin, float bestT, out uint first, out uint count,
                   out float entry) {
    return enterRoot(leaf, origin, invDir, tmin, bestT, first, count, entry) && count != 0u;
}
#endif

// The hint pass's visit (culling/hint_pass.glsl): the leaf entered as above, then its triangles with the hit rule;
// true when the ray met the leaf's box (the leaf counts as visited). The cell passes visit hints inside their list
// traversal instead (culling/cell_list_traverse.glsl).
bool visitHintLeaf(uint leaf, vec3 origin, vec3 direction, float tmin, inout TraceHit best, inout TraceCost cost) {
    uint first, count;
    float entry;
    if (!enterHintLeaf(leaf, origin, safeInverseDirection(direction), tmin, best.t, first, count, entry)) {
        return false;
    }
    ++cost.leaves;
    intersectLeaf(first, count, origin, direction, tmin, best, cost);
    return true;
}
