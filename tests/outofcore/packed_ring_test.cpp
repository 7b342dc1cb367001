// PackedRing (culling/outofcore/packed_ring.h), the LOD proxy pools' allocation: over random sizes, pins and
// orders, resident entries stay within their parts and never overlap, pinned entries are never evicted, what a
// placement reports evicted is exactly what left, a failed placement changes nothing, and entries whose sizes sum
// to within the capacity are all placed without an eviction.
#include "culling/outofcore/packed_ring.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>

namespace chcrt {
namespace {

using outofcore::PackedRing;

// Every resident entry within its part's capacity, none overlapping another in any part.
void expectDisjointWithinCapacity(const PackedRing& ring, const std::set<uint32_t>& resident,
                                  const std::vector<PackedRing::Units>& sizes) {
    for (size_t p = 0; p < PackedRing::kParts; ++p) {
        std::vector<std::pair<uint64_t, uint64_t>> ranges; // [begin, end)
        for (uint32_t key : resident) {
            if (sizes[key][p] == 0) continue;
            const uint64_t begin = ring.offset(key)[p];
            ranges.emplace_back(begin, begin + sizes[key][p]);
            ASSERT_LE(begin + sizes[key][p], ring.capacity()[p]) << "part " << p << " key " << key;
        }
        std::sort(ranges.begin(), ranges.end());
        for (size_t k = 1; k < ranges.size(); ++k) ASSERT_LE(ranges[k - 1].second, ranges[k].first) << "part " << p;
    }
}

TEST(PackedRing, RandomPlacementsKeepEntriesDisjointAndPinnedOnesResident) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 40; ++trial) {
        const PackedRing::Units capacity{100 + rng() % 900, 100 + rng() % 900, trial % 2 ? 0u : 100 + rng() % 900};
        const uint32_t keys = 200;
        std::vector<PackedRing::Units> sizes(keys);
        for (PackedRing::Units& s : sizes) {
            for (size_t p = 0; p < PackedRing::kParts; ++p) s[p] = capacity[p] == 0 ? 0 : 1 + rng() % (capacity[p] / 4);
        }
        PackedRing ring(capacity, keys);
        std::set<uint32_t> resident;
        uint64_t evictions = 0, failures = 0;
        for (int step = 0; step < 400; ++step) {
            const uint32_t key = uint32_t(rng() % keys);
            if (resident.count(key)) continue;
            std::set<uint32_t> pinned; // about a fifth of the resident entries
            for (uint32_t r : resident) {
                if (rng() % 5 == 0) pinned.insert(r);
            }
            std::vector<uint32_t> evicted;
            const bool placed = ring.place(key, sizes[key], [&](uint32_t k) { return pinned.count(k) != 0; }, evicted);
            if (!placed) {
                ASSERT_TRUE(evicted.empty());
                ++failures;
            }
            for (uint32_t e : evicted) {
                ASSERT_EQ(resident.erase(e), 1u) << "evicted an entry that was not resident";
                ASSERT_EQ(pinned.count(e), 0u) << "evicted a pinned entry";
                ++evictions;
            }
            if (placed) resident.insert(key);
            for (uint32_t k = 0; k < keys; ++k) ASSERT_EQ(ring.resident(k), resident.count(k) != 0) << "key " << k;
            expectDisjointWithinCapacity(ring, resident, sizes);
        }
        EXPECT_GT(evictions, 0u); // 200 keys of up to a quarter of the capacity each cannot all stay
        (void)failures;
    }
}

TEST(PackedRing, EntriesThatFitTogetherAreAllPlacedWithoutEvictions) {
    std::mt19937 rng(4);
    std::vector<PackedRing::Units> sizes(50);
    PackedRing::Units total{};
    for (PackedRing::Units& s : sizes) {
        s = {1 + rng() % 40, 1 + rng() % 40, rng() % 3 == 0 ? 0u : 1 + rng() % 40};
        for (size_t p = 0; p < PackedRing::kParts; ++p) total[p] += s[p];
    }
    PackedRing ring(total, uint32_t(sizes.size())); // exactly the sum: the cache's pool when all of a level fits
    std::vector<uint32_t> evicted;
    for (uint32_t key = 0; key < sizes.size(); ++key) {
        ASSERT_TRUE(ring.place(key, sizes[key], [](uint32_t) { return false; }, evicted));
    }
    EXPECT_TRUE(evicted.empty());
    for (uint32_t key = 0; key < sizes.size(); ++key) EXPECT_TRUE(ring.resident(key));
}

TEST(PackedRing, PinnedEntriesThatFillThePartMakeAPlacementFail) {
    PackedRing ring({10, 10, 0}, 4);
    std::vector<uint32_t> evicted;
    const auto none = [](uint32_t) { return false; };
    ASSERT_TRUE(ring.place(0, {4, 4, 0}, none, evicted));
    ASSERT_TRUE(ring.place(1, {4, 4, 0}, none, evicted));
    EXPECT_FALSE(ring.fits({11, 1, 0}));
    // 2 units left before the end, and pinned entries everywhere else: no place for 3 units.
    EXPECT_FALSE(ring.place(2, {3, 1, 0}, [](uint32_t k) { return k <= 1; }, evicted));
    EXPECT_TRUE(evicted.empty());
    EXPECT_TRUE(ring.resident(0) && ring.resident(1) && !ring.resident(2));
    // Entry 1 pinned: the cursor starts again from the beginning and evicts entry 0 only.
    ASSERT_TRUE(ring.place(2, {3, 1, 0}, [](uint32_t k) { return k == 1; }, evicted));
    EXPECT_EQ(evicted, std::vector<uint32_t>{0});
    EXPECT_EQ(ring.offset(2)[0], 0u);
    EXPECT_TRUE(ring.resident(1));
}

} // namespace
} // namespace chcrt
