// GPU subtree cache slots (renderer/outofcore/gpu_cache_slots.h): the budget, one slot per subtree at most, the
// texel limit of one texture buffer (so a budget above ~2 GB on a GPU with 141 GB allocates what one buffer
// addresses instead of failing), and the GPU memory the driver reports.
#include "renderer/outofcore/gpu_cache_slots.h"
#include "shaders/shared/bvh_layout.h"

#include <gtest/gtest.h>

namespace chcrt::outofcore {
namespace {

constexpr uint64_t kNodes = 2000, kTriangles = 1500; // one slot: 64,000 + 72,000 bytes
constexpr uint64_t kSlotBytes = kNodes * 32 + kTriangles * 48;
constexpr uint64_t kTexels27 = uint64_t(1) << 27;    // NVIDIA's and llvmpipe's GL_MAX_TEXTURE_BUFFER_SIZE

TEST(GpuCacheSlots, TheBudgetAndTheSubtreesBoundTheSlots) {
    EXPECT_EQ(gpuCacheSlots(10 * kSlotBytes + 5, kNodes, kTriangles, 1000, {kTexels27, 0}), 10u);
    EXPECT_EQ(gpuCacheSlots(10 * kSlotBytes, kNodes, kTriangles, 4, {kTexels27, 0}), 4u); // one per subtree
    EXPECT_EQ(gpuCacheSlots(kSlotBytes - 1, kNodes, kTriangles, 1000, {kTexels27, 0}), 0u);
}

TEST(GpuCacheSlots, OneTextureBufferBoundsTheSlotsOfALargeBudget) {
    // 64 GiB asked on a GPU that has them: the triangle buffer addresses 2^27 texels = 29,826 slots of 1,500
    // triangles (3 texels each), far fewer than the budget holds.
    const uint64_t budget = uint64_t(64) << 30;
    const uint64_t slots = gpuCacheSlots(budget, kNodes, kTriangles, 1'000'000, {kTexels27, uint64_t(141) << 30});
    EXPECT_EQ(slots, kTexels27 / (kTriangles * CHCRT_TRI_TEXELS_PER_TRIANGLE));
    EXPECT_LT(slots, budget / kSlotBytes);
    // Node-heavy slots are bounded by the node buffer (2 texels per node) instead.
    EXPECT_EQ(gpuCacheSlots(budget, 100'000, 10, 1'000'000, {kTexels27, 0}),
              kTexels27 / (100'000 * CHCRT_BVH_TEXELS_PER_NODE));
}

TEST(GpuCacheSlots, ReportedGpuMemoryBoundsTheBudget) {
    const uint64_t available = 100 * kSlotBytes;
    // Three quarters of what is available: 75 slots, not the 1,000 the budget would hold.
    EXPECT_EQ(gpuCacheSlots(1000 * kSlotBytes, kNodes, kTriangles, 5000, {kTexels27, available}), 75u);
    // Not reported (0): the budget alone.
    EXPECT_EQ(gpuCacheSlots(1000 * kSlotBytes, kNodes, kTriangles, 5000, {kTexels27, 0}), 1000u);
}

} // namespace
} // namespace chcrt::outofcore
