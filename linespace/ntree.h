#pragma once
// N-tree base structure with binary Line Spaces on its inner nodes (soft-shadow paper §3, representative
// candidate paper §3.2 "Adaptation to NTree"): a regular recursive grid of cubic nodes, each subdivided node
// split into N x N x N equal cubes, down to depth d (root = level 0, cells of level d are leaves). Only
// non-empty nodes above level d are subdivided and carry a Line Space of resolution N, so patches coincide
// with the children's faces. A shaft of a subdivided node is non-empty iff it intersects a non-empty child
// (soft-shadow paper §3: "if all intersected subnodes are empty ... the shaft is empty"), decided by the exact
// shaft/box test with the builders' dilation: conservative with respect to the geometry.
//
// Triangles are assigned to every cell they overlap (exact triangle/box test), so a cell is non-empty iff
// geometry passes through it. Traversal: ntree_gpu.h (pools) and shaders/linespace/ntree_traverse.glsl (method
// ntree+ls). Not implemented: representative candidates on the N-tree.
#include "renderer/bvh/bvh.h"
#include "renderer/core/progress.h"

#include <cstdint>
#include <string>
#include <vector>

namespace chcrt::ls {

struct NTreeParams {
    uint32_t n = 6;       // branching factor per axis = Line Space resolution (papers: 4..10)
    uint32_t depth = 3;   // levels below the root (papers: 3 or 4)
    uint32_t threads = 0; // 0 = hardware concurrency
    std::string toString() const; // "NTree(N=6, d=3)"
};

inline constexpr uint32_t kNoChild = 0xFFFFFFFFu;

struct NTreeNode {
    glm::vec3 lower{0.0f};
    float size = 0.0f;               // cube edge
    uint32_t level = 0;
    uint32_t firstChild = kNoChild;  // N^3 children, x fastest then y then z; kNoChild for leaves/empty nodes
    uint32_t firstTriangle = 0;      // into NTree::triangleRefs
    uint32_t triangleCount = 0;      // triangles overlapping the cube (0 = empty)
    uint32_t space = kNoChild;       // Line Space of a subdivided node
    Aabb bounds() const { return {lower, lower + glm::vec3(size)}; }
};

struct NTreeStats {
    double buildSeconds = 0.0;
    uint32_t nodeCount = 0;       // all stored nodes (children groups include empty cells)
    uint32_t subdividedCount = 0; // nodes with a Line Space
    uint64_t triangleRefs = 0;
    uint64_t binaryFilled = 0, binaryShafts = 0;
    uint64_t lineSpaceBytes = 0; // bitsets
    uint64_t nodeBytes = 0;      // the paper's pools: 32-byte node records + one 32-bit child pointer per cell
    std::string summary() const;
};

struct NTree {
    NTreeParams params;
    std::vector<NTreeNode> nodes;       // nodes[0] = root
    std::vector<uint32_t> triangleRefs; // indices into Bvh::triangles, per node
    std::vector<uint32_t> binaryWords;  // symmetric bitsets of the subdivided nodes, by space
    NTreeStats stats;
    bool binaryFilled(uint32_t space, uint32_t symmetricShaft) const;
};

// Builds the tree over the BVH's triangles (any triangle list would do; the BVH's is the GPU's order) and the
// binary Line Spaces of its subdivided nodes. Throws InputError for N < 2, N > CHCRT_LS_MAX_N or depth 0.
NTree buildNTree(const Bvh& bvh, const NTreeParams& params, Progress& progress = nullProgress());

// The root buildNTree starts from: a cube centred on the BVH's root bounds, holding every triangle (the cache
// checks a loaded tree against it).
NTreeNode nTreeRoot(const Bvh& bvh);

// Everything in tree.stats but buildSeconds, from the tree's nodes, references and bitsets.
void computeNTreeStats(NTree& tree);

} // namespace chcrt::ls
