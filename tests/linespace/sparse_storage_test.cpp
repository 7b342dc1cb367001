// Sparse storage (Algorithm 2): lookups equal the dense oracle for every shaft of random Line Spaces at every
// fill rate, offsets are the prefix sums, and inconsistent pools (as from a corrupt cache) are rejected.
#include "linespace/shaft_index.h"
#include "linespace/sparse_storage.h"
#include "tests/linespace/linespace_test_util.h"

#include <gtest/gtest.h>

namespace chcrt::ls {
namespace {

TEST(SparseStorage, LookupEqualsDenseForEveryShaft) {
    test::Rng rng{5};
    for (const uint32_t n : {1u, 3u, 4u, 6u}) {
        const uint32_t shafts = lsShaftCount(n, false);
        SparseShaftStore store(shafts);
        std::vector<std::vector<uint32_t>> dense;
        const uint32_t fills[] = {0, 3, 50, 97, 100}; // percent, including empty and full Line Spaces
        for (const uint32_t fill : fills) {
            std::vector<uint32_t> values(shafts);
            for (uint32_t& v : values) {
                v = rng.below(100) < fill ? rng.below(1u << 30) : kEmptyShaft;
            }
            EXPECT_EQ(store.append(values), dense.size());
            dense.push_back(std::move(values));
        }
        for (uint32_t space = 0; space < dense.size(); ++space) {
            for (uint32_t s = 0; s < shafts; ++s) {
                ASSERT_EQ(store.lookup(space, s), dense[space][s]) << "N=" << n << " space " << space << " shaft " << s;
                ASSERT_EQ(store.filled(space, s), dense[space][s] != kEmptyShaft);
            }
        }
        EXPECT_EQ(store.spaceCount(), dense.size());
        // Data holds only the filled shafts.
        uint64_t filled = 0;
        for (const auto& d : dense) {
            filled += static_cast<uint64_t>(std::count_if(d.begin(), d.end(), [](uint32_t v) { return v != kEmptyShaft; }));
        }
        EXPECT_EQ(store.filledCount(), filled);
        EXPECT_EQ(store.bytes(), 4 * (2 * uint64_t(store.wordsPerSpace()) * dense.size() + filled));
    }
}

TEST(SparseStorage, PaperExampleSlot) {
    // Bits 1, 4, 31 set; offset 10: shaft 4 is the second filled shaft of the word -> slot 11.
    const uint32_t word = (1u << 1) | (1u << 4) | (1u << 31);
    EXPECT_EQ(gpu::lsSparseSlot(word, 10, 1), 10u);
    EXPECT_EQ(gpu::lsSparseSlot(word, 10, 4), 11u);
    EXPECT_EQ(gpu::lsSparseSlot(word, 10, 31), 12u);
    EXPECT_EQ(gpu::lsSparseSlot(word, 10, 32 + 4), 11u); // only shaft % 32 matters within the word
    EXPECT_EQ(gpu::lsSparseSlot(word, 10, 0), CHCRT_LS_EMPTY_SLOT);
}

TEST(SparseStorage, FromPoolsRejectsInconsistentPools) {
    SparseShaftStore store(100);
    std::vector<uint32_t> dense(100, kEmptyShaft);
    dense[3] = 7;
    dense[64] = 8;
    dense[99] = 9;
    store.append(dense);
    store.append(dense);
    SparseShaftStore copy;
    ASSERT_TRUE(SparseShaftStore::fromPools(100, store.words(), store.offsets(), store.data(), copy));
    EXPECT_EQ(copy.lookup(1, 64), 8u);
    auto offsets = store.offsets();
    offsets[2] += 1;
    EXPECT_FALSE(SparseShaftStore::fromPools(100, store.words(), offsets, store.data(), copy));
    auto words = store.words();
    words[3] |= 1u << 10; // bit past shaft 99 in the last word
    EXPECT_FALSE(SparseShaftStore::fromPools(100, words, store.offsets(), store.data(), copy));
    auto data = store.data();
    data.pop_back();
    EXPECT_FALSE(SparseShaftStore::fromPools(100, store.words(), store.offsets(), data, copy));
    EXPECT_FALSE(SparseShaftStore::fromPools(100, {1, 2, 3}, {0, 1, 2}, {5, 6, 7, 8}, copy));
}

} // namespace
} // namespace chcrt::ls
