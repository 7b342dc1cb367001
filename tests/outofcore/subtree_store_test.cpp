// The host subtree store: LRU under a byte budget, hits and misses counted, contents equal to the file's.
#include "renderer/core/error.h"
#include "renderer/outofcore/subtree_store.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

namespace chcrt {
namespace {

// What the store holds of subtree i (a whole read, kept as stored: a compact blob is not decoded).
uint64_t storedBytes(const outofcore::ChsFile& chs, uint32_t i) {
    outofcore::SubtreeData d;
    chs.readSubtree(i, 0, d, true, false);
    return d.bytes();
}

TEST(SubtreeStore, KeepsTheMostRecentlyUsedUnderItsBudget) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file, 1000);
    const outofcore::ChsFile chs(file);
    ASSERT_GT(chs.header().subtreeCount, 6u);
    uint64_t largest = 0;
    for (uint32_t i = 0; i < 6; ++i) largest = std::max(largest, storedBytes(chs, i));
    outofcore::SubtreeStore store(chs, 3 * largest);
    for (uint32_t i = 0; i < 6; ++i) {
        const auto d = store.get(i);
        EXPECT_EQ(d->nodeCount(), chs.subtrees()[i].nodeCount);
        EXPECT_LE(store.stats().residentBytes, store.budgetBytes());
    }
    EXPECT_EQ(store.stats().misses, 6u);
    EXPECT_GT(store.stats().evictions, 0u);
    store.get(5); // most recent: still there
    EXPECT_EQ(store.stats().hits, 1u);
    store.get(0); // oldest: evicted, read again
    EXPECT_EQ(store.stats().misses, 7u);
    EXPECT_LE(store.stats().peakResidentBytes, store.budgetBytes());
    const auto again = store.get(0);
    const outofcore::SubtreeData direct = chs.readSubtree(0);
    EXPECT_TRUE(test::sameContents(*again, direct));
    ASSERT_EQ(again->triangleCount(), direct.triangles.size()); // the store keeps a compact blob compact
    for (size_t k = 0; k < direct.triangles.size(); ++k) {
        const TriangleGpu t = again->triangle(k);
        ASSERT_EQ(std::memcmp(&t, &direct.triangles[k], sizeof(TriangleGpu)), 0) << "triangle " << k;
    }
}

} // namespace
} // namespace chcrt

namespace chcrt {
namespace {

// Evicted subtrees' buffers are read into again (subtree_store.h, SubtreeBuffers): what a read into them returns
// equals a fresh read, whole and for the GPU alone, and the store counts the memory they hold.
TEST(SubtreeStore, RecycledBuffersHoldWhatAFreshReadHolds) {
    for (const bool compact : {true, false}) {
        SCOPED_TRACE(compact ? "compact layout" : "full layout");
        test::ScratchDir dir;
        const auto file = dir.file("city.chs");
        test::prepareSmall("city:20k", file, 1000, 256ull << 20, compact);
        const outofcore::ChsFile chs(file);
        const uint32_t count = chs.header().subtreeCount;
        ASSERT_GE(count, 6u);
        outofcore::SubtreeStore store(chs, 1); // keeps nothing: every get() reads, every subtree leaves at once
        for (int pass = 0; pass < 2; ++pass) {
            for (uint32_t i = 0; i < count; ++i) {
                const bool attributes = (i + uint32_t(pass)) % 2 == 0;
                const std::shared_ptr<const outofcore::SubtreeData> got = store.get(count - 1 - i, 0, attributes);
                outofcore::SubtreeData fresh;
                chs.readSubtree(count - 1 - i, 0, fresh, true, false); // as the store reads, into fresh buffers
                ASSERT_TRUE(test::sameContents(*got, fresh)) << "subtree " << count - 1 - i;
                if (got->attributes) {
                    ASSERT_EQ(got->normals.size(), fresh.normals.size());
                    EXPECT_EQ(std::memcmp(got->normals.data(), fresh.normals.data(),
                                          fresh.normals.size() * sizeof(glm::vec3)), 0);
                    for (size_t k = 0; k < fresh.triangleCount(); ++k) {
                        const TriangleGpu a = got->triangle(k), b = fresh.triangle(k);
                        ASSERT_EQ(std::memcmp(&a, &b, sizeof(TriangleGpu)), 0);
                    }
                } else {
                    EXPECT_FALSE(attributes);
                }
                EXPECT_GE(got->bytes(), got->readBytes());
            }
        }
        EXPECT_EQ(store.stats().residentBytes, 0u);
    }
}

TEST(SubtreeStore, PrefetchedSubtreesAreHits) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file, 1000);
    const outofcore::ChsFile chs(file);
    outofcore::SubtreeStore store(chs, 64ull << 20);
    const std::vector<uint32_t> wanted = {3, 1, 4};
    store.prefetch(wanted);
    store.waitForPrefetch();
    EXPECT_EQ(store.stats().prefetched, 3u);
    for (uint32_t s : wanted) EXPECT_EQ(store.get(s)->nodeCount(), chs.subtrees()[s].nodeCount);
    EXPECT_EQ(store.stats().hits, 3u);
    EXPECT_EQ(store.stats().misses, 3u); // the prefetch reads, none by get()
    store.prefetch(std::vector<uint32_t>{1, 5}); // 1 is resident: only 5 is read
    store.waitForPrefetch();
    EXPECT_EQ(store.stats().prefetched, 4u);
}

} // namespace
} // namespace chcrt

