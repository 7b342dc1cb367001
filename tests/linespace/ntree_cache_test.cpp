// N-tree disk cache (linespace/ntree_cache.h): a hit loads the same tree, other parameters or another scene
// build anew, and damage of any kind (bytes, length, a file under the wrong key, a structurally wrong tree with
// a valid checksum) is detected and rebuilt, never trusted.
#include "linespace/ntree_cache.h"
#include "linespace/shaft_index.h"
#include "tests/linespace/linespace_test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

namespace chcrt::ls {
namespace {

class NTreeCacheTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() /
               ("chcrt_ntree_cache_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::remove_all(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    size_t fileCount() const {
        return size_t(std::distance(std::filesystem::directory_iterator(dir_), std::filesystem::directory_iterator()));
    }
    std::filesystem::path dir_;
};

NTreeParams params(uint32_t n, uint32_t depth) {
    NTreeParams p;
    p.n = n;
    p.depth = depth;
    return p;
}

void expectSame(const NTree& a, const NTree& b) {
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(NTreeNode)), 0);
    EXPECT_EQ(a.triangleRefs, b.triangleRefs);
    EXPECT_EQ(a.binaryWords, b.binaryWords);
    EXPECT_EQ(a.stats.nodeCount, b.stats.nodeCount);
    EXPECT_EQ(a.stats.subdividedCount, b.stats.subdividedCount);
    EXPECT_EQ(a.stats.binaryFilled, b.stats.binaryFilled);
    EXPECT_EQ(a.stats.binaryShafts, b.stats.binaryShafts);
    EXPECT_EQ(a.stats.lineSpaceBytes, b.stats.lineSpaceBytes);
    EXPECT_EQ(a.stats.nodeBytes, b.stats.nodeBytes);
}

std::vector<char> readBytes(const std::filesystem::path& file) {
    std::vector<char> bytes(std::filesystem::file_size(file));
    std::ifstream(file, std::ios::binary).read(bytes.data(), std::streamsize(bytes.size()));
    return bytes;
}

