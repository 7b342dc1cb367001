#pragma once
// Bounding volume hierarchy over a scene's triangles: binned SAH build (multi-threaded), the flat node array
// that the GLSL tracer reads (shaders/shared/bvh_layout.h), and statistics.
#include "renderer/core/aabb.h"
#include "renderer/core/progress.h"
#include "renderer/scene/scene.h"
#include "shaders/shared/bvh_layout.h"

#include <cstdint>
#include <vector>

namespace chcrt {

using gpu::BvhNodeGpu;
using gpu::TriangleGpu;

struct BvhBuildOptions {
    uint32_t maxLeafTriangles = 4; // a node with this many or fewer triangles becomes a leaf
    uint32_t binCount = 16;        // SAH bins per axis
    float traversalCost = 1.0f;    // SAH C_t
    float intersectionCost = 1.0f; // SAH C_i
    uint32_t threads = 0;          // 0 = hardware concurrency
    bool medianSplit = false;      // object-median split instead of SAH (reference for tests)
};

struct BvhStats {
    double buildSeconds = 0.0;
    double sahCost = 0.0; // sum over nodes of area/rootArea * (C_t for inner, C_i * count for leaves)
    uint32_t nodeCount = 0;
    uint32_t leafCount = 0;
    uint32_t maxDepth = 0; // root = depth 0
    double averageLeafTriangles = 0.0;
    uint64_t bytes = 0; // nodes + triangles as uploaded to the GPU
};

struct Bvh {
    // nodes[0] is the root. Inner: children leftFirst, leftFirst + 1. Leaf: triangles
    // [leftFirst, leftFirst + triCount) of `triangles` (BVH order).
    std::vector<BvhNodeGpu> nodes;
    std::vector<TriangleGpu> triangles; // BVH leaf order, with original ids
    BvhStats stats;

    Aabb rootBounds() const;
    bool isLeaf(uint32_t node) const { return nodes[node].triCount != 0; }
};

// Builds the BVH. Throws InputError for a scene without triangles. Guarantees maxDepth < CHCRT_MAX_BVH_DEPTH.
Bvh buildBvh(const Scene& scene, const BvhBuildOptions& options = {}, Progress& progress = nullProgress());

// SAH cost of a built tree (as in BvhStats::sahCost) with the given costs.
double computeSahCost(const Bvh& bvh, float traversalCost = 1.0f, float intersectionCost = 1.0f);

} // namespace chcrt