namespace chcrt {
namespace {

// The file changes under an open store (another process truncates or rewrites it while a walkthrough renders):
// subtrees read before stay valid in memory, and each later read fails with an InputError naming the file and the
// subtree (a truncated read, or the subtree's checksum against the directory read at open), never with garbage.
TEST(SubtreeStore, AFileTruncatedOrOverwrittenUnderItFailsTheReadsNamingFileAndSubtree) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file, 1000);
    const outofcore::ChsFile chs(file);
    const uint32_t count = chs.header().subtreeCount;
    ASSERT_GE(count, 4u);
    outofcore::SubtreeStore store(chs, 64ull << 20);
    ASSERT_NE(store.get(0), nullptr);
    const auto expectFailure = [&](uint32_t subtree, const std::string& what) {
        try {
            store.get(subtree);
            ADD_FAILURE() << "subtree " << subtree << " was read";
        } catch (const InputError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(file.string()), std::string::npos) << message;
            EXPECT_NE(message.find("subtree " + std::to_string(subtree)), std::string::npos) << message;
            EXPECT_NE(message.find(what), std::string::npos) << message;
        }
    };

    // Overwritten in place (same size, other bytes): every subtree but the first one's blob gets new content.
    const auto original = test::readBytes(file);
    std::vector<char> overwritten = original;
    const uint64_t from = chs.subtrees()[1].offset;
    for (uint64_t i = from; i < chs.header().metaOffset; ++i) overwritten[i] = char(0xA5);
    test::writeBytes(file, overwritten);
    expectFailure(1, "checksum mismatch");
    expectFailure(count - 1, "checksum mismatch");
    EXPECT_EQ(store.get(0)->nodeCount(), chs.subtrees()[0].nodeCount) << "read before the change: kept";

    // Truncated just after the first subtree.
    std::filesystem::resize_file(file, from);
    expectFailure(2, "file is truncated");
    expectFailure(count - 1, "file is truncated");
    EXPECT_EQ(store.stats().residentBytes, store.get(0)->bytes()) << "nothing of the failed reads was kept";
}

} // namespace
} // namespace chcrt

namespace chcrt {
namespace {

// Prefetch is a guess and yields to the frames (subtree_store.h): it never evicts a subtree used in the current or
// the previous frame (it skips instead), stays under the budget, stops at its byte limit, counts each prefetched
// subtree's first use as a hit once, and counts the bytes of prefetched subtrees evicted before any use as waste.
TEST(SubtreeStore, PrefetchYieldsToTheFramesSubtreesAndCountsHitsAndWaste) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file, 1000);
    const outofcore::ChsFile chs(file);
    const uint32_t count = chs.header().subtreeCount;
    ASSERT_GT(count, 12u);
    std::vector<uint64_t> bytes(count);
    for (uint32_t i = 0; i < count; ++i) bytes[i] = storedBytes(chs, i);
    // Subtrees 0, 1 and 2 fill the budget exactly: any more needs an eviction.
    outofcore::SubtreeStore store(chs, bytes[0] + bytes[1] + bytes[2]);
    store.get(0);
    store.get(1);
    store.advanceFrame(); // 0 and 1 were used in the previous frame: protected
    store.prefetch(std::vector<uint32_t>{2, 3, 4});
    store.waitForPrefetch();
    outofcore::SubtreeStoreStats s = store.stats();
    // 2 fits beside 0 and 1; 3 and 4 would need one of 0, 1 (previous frame) or 2 (this frame) evicted.
    EXPECT_EQ(s.prefetched, 1u);
    EXPECT_EQ(s.prefetchSkipped, 2u);
    EXPECT_EQ(s.evictions, 0u);
    EXPECT_TRUE(store.contains(0) && store.contains(1) && store.contains(2));
    EXPECT_FALSE(store.contains(3) || store.contains(4));
    store.get(2);
    store.get(2);
    EXPECT_EQ(store.stats().prefetchHits, 1u) << "a prefetched subtree's first use only";

