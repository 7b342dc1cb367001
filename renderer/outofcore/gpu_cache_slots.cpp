#include "renderer/outofcore/gpu_cache_slots.h"

#include "shaders/shared/bvh_layout.h"

#include <algorithm>

namespace chcrt::outofcore {

uint64_t gpuCacheBudget(uint64_t budgetBytes, const GpuCacheLimits& limits) {
    return limits.availableGpuBytes != 0 ? std::min(budgetBytes, limits.availableGpuBytes / 4 * 3) : budgetBytes;
}

uint64_t gpuCacheSlots(uint64_t budgetBytes, uint64_t slotNodes, uint64_t slotTriangles, uint64_t subtrees,
                       const GpuCacheLimits& limits) {
    const uint64_t slotBytes = slotNodes * sizeof(gpu::BvhNodeGpu) + slotTriangles * sizeof(gpu::TriangleGpu);
    if (slotBytes == 0) return 0;
    uint64_t slots = std::min(gpuCacheBudget(budgetBytes, limits) / slotBytes, subtrees);
    if (limits.maxTextureBufferTexels != 0) {
        if (slotNodes != 0) slots = std::min(slots, limits.maxTextureBufferTexels / (slotNodes * CHCRT_BVH_TEXELS_PER_NODE));
        if (slotTriangles != 0) {
            slots = std::min(slots, limits.maxTextureBufferTexels / (slotTriangles * CHCRT_TRI_TEXELS_PER_TRIANGLE));
        }
    }
    return slots;
}

} // namespace chcrt::outofcore
