#pragma once
// CHC+RT §4.3/§5.4: everything the culling needs to know about the scene, as plain data. The upper hierarchy
// (BVH nodes from the root down to and including the termination-subtree roots, §5.2) with boxes and children,
// plus per termination subtree its height and triangle count. The subtrees' own nodes and triangles are not
// here: they are reached through a SubtreeSource (subtree_source.h), in core the scene's BVH, out of core a
// cache. Built from an in-core Bvh by buildCullingHierarchy; out-of-core code builds the same struct from its
// file, so the tracer never touches a Bvh.
#include "culling/subtree_partition.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace chcrt {

struct CullingHierarchy {
    static constexpr uint32_t kNone = 0xffffffffu;
    struct Node {
        glm::vec3 boxMin{0.0f}, boxMax{0.0f};
        // Upper inner node: index of its first child in `nodes` (the second is the next index); kNone for a
        // termination root.
        uint32_t firstChild = kNone;
        // Termination root: index into `subtrees`; kNone for an upper inner node.
        uint32_t subtree = kNone;
        // §5.1 tighter bounds: the boxes of the node's two children (of the BVH below a termination root too);
        // tightCount = 1 when the node is a BVH leaf (then tightMin[0]/tightMax[0] is its own box).
        uint32_t tightCount = 1;
        glm::vec3 tightMin[2]{}, tightMax[2]{};
        bool isTerminal() const { return subtree != kNone; }
    };
    struct Subtree {
        uint32_t node = 0;       // its node in `nodes`
        uint32_t height = 0;     // edges from the root to its deepest leaf (bounds the traversal stack, §5.2)
        uint32_t triangles = 0;
        uint32_t bvhNode = 0;    // in-core BVH node index (the default SubtreeSource's GPU root); file-specific otherwise
    };
    std::vector<Node> nodes;     // nodes[0] = root
    std::vector<Subtree> subtrees;
    uint32_t maxSubtreeHeight = 0;
    SubtreePartitionOptions partition;

    // Surface area of a node's box (§4.4 split heuristic).
    float surfaceArea(uint32_t node) const;
};

// The upper hierarchy of an in-core BVH for the given termination limits (throws InputError for 0 limits).
CullingHierarchy buildCullingHierarchy(const Bvh& bvh, const SubtreePartitionOptions& options = {});

} // namespace chcrt
