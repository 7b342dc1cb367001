#include "renderer/outofcore/gpu_cache_slots.h"

#include "shaders/shared/bvh_layout.h"

#include <algorithm>

namespace chcrt::outofcore {

uint64_t gpuCacheBudget(uint64_t budgetBytes, const GpuCacheLimits& limits) {
    return limits.availableGpuBytes != 0 ? std::min(budgetBytes, limits.availableGpuBytes / 4 * 3) : budgetBytes;
}

uint64_t gpuCacheSlots(uint64_t budgetBytes, const GpuSlotShape& shape, uint64_t subtrees, const GpuCacheLimits& limits) {
    const uint64_t slotBytes = shape.bytes();
    if (slotBytes == 0) return 0;
    uint64_t slots = std::min(gpuCacheBudget(budgetBytes, limits) / slotBytes, subtrees);
    const uint64_t maxTexels = limits.maxTextureBufferTexels;
    if (maxTexels != 0) {
        if (shape.nodes != 0) slots = std::min(slots, maxTexels / shape.nodeTexels());
        if (shape.triangles != 0) slots = std::min(slots, maxTexels / shape.triangleTexels());
        if (shape.vertices != 0) slots = std::min(slots, maxTexels / shape.vertices);
    }
    return slots;
}

uint64_t gpuCacheSlots(uint64_t budgetBytes, uint64_t slotNodes, uint64_t slotTriangles, uint64_t subtrees,
                       const GpuCacheLimits& limits) {
    return gpuCacheSlots(budgetBytes, GpuSlotShape{slotNodes, slotTriangles, 0, false}, subtrees, limits);
}

} // namespace chcrt::outofcore
