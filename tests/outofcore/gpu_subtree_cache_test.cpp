// The GPU subtree cache (gl): under a budget far smaller than the scene, requests force evictions; after every
// acquire each resident slot read back from the texture buffers equals the file's subtree rebased to the slot,
// the allocation stays within the budget, and the two policies pick the victims they promise.
#include "culling/outofcore/gpu_subtree_cache.h"
#include "renderer/core/error.h"
#include "tests/gl/gl_test_fixture.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace chcrt {
namespace {

using outofcore::CachePolicy;
using outofcore::GpuSubtreeCache;

class GpuSubtreeCacheTest : public test::GlTest {
protected:
    void SetUp() override {
        test::GlTest::SetUp();
        test::prepareSmall("city:50k", file_, 1500);
        chs_ = std::make_unique<outofcore::ChsFile>(file_);
        store_ = std::make_unique<outofcore::SubtreeStore>(*chs_, 4ull << 20);
    }
    uint64_t slotBytes() const {
        return uint64_t(chs_->header().maxSubtreeNodes) * sizeof(BvhNodeGpu) +
               uint64_t(chs_->header().maxSubtreeTriangles) * sizeof(TriangleGpu);
    }
    // Every resident slot equals the file's subtree with indices rebased to the slot.
    void expectSlotsMatchFile(const GpuSubtreeCache& cache) {
        for (uint32_t slot = 0; slot < cache.slotCount(); ++slot) {
            const uint32_t subtree = cache.slotSubtree(slot);
            if (subtree == SubtreeSource::kNotResident) continue;
            const outofcore::SubtreeData d = chs_->readSubtree(subtree);
            std::vector<BvhNodeGpu> nodes(d.nodes.size());
            std::vector<TriangleGpu> tris(d.triangles.size());
            glGetNamedBufferSubData(cache.nodeBuffer(), GLintptr(uint64_t(slot) * cache.slotNodes() * sizeof(BvhNodeGpu)),
                                    GLsizeiptr(nodes.size() * sizeof(BvhNodeGpu)), nodes.data());
            glGetNamedBufferSubData(cache.triangleBuffer(),
                                    GLintptr(uint64_t(slot) * cache.slotTriangles() * sizeof(TriangleGpu)),
                                    GLsizeiptr(tris.size() * sizeof(TriangleGpu)), tris.data());
            for (size_t k = 0; k < nodes.size(); ++k) {
                BvhNodeGpu expected = d.nodes[k];
                expected.leftFirst += expected.triCount != 0 ? slot * cache.slotTriangles() : slot * cache.slotNodes();
                ASSERT_EQ(0, std::memcmp(&expected, &nodes[k], sizeof(BvhNodeGpu))) << "slot " << slot << " node " << k;
            }
            ASSERT_EQ(0, std::memcmp(d.triangles.data(), tris.data(), tris.size() * sizeof(TriangleGpu))) << "slot " << slot;
        }
    }
    test::ScratchDir dir_;
    std::filesystem::path file_ = dir_.file("city.chs");
    std::unique_ptr<outofcore::ChsFile> chs_;
    std::unique_ptr<outofcore::SubtreeStore> store_;
};

TEST_F(GpuSubtreeCacheTest, UploadsEvictAndMatchTheFileUnderTheBudget) {
    const uint32_t subtrees = chs_->header().subtreeCount;
    ASSERT_GT(subtrees, 20u);
    for (CachePolicy policy : {CachePolicy::RoundRobin, CachePolicy::Lru}) {
        const uint64_t budget = 5 * slotBytes() + slotBytes() / 2; // 5 slots; the scene has > 20 subtrees
        GpuSubtreeCache cache(*store_, {budget, policy});
        ASSERT_EQ(cache.slotCount(), 5u);
        EXPECT_LE(cache.stats().allocatedBytes, budget);
        std::mt19937 rng(3);
        for (int round = 0; round < 40; ++round) {
            std::vector<uint32_t> request(1 + rng() % 4);
            for (uint32_t& s : request) s = uint32_t(rng() % subtrees);
            std::vector<uint32_t> roots(request.size());
            cache.acquire(request, roots);
            for (size_t i = 0; i < request.size(); ++i) {
                ASSERT_NE(roots[i], SubtreeSource::kNotResident); // <= 4 requested, 5 slots: all fit
                ASSERT_EQ(roots[i] % cache.slotNodes(), 0u);
                EXPECT_EQ(cache.slotSubtree(roots[i] / cache.slotNodes()), request[i]);
            }
            expectSlotsMatchFile(cache);
            EXPECT_LE(cache.stats().allocatedBytes, budget);
            EXPECT_LE(cache.stats().residentBytes, cache.stats().allocatedBytes);
        }
        EXPECT_GT(cache.stats().evictions, 10u);
        EXPECT_GT(cache.stats().hits, 0u);
        EXPECT_GT(cache.stats().uploadedTriangleBytes, budget); // more was transferred than fits at once
    }
}

TEST_F(GpuSubtreeCacheTest, MoreRequestsThanSlotsAreDeferredNotDropped) {
    GpuSubtreeCache cache(*store_, {3 * slotBytes(), CachePolicy::Lru});
    ASSERT_EQ(cache.slotCount(), 3u);
    const std::vector<uint32_t> request = {0, 1, 2, 3, 4};
    std::vector<uint32_t> roots(request.size());
    cache.acquire(request, roots);
    int resident = 0;
    for (uint32_t r : roots) resident += r != SubtreeSource::kNotResident;
    EXPECT_EQ(resident, 3);
    EXPECT_EQ(cache.stats().deferred, 2u);
    expectSlotsMatchFile(cache);
}

TEST_F(GpuSubtreeCacheTest, PoliciesChooseTheirVictims) {
    auto run = [&](CachePolicy policy) {
        GpuSubtreeCache cache(*store_, {3 * slotBytes(), policy});
        std::vector<uint32_t> root(1);
        for (uint32_t s : {0u, 1u, 2u, 0u, 3u}) cache.acquire(std::vector<uint32_t>{s}, root);
        std::vector<uint32_t> resident;
        for (uint32_t slot = 0; slot < 3; ++slot) resident.push_back(cache.slotSubtree(slot));
        return resident;
    };
    // Round-robin replaces slot 0 (subtree 0, although just used); LRU replaces subtree 1.
    EXPECT_EQ(run(CachePolicy::RoundRobin), (std::vector<uint32_t>{3, 1, 2}));
    EXPECT_EQ(run(CachePolicy::Lru), (std::vector<uint32_t>{0, 3, 2}));
}

TEST_F(GpuSubtreeCacheTest, BudgetBelowOneSlotIsAnError) {
    EXPECT_THROW(GpuSubtreeCache(*store_, {slotBytes() - 1, CachePolicy::Lru}), InputError);
}

} // namespace
} // namespace chcrt
