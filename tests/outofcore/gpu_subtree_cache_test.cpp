// The GPU subtree cache (gl): under a budget far smaller than the scene, requests force evictions; after every
// acquire each resident slot read back from the texture buffers equals the file's subtree rebased to the slot,
// the allocation stays within the budget, and the two policies pick the victims they promise.
#include "culling/outofcore/gpu_subtree_cache.h"
#include "renderer/core/error.h"
#include "renderer/outofcore/compact_subtree.h"
#include "tests/gl/gl_test_fixture.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <span>
#include <string>

namespace chcrt {
namespace {

using outofcore::CachePolicy;
using outofcore::GpuSubtreeCache;

// Each test runs on the compact layout (the default, .chs version 3) and the full one.
class GpuSubtreeCacheTest : public test::GlTest, public ::testing::WithParamInterface<bool> {
protected:
    void SetUp() override {
        test::GlTest::SetUp();
        test::prepareSmall("city:50k", file_, 1500, 256ull << 20, GetParam());
        chs_ = std::make_unique<outofcore::ChsFile>(file_);
        ASSERT_EQ(chs_->compact(), GetParam());
        store_ = std::make_unique<outofcore::SubtreeStore>(*chs_, 4ull << 20);
    }
    uint64_t slotBytes() const {
        const outofcore::ChsHeader& h = chs_->header();
        if (chs_->compact()) {
            return outofcore::compactNodeTexels(h.maxSubtreeNodes) * 16 + uint64_t(h.maxSubtreeTriangles) * 16 +
                   uint64_t(chs_->maxSubtreeVertices()) * 12;
        }
        return uint64_t(h.maxSubtreeNodes) * sizeof(BvhNodeGpu) + uint64_t(h.maxSubtreeTriangles) * sizeof(TriangleGpu);
    }
    template <class T>
    static std::vector<T> readBack(GLuint buffer, uint64_t first, size_t count) {
        std::vector<T> out(count);
        if (count != 0) glGetNamedBufferSubData(buffer, GLintptr(first * sizeof(T)), GLsizeiptr(count * sizeof(T)), out.data());
        return out;
    }
    // The entry whose nodes start at `nodeBase` and whose triangles (and a compact file's vertices) start at
    // `triBase` (`vertexBase`) equals `d` with its indices rebased there.
    void expectEntryAt(const GpuSubtreeCache& cache, uint64_t nodeBase, uint64_t triBase, uint64_t vertexBase,
                       const outofcore::SubtreeData& d, const std::string& what) {
        if (chs_->compact()) {
            const auto nodes = readBack<glm::uvec4>(cache.nodeBuffer(), nodeBase, d.compactNodes.size());
            const auto tris = readBack<glm::uvec4>(cache.triangleBuffer(), triBase, d.compactTriangles.size());
            const auto vertices = readBack<glm::vec3>(cache.vertexBuffer(), vertexBase, d.vertices.size());
            // As stored, but for the root's texel 2: the entry's first triangle and vertex.
            for (size_t k = 0; k < nodes.size(); ++k) {
                const glm::uvec4 expected =
                    k == 2 ? glm::uvec4(uint32_t(triBase), uint32_t(vertexBase), d.compactNodes[2].z, d.compactNodes[2].w)
                           : d.compactNodes[k];
                ASSERT_EQ(expected, nodes[k]) << what << " texel " << k;
            }
            ASSERT_EQ(0, std::memcmp(d.compactTriangles.data(), tris.data(), tris.size() * sizeof(glm::uvec4))) << what;
            ASSERT_EQ(0, std::memcmp(d.vertices.data(), vertices.data(), vertices.size() * sizeof(glm::vec3))) << what;
            return;
        }
        const auto nodes = readBack<BvhNodeGpu>(cache.nodeBuffer(), nodeBase, d.nodes.size());
        const auto tris = readBack<TriangleGpu>(cache.triangleBuffer(), triBase, d.triangles.size());
        for (size_t k = 0; k < nodes.size(); ++k) {
            BvhNodeGpu expected = d.nodes[k];
            expected.leftFirst += uint32_t(expected.triCount != 0 ? triBase : nodeBase);
            ASSERT_EQ(0, std::memcmp(&expected, &nodes[k], sizeof(BvhNodeGpu))) << what << " node " << k;
        }
        ASSERT_EQ(0, std::memcmp(d.triangles.data(), tris.data(), tris.size() * sizeof(TriangleGpu))) << what;
    }
    // Every resident slot equals the file's subtree with indices rebased to the slot.
    void expectSlotsMatchFile(const GpuSubtreeCache& cache) {
        for (uint32_t slot = 0; slot < cache.slotCount(); ++slot) {
            const uint32_t subtree = cache.slotSubtree(slot);
            if (subtree == SubtreeSource::kNotResident) continue;
            const uint64_t vertexBase = chs_->compact() ? uint64_t(slot) * cache.slotVertices() : 0;
            expectEntryAt(cache, uint64_t(slot) * cache.slotNodes(), uint64_t(slot) * cache.slotTriangles(), vertexBase,
                          chs_->readSubtree(subtree), "slot " + std::to_string(slot));
        }
    }
    test::ScratchDir dir_;
    std::filesystem::path file_ = dir_.file("city.chs");
    std::unique_ptr<outofcore::ChsFile> chs_;
    std::unique_ptr<outofcore::SubtreeStore> store_;
};

TEST_P(GpuSubtreeCacheTest, UploadsEvictAndMatchTheFileUnderTheBudget) {
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

TEST_P(GpuSubtreeCacheTest, MoreRequestsThanSlotsAreDeferredNotDropped) {
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

TEST_P(GpuSubtreeCacheTest, PoliciesChooseTheirVictims) {
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

// LOD proxies are packed at their own sizes into their level's pool (packed_ring.h): under a budget whose coarsest
// pool holds a few of them, every proxy an acquire returns reads back as the file's proxy where its root says (the
// compact root's bases, the full layout's rebased leaves), so no two proxies of one request overlap.
TEST_P(GpuSubtreeCacheTest, PackedProxiesMatchTheFileUnderTheBudget) {
    const uint32_t subtrees = chs_->header().subtreeCount, coarsest = chs_->lodLevels();
    ASSERT_GE(coarsest, 1u);
    outofcore::GpuCacheOptions options{3 * slotBytes(), CachePolicy::Lru};
    options.lodPixels = 1e9f; // every proxy's error projects below it: the coarsest level that has one serves
    GpuSubtreeCache cache(*store_, options);
    cache.setView(glm::vec3(1e6f), 1000.0f);
    EXPECT_LE(cache.stats().allocatedBytes, options.budgetBytes);
    std::mt19937 rng(5);
    uint32_t served = 0;
    for (int round = 0; round < 60; ++round) {
        std::vector<uint32_t> request(1 + rng() % 6);
        for (uint32_t& s : request) s = uint32_t(rng() % subtrees);
        std::vector<uint32_t> roots(request.size());
        cache.acquire(request, roots);
        for (size_t i = 0; i < request.size(); ++i) {
            const uint32_t level = cache.levelFor(request[i]);
            if (level == 0 || roots[i] == SubtreeSource::kNotResident) continue;
            const outofcore::SubtreeData d = chs_->readSubtree(request[i], level);
            uint64_t triBase = 0, vertexBase = 0;
            if (chs_->compact()) {
                const glm::uvec4 bases = readBack<glm::uvec4>(cache.nodeBuffer(), roots[i] + 2, 1)[0];
                triBase = bases.x, vertexBase = bases.y;
            } else {
                const auto nodes = readBack<BvhNodeGpu>(cache.nodeBuffer(), roots[i], d.nodes.size());
                size_t leaf = 0;
                while (leaf < nodes.size() && d.nodes[leaf].triCount == 0) ++leaf;
                ASSERT_LT(leaf, nodes.size());
                triBase = nodes[leaf].leftFirst - d.nodes[leaf].leftFirst;
            }
            expectEntryAt(cache, roots[i], triBase, vertexBase, d,
                          "round " + std::to_string(round) + " subtree " + std::to_string(request[i]));
            ++served;
        }
        EXPECT_LE(cache.stats().residentBytes, cache.stats().allocatedBytes);
    }
    EXPECT_GT(served, 100u);
    EXPECT_GT(cache.stats().proxyUploads, 0u);
    EXPECT_GT(cache.stats().evictions, 10u); // the pools hold fewer proxies than were asked for
}

// The per-trace upload limit (the viewer's streaming) with packed proxy pools: it holds while the pools fill (traces
// left incomplete), and once a pool must evict a proxy of the current trace to place another, later traces could not
// do better, so the limit lifts and a trace completes — although the proxies asked for never fit at once.
TEST_P(GpuSubtreeCacheTest, UploadLimitLiftsOnceAProxyPoolHoldsOnlyThisTracesProxies) {
    outofcore::GpuCacheOptions options{3 * slotBytes(), CachePolicy::Lru};
    options.lodPixels = 1e9f;
    options.maxUploadsPerTrace = 2;
    GpuSubtreeCache cache(*store_, options);
    cache.setView(glm::vec3(1e6f), 1000.0f);
    std::vector<uint32_t> proxies; // subtrees served as a proxy
    for (uint32_t s = 0; s < chs_->header().subtreeCount; ++s) {
        if (cache.levelFor(s) != 0) proxies.push_back(s);
    }
    ASSERT_GT(proxies.size(), 10u);
    int incomplete = 0, completeAt = -1;
    for (int trace = 0; trace < int(proxies.size()) && completeAt < 0; ++trace) {
        cache.beginTrace();
        const uint64_t before = cache.stats().postponed;
        for (size_t i = 0; i < proxies.size(); i += 2) { // requests of two, as a tracer's residency rounds
            const size_t n = std::min<size_t>(2, proxies.size() - i);
            std::vector<uint32_t> roots(n);
            cache.acquire(std::span<const uint32_t>(proxies.data() + i, n), roots);
        }
        if (cache.stats().postponed == before) completeAt = trace;
        else ++incomplete;
    }
    EXPECT_GT(incomplete, 0) << "the limit never held";
    ASSERT_GE(completeAt, 0) << "no trace completed: the limit never lifted";
    EXPECT_GT(cache.stats().evictions, 0u) << "the proxies asked for fit at once: nothing tested the lift";
}

TEST_P(GpuSubtreeCacheTest, BudgetBelowOneSlotIsAnError) {
    EXPECT_THROW(GpuSubtreeCache(*store_, {slotBytes() - 1, CachePolicy::Lru}), InputError);
}

INSTANTIATE_TEST_SUITE_P(Layouts, GpuSubtreeCacheTest, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& param) { return param.param ? "Compact" : "Full"; });

} // namespace
} // namespace chcrt