void writeBytes(const std::filesystem::path& file, const std::vector<char>& bytes) {
    std::ofstream(file, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
}

TEST_F(NTreeCacheTest, HitLoadsTheSameTreeAndParametersOrSceneChangesRebuild) {
    const Bvh bvh = buildBvh(test::makeScene(test::randomSoup(800, 21)));
    CacheOutcome outcome{};
    const NTree built = loadOrBuildNTree(bvh, params(4, 2), dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Built);
    ASSERT_GT(built.stats.subdividedCount, 1u);
    const std::filesystem::path file = nTreeCachePath(dir_, nTreeInputHash(bvh), params(4, 2));
    ASSERT_TRUE(std::filesystem::exists(file));
    EXPECT_EQ(fileCount(), 1u); // no temporary file left behind

    const NTree loaded = loadOrBuildNTree(bvh, params(4, 2), dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Loaded);
    expectSame(built, loaded);
    EXPECT_EQ(built.stats.buildSeconds, loaded.stats.buildSeconds); // stored: reports show what the build cost

    // Each parameter is part of the key: a change builds (a new file), the old file still loads.
    for (const NTreeParams& other : {params(3, 2), params(2, 3)}) { // not (4, 3): 80 % of this test, 47 s under ASan
        const NTree tree = loadOrBuildNTree(bvh, other, dir_, nullProgress(), &outcome);
        EXPECT_EQ(outcome, CacheOutcome::Built) << other.toString();
        expectSame(tree, buildNTree(bvh, other));
    }
    EXPECT_EQ(fileCount(), 3u);
    loadOrBuildNTree(bvh, params(4, 2), dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Loaded);
    // The thread count is not: the tree does not depend on it.
    NTreeParams oneThread = params(4, 2);
    oneThread.threads = 1;
    loadOrBuildNTree(bvh, oneThread, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Loaded);

    // Another scene (here: one vertex moved) has another key and builds its own tree.
    Scene movedScene = test::makeScene(test::randomSoup(800, 21));
    movedScene.positions[0] += glm::vec3(0.25f);
    const Bvh moved = buildBvh(movedScene);
    EXPECT_NE(nTreeInputHash(moved), nTreeInputHash(bvh));
    const NTree movedTree = loadOrBuildNTree(moved, params(4, 2), dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Built);
    expectSame(movedTree, buildNTree(moved, params(4, 2)));

    // No cache directory: always builds, writes nothing.
    loadOrBuildNTree(bvh, params(4, 2), {}, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Built);
    EXPECT_EQ(fileCount(), 4u);
}

TEST_F(NTreeCacheTest, DamagedFilesAreDetectedAndRebuilt) {
    const Bvh bvh = buildBvh(test::makeScene(test::randomSoup(600, 22)));
    const NTreeParams p = params(3, 2);
    CacheOutcome outcome{};
    const NTree built = loadOrBuildNTree(bvh, p, dir_, nullProgress(), &outcome);
    const uint64_t hash = nTreeInputHash(bvh);
    const std::filesystem::path file = nTreeCachePath(dir_, hash, p);
    const std::vector<char> original = readBytes(file);
    const size_t size = original.size();
    ASSERT_GT(size, 200u);

    // A flipped byte anywhere (magic, version, parameters, hash, size, checksum, payload), truncation, extra bytes.
    for (const size_t position : {size_t(0), size_t(8), size_t(12), size_t(16), size_t(33), size_t(40), size_t(48),
                                  size_t(56), size / 2, size - 9, size - 1}) {
        std::vector<char> damaged = original;
        damaged[position] ^= 0x10;
        writeBytes(file, damaged);
        NTree out;
        EXPECT_EQ(loadNTreeCache(file, bvh, hash, p, out), CacheLoad::Corrupt) << "byte " << position;
    }
    for (const size_t length : {size_t(0), size_t(30), size_t(56), size - 4}) {
        writeBytes(file, std::vector<char>(original.begin(), original.begin() + std::ptrdiff_t(length)));
        NTree out;
        EXPECT_EQ(loadNTreeCache(file, bvh, hash, p, out), CacheLoad::Corrupt) << "length " << length;
    }
    std::vector<char> longer = original;
    longer.push_back(0);
    writeBytes(file, longer);
    NTree out;
    EXPECT_EQ(loadNTreeCache(file, bvh, hash, p, out), CacheLoad::Corrupt);

    // A corrupt file is rebuilt and replaced, giving the same tree; then it loads again.
    const NTree rebuilt = loadOrBuildNTree(bvh, p, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::RebuiltCorrupt);
    expectSame(built, rebuilt);
    loadOrBuildNTree(bvh, p, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Loaded);

    // Files under the wrong key: another scene's name, other parameters' name.
    const Bvh otherBvh = buildBvh(test::makeScene(test::randomSoup(600, 23)));
    std::filesystem::copy_file(file, nTreeCachePath(dir_, nTreeInputHash(otherBvh), p));
    loadOrBuildNTree(otherBvh, p, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::RebuiltCorrupt);
    std::filesystem::copy_file(file, nTreeCachePath(dir_, hash, params(3, 3)));
    loadOrBuildNTree(bvh, params(3, 3), dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::RebuiltCorrupt);
}

// Checksums only catch accidental damage; a well-formed file whose tree does not fit the scene (written by a
// buggy or other build) must not reach the GPU pools either.
TEST_F(NTreeCacheTest, StructurallyWrongTreesWithValidChecksumsAreRejected) {
    const Bvh bvh = buildBvh(test::makeScene(test::randomSoup(600, 24)));
    const NTreeParams p = params(3, 2); // 15 * 3^4 = 1215 shafts: the last bitset word has an unused bit
    ASSERT_NE(lsShaftCount(3, true) % 32u, 0u);
    const NTree built = buildNTree(bvh, p);
    const uint64_t hash = nTreeInputHash(bvh);
    const std::filesystem::path file = nTreeCachePath(dir_, hash, p);
    saveNTreeCache(file, hash, built);
    NTree out;
    ASSERT_EQ(loadNTreeCache(file, bvh, hash, p, out), CacheLoad::Loaded);
    expectSame(built, out);

    uint32_t subdividedChild = 0; // a subdivided node below the root
    for (uint32_t i = 1; i < built.nodes.size() && subdividedChild == 0; ++i) {
        if (built.nodes[i].firstChild != kNoChild) subdividedChild = i;
    }
    ASSERT_NE(subdividedChild, 0u);
    const uint32_t words = lsWordCount(3, true);
    const auto damages = std::vector<std::pair<const char*, void (*)(NTree&, uint32_t, uint32_t)>>{
        {"triangle id out of range", [](NTree& t, uint32_t, uint32_t) { t.triangleRefs.back() = 1u << 30; }},
        {"triangle range past the end",
         [](NTree& t, uint32_t node, uint32_t) { t.nodes[node].triangleCount = uint32_t(t.triangleRefs.size()); }},
        {"child pointer", [](NTree& t, uint32_t node, uint32_t) { t.nodes[node].firstChild += 1; }},
        {"child pointer out of range", [](NTree& t, uint32_t node, uint32_t) { t.nodes[node].firstChild = 1u << 30; }},
        {"leaf with children", [](NTree& t, uint32_t, uint32_t) { t.nodes.back().firstChild = 1; }},
        {"Line Space index", [](NTree& t, uint32_t node, uint32_t) { t.nodes[node].space += 1; }},
        {"cell moved", [](NTree& t, uint32_t node, uint32_t) { t.nodes[t.nodes[node].firstChild + 5].lower.y += 0.01f; }},
        {"cell size", [](NTree& t, uint32_t node, uint32_t) { t.nodes[t.nodes[node].firstChild].size *= 2.0f; }},
        {"cell level", [](NTree& t, uint32_t node, uint32_t) { t.nodes[t.nodes[node].firstChild].level = 7; }},
        {"root moved", [](NTree& t, uint32_t, uint32_t) { t.nodes[0].lower.x -= 0.5f; }},
        {"NaN root", [](NTree& t, uint32_t, uint32_t) { t.nodes[0].size = std::nanf(""); }},
        {"missing nodes", [](NTree& t, uint32_t, uint32_t) { t.nodes.pop_back(); }},
        {"extra nodes", [](NTree& t, uint32_t, uint32_t) { t.nodes.push_back(t.nodes.back()); }},
        {"bitset words missing", [](NTree& t, uint32_t, uint32_t) { t.binaryWords.pop_back(); }},
        {"bit past the last shaft", [](NTree& t, uint32_t, uint32_t w) { t.binaryWords[w - 1] |= 0x80000000u; }},
    };
    for (const auto& [what, damage] : damages) {
        NTree tree = built;
        damage(tree, subdividedChild, words);
        saveNTreeCache(file, hash, tree);
        NTree loaded;
        EXPECT_EQ(loadNTreeCache(file, bvh, hash, p, loaded), CacheLoad::Corrupt) << what;
        CacheOutcome outcome{};
        const NTree rebuilt = loadOrBuildNTree(bvh, p, dir_, nullProgress(), &outcome);
        EXPECT_EQ(outcome, CacheOutcome::RebuiltCorrupt) << what;
        expectSame(built, rebuilt);
    }
}

} // namespace
} // namespace chcrt::ls
