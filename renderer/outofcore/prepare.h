#pragma once
// `chcrt prepare`: turns a scene (generator spec or file) into a prepared scene (.chs) with peak memory bounded
// by a budget, not by the scene's size (issue #5). A generated city larger than the budget is generated in
// parts (consecutive buildings, i.e. strips of blocks, so the parts are spatially compact), each part built
// into its own BVH and written as termination subtrees at once; a top-level SAH tree over the parts' roots
// joins them at the end. Any other scene must fit the budget once; a grid of copies of it (the paper's
// Powerplant x 16) is written copy by copy from the one BVH, moved. Output is deterministic for a given spec
// and options (single-threaded BVH builds are not required: the builder is deterministic).
#include "renderer/bvh/bvh.h"
#include "renderer/core/progress.h"
#include "renderer/outofcore/lod_proxies.h"

#include <cstdint>
#include <filesystem>
#include <string>

namespace chcrt::outofcore {

// Default subtree size for a 1 GiB GPU cache: 64k triangles (~4 MB of nodes + triangles on the GPU), so a
// 1 GiB cache holds ~256 subtrees. The paper's 1M-triangle subtrees (~64-100 MB each) would leave ~10-16
// slots, far too coarse for a street-level working set spread over many blocks.
inline constexpr uint32_t kDefaultSubtreeTriangles = 1u << 16;
inline constexpr uint32_t kDefaultSubtreeHeight = 24; // CHC+RT §5.2

// Peak bytes per triangle while one part is generated and built (scene arrays ~100 B, BVH build ~150 B,
// subtree staging); measured with /usr/bin/time -v on city parts (docs/outofcore.md).
inline constexpr uint64_t kPrepareBytesPerTriangle = 400;

struct PrepareOptions {
    uint64_t memoryBytes = 2048ull << 20;
    uint32_t subtreeTriangles = kDefaultSubtreeTriangles;
    uint32_t subtreeHeight = kDefaultSubtreeHeight;
    uint32_t lodLevels = kDefaultLodLevels; // LOD proxy levels per subtree (lod_proxies.h); 0 = none
    bool compact = true; // compact subtrees (version 3, compact_subtree.h); false: the full layout (versions 1 and 2)
    uint32_t gridX = 1, gridZ = 1; // copies of the scene (any scene; a city grid repeats the whole city)
    BvhBuildOptions bvh;
};

struct PrepareReport {
    uint64_t triangles = 0;
    uint32_t subtrees = 0;
    uint32_t chunks = 0;
    uint64_t fileBytes = 0;
    uint64_t subtreeBytes = 0; // the subtrees' blobs
    uint64_t proxyBytes = 0;   // the LOD proxies' blobs
    uint64_t proxies = 0;      // kept proxy levels
    uint64_t vertices = 0;     // the compact subtree blobs' distinct vertices
    bool compact = false;
    double seconds = 0.0;
};

// Parses "NxM" (both >= 1). Throws InputError.
void parseGrid(const std::string& text, uint32_t& x, uint32_t& z);

// Prepares `scene` (generator spec, optionally "grid:NxM:<spec or file>", or a scene file) into `output`.
// Throws InputError for bad input or a budget too small for the smallest part.
PrepareReport prepareScene(const std::string& scene, const std::filesystem::path& output, const PrepareOptions& options,
                           Progress& progress = nullProgress());

} // namespace chcrt::outofcore
