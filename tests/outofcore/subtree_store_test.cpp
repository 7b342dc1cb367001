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

TEST(SubtreeStore, KeepsTheMostRecentlyUsedUnderItsBudget) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file, 1000);
    const outofcore::ChsFile chs(file);
    ASSERT_GT(chs.header().subtreeCount, 6u);
    uint64_t largest = 0;
    for (uint32_t i = 0; i < 6; ++i) largest = std::max(largest, chs.readSubtree(i).bytes());
    outofcore::SubtreeStore store(chs, 3 * largest);
    for (uint32_t i = 0; i < 6; ++i) {
        const auto d = store.get(i);
        EXPECT_EQ(d->nodes.size(), chs.subtrees()[i].nodeCount);
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
    ASSERT_EQ(again->triangles.size(), direct.triangles.size());
    EXPECT_EQ(0, std::memcmp(again->triangles.data(), direct.triangles.data(), direct.triangles.size() * sizeof(TriangleGpu)));
}

} // namespace
} // namespace chcrt

namespace chcrt {
namespace {

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
    for (uint32_t s : wanted) EXPECT_EQ(store.get(s)->nodes.size(), chs.subtrees()[s].nodeCount);
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
    EXPECT_EQ(store.get(0)->nodes.size(), chs.subtrees()[0].nodeCount) << "read before the change: kept";

    // Truncated just after the first subtree.
    std::filesystem::resize_file(file, from);
    expectFailure(2, "file is truncated");
    expectFailure(count - 1, "file is truncated");
    EXPECT_EQ(store.stats().residentBytes, store.get(0)->bytes()) << "nothing of the failed reads was kept";
}

} // namespace
} // namespace chcrt
