#pragma once
// How many slots the GPU subtree cache (culling/outofcore/gpu_subtree_cache.h) allocates for a budget: pure
// arithmetic, so that the limits can be tested without a GPU that has them.
#include "shaders/shared/bvh_layout.h"

#include <cstdint>

namespace chcrt::outofcore {

struct GpuCacheLimits {
    // Texels one texture buffer holds (GL_MAX_TEXTURE_BUFFER_SIZE): the cache keeps nodes (2 texels each) and
    // triangles (3 texels each) in one buffer apiece, so 2^27 texels (NVIDIA, llvmpipe) cap the triangle slots at
    // 44.7M triangles, about 2.1 GB, whatever --gpu-cache-mb says.
    uint64_t maxTextureBufferTexels = 0;
    // GPU memory the driver reports as available (queryGpuMemory); 0 where it reports none.
    uint64_t availableGpuBytes = 0;
};

// The part of `budgetBytes` the cache may allocate: where GPU memory is reported, within three quarters of it (the
// frame's targets and the driver need the rest).
uint64_t gpuCacheBudget(uint64_t budgetBytes, const GpuCacheLimits& limits);

// What one slot holds, in records of the cache's layout (shared/bvh_layout.h): the full layout (nodes of 32 bytes,
// triangles of 48) or the compact one (node texels of 16 bytes, a subtree taking its node count + 1; triangle texels
// of 16 bytes; vertices of 12 bytes in a third buffer).
struct GpuSlotShape {
    uint64_t nodes = 0, triangles = 0, vertices = 0;
    bool compact = false;
    uint64_t nodeBytes() const { return nodes * (compact ? 16 : 32); }
    uint64_t triangleBytes() const { return triangles * (compact ? 16 : 48); }
    uint64_t vertexBytes() const { return vertices * 12; }
    uint64_t bytes() const { return nodeBytes() + triangleBytes() + vertexBytes(); }
    uint64_t nodeTexels() const { return nodes * (compact ? 1 : 2); }
    uint64_t triangleTexels() const { return triangles * (compact ? 1 : 3); }
};
// The shape of one subtree (or proxy) of `nodes` nodes, `triangles` triangles and `vertices` distinct vertices
// (compact files) in the cache: a compact subtree's nodes take their count + 2 texels (its root takes three).
inline GpuSlotShape gpuEntryShape(uint64_t nodes, uint64_t triangles, uint64_t vertices, bool compact) {
    return {compact ? nodes + CHCRT_COMPACT_ROOT_TEXELS - 1 : nodes, triangles, compact ? vertices : 0, compact};
}
// Slots of that shape: as many as `budgetBytes` holds, at most one per subtree, at most what one texture buffer
// addresses, and, where GPU memory is reported, within three quarters of it. 0 when the budget holds no slot.
uint64_t gpuCacheSlots(uint64_t budgetBytes, const GpuSlotShape& shape, uint64_t subtrees, const GpuCacheLimits& limits);

// Slots of `slotNodes` nodes and `slotTriangles` triangles: as many as `budgetBytes` holds, at most one per subtree
// (`subtrees`), at most what one texture buffer addresses, and, where GPU memory is reported, within three quarters
// of it (the frame's targets and the driver need the rest). 0 when the budget holds no slot.
uint64_t gpuCacheSlots(uint64_t budgetBytes, uint64_t slotNodes, uint64_t slotTriangles, uint64_t subtrees,
                       const GpuCacheLimits& limits);

} // namespace chcrt::outofcore