    // Two subtrees that fit the budget together, and a third.
    uint32_t x = 0, y = 0, z = 0;
    for (uint32_t a = 5; a < count && x == 0; ++a) {
        for (uint32_t b = a + 1; b < count && x == 0; ++b) {
            if (bytes[a] + bytes[b] <= store.budgetBytes()) x = a, y = b;
        }
    }
    ASSERT_NE(x, 0u);
    for (uint32_t c = 5; c < count && z == 0; ++c) {
        if (c != x && c != y && bytes[c] <= store.budgetBytes()) z = c;
    }
    ASSERT_NE(z, 0u);

    // Two frames on, 0, 1 and 2 were last used before the previous frame: a prefetch may evict them.
    store.advanceFrame();
    store.advanceFrame();
    store.prefetch(std::vector<uint32_t>{x, y});
    store.waitForPrefetch();
    EXPECT_TRUE(store.contains(x) && store.contains(y));
    EXPECT_EQ(store.stats().prefetched, 3u);
    EXPECT_LE(store.stats().peakResidentBytes, store.budgetBytes());

    // A guess never displaces an earlier guess that no get() has used, however old: z waits while x and y fill
    // the store unused (else guesses that outnumber the store are read and evicted frame after frame).
    store.advanceFrame();
    store.advanceFrame();
    const uint64_t skipped = store.stats().prefetchSkipped;
    store.prefetch(std::vector<uint32_t>{z});
    store.waitForPrefetch();
    EXPECT_FALSE(store.contains(z));
    EXPECT_TRUE(store.contains(x) && store.contains(y));
    EXPECT_EQ(store.stats().prefetchSkipped, skipped + 1);
    EXPECT_EQ(store.stats().prefetched, 3u);

    // Once used, x and y are ordinary entries again; two frames on, a prefetch may evict them. The byte limit of
    // one call: only the first subtree fits.
    store.get(x);
    store.get(y);
    EXPECT_EQ(store.stats().prefetchHits, 3u);
    store.advanceFrame();
    store.advanceFrame();
    store.prefetch(std::vector<uint32_t>{z, 3}, chs.subtrees()[z].bytes);
    store.waitForPrefetch();
    EXPECT_TRUE(store.contains(z));
    EXPECT_FALSE(store.contains(3));
    EXPECT_EQ(store.stats().prefetched, 4u);

    // The frame's own reads evict anything; z leaves unused: its bytes are waste.
    for (uint32_t i = 5; i < count && store.contains(z); ++i) {
        if (i != x && i != y && i != z) store.get(i);
    }
    ASSERT_FALSE(store.contains(z));
    s = store.stats();
    EXPECT_EQ(s.prefetchWastedBytes, bytes[z]);
    EXPECT_EQ(s.prefetchHits, 3u);
    EXPECT_LE(s.peakResidentBytes, store.budgetBytes());
}

// Guesses no get() has used count against the next lists' bytes: while a list's worth waits unused nothing more is
// read (a walkthrough whose guesses are never used stops reading after one list), and using one makes room again.
TEST(SubtreeStore, UnusedGuessesHoldBackFurtherPrefetches) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file, 1000);
    const outofcore::ChsFile chs(file);
    ASSERT_GE(chs.header().subtreeCount, 8u);
    outofcore::SubtreeStore store(chs, 64ull << 20); // room for all: only the rule below holds prefetches back
    const uint64_t budget = chs.subtrees()[0].bytes + chs.subtrees()[1].bytes;
    store.prefetch(std::vector<uint32_t>{0, 1, 2}, budget); // 0 and 1 fit the list's bytes
    store.waitForPrefetch();
    EXPECT_EQ(store.stats().prefetched, 2u);
    store.advanceFrame();
    const uint64_t later = std::max(budget, chs.subtrees()[3].bytes); // would hold subtree 3 by itself
    store.prefetch(std::vector<uint32_t>{3, 4}, later); // 0 and 1 unused: nothing more
    store.waitForPrefetch();
    EXPECT_EQ(store.stats().prefetched, 2u);
    EXPECT_FALSE(store.contains(3) || store.contains(4));
    store.get(0); // guesses used: their bytes are free for guesses again
    store.get(1);
    store.prefetch(std::vector<uint32_t>{3, 4}, later);
    store.waitForPrefetch();
    EXPECT_GE(store.stats().prefetched, 3u);
    EXPECT_TRUE(store.contains(3));
    EXPECT_EQ(store.stats().prefetchHits, 2u);
}

} // namespace
} // namespace chcrt
