#pragma once
// Line Spaces on BVH nodes (representative candidate paper §3.2, "Adaptation to BVH"): the nodes are chosen by
// depth D and triangle threshold T, each gets a binary Line Space (symmetric bitset) and optionally a
// representative candidate Line Space (sparse, non-symmetric), all in shared pools. Built on all cores with
// progress, timed, and sized.
//
// Node choice: walking down from the root, a node becomes a Line Space node when it is at depth D, or earlier
// when its subtree has fewer than T triangles (or is a leaf): the cut where the paper's tree "ends" for Line
// Space purposes ("determined by the depth D or a triangle count lower than T"). Every triangle of the scene
// lies below exactly one Line Space node (the cut covers the tree), so Line Space nodes can act as leaves.
#include "linespace/sparse_storage.h"
#include "renderer/bvh/bvh.h"
#include "renderer/core/progress.h"
#include "shaders/shared/linespace_layout.h"

#include <cstdint>
#include <string>
#include <vector>

namespace chcrt::ls {

struct LineSpaceParams {
    uint32_t n = 6;                 // patches per face edge (N); N^2 patches per face
    uint32_t depth = 9;             // D: BVH depth of the Line Space nodes (root = 0); the paper's LS(9)
    uint32_t triangleThreshold = 8; // T: shallower subtrees with fewer triangles end the cut (paper: T = 8)
    bool candidates = true;         // also build the representative candidate Line Space
    uint32_t threads = 0;           // 0 = hardware concurrency
    std::string toString() const;   // "N=6 D=9 T=8 candidates"
};

struct LineSpaceStats {
    double buildSeconds = 0.0;
    uint32_t spaceCount = 0;
    uint64_t binaryShafts = 0;          // 15 N^4 per Line Space
    uint64_t binaryFilled = 0;          // non-empty shafts
    uint64_t candidateShafts = 0;       // 30 N^4 per Line Space (0 without candidates)
    uint64_t candidateFilled = 0;       // shafts with a candidate
    uint64_t binaryBytes = 0;           // bitsets
    uint64_t candidateBytes = 0;        // bitsets + offsets + candidate indices
    uint64_t nodeBytes = 0;             // LineSpaceNodeGpu records
    uint64_t totalBytes() const { return binaryBytes + candidateBytes + nodeBytes; }
    std::string summary() const;        // one line for reports
};

inline constexpr uint32_t kNoSpace = 0xFFFFFFFFu;

struct LineSpaces {
    LineSpaceParams params;
    std::vector<uint32_t> bvhNodes;        // BVH node of each Line Space, in DFS order of the cut
    std::vector<uint32_t> spaceOfBvhNode;  // per BVH node: its Line Space or kNoSpace
    std::vector<uint32_t> binaryWords;     // symmetric bitsets, lsWordCount(n, true) words per Line Space
    SparseShaftStore candidates;           // non-symmetric; data = index into Bvh::triangles
    LineSpaceStats stats;

    uint32_t binaryWordsPerSpace() const;
    // Is the (symmetric-layout) shaft of Line Space `space` non-empty?
    bool binaryFilled(uint32_t space, uint32_t symmetricShaft) const;
    // Node records for the GPU (bounds from the BVH; wordBase = space * words per space).
    std::vector<gpu::LineSpaceNodeGpu> gpuNodes(const Bvh& bvh) const;
};

// The Line Space nodes of the cut described above, in depth-first order.
std::vector<uint32_t> selectLineSpaceNodes(const Bvh& bvh, uint32_t depth, uint32_t triangleThreshold);

// Builds all Line Spaces. Throws InputError for N outside 1..CHCRT_LS_MAX_N or an empty BVH.
LineSpaces buildLineSpaces(const Bvh& bvh, const LineSpaceParams& params, Progress& progress = nullProgress());

} // namespace chcrt::ls
