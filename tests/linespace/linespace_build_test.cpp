// Line Spaces on a BVH: the node cut by depth D and threshold T covers every triangle exactly once, the build
// is independent of the thread count, its binary bits equal the single-node builder's, and the cache round
// trip restores the same Line Spaces while corrupt or mismatching files are detected and rebuilt.
#include "linespace/binary_linespace.h"
#include "linespace/linespace_build.h"
#include "linespace/linespace_cache.h"
#include "linespace/shaft_geometry.h"
#include "linespace/shaft_index.h"
#include "linespace/subtree_query.h"
#include "renderer/core/error.h"
#include "tests/linespace/linespace_test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace chcrt::ls {
namespace {

Bvh soupBvh(uint32_t count, uint32_t seed) { return buildBvh(test::makeScene(test::randomSoup(count, seed))); }

uint32_t nodeDepth(const Bvh& bvh, uint32_t target) {
    std::vector<std::pair<uint32_t, uint32_t>> stack{{0u, 0u}};
    while (!stack.empty()) {
        const auto [node, depth] = stack.back();
        stack.pop_back();
        if (node == target) {
            return depth;
        }
        if (!bvh.isLeaf(node)) {
            stack.push_back({bvh.nodes[node].leftFirst, depth + 1});
            stack.push_back({bvh.nodes[node].leftFirst + 1, depth + 1});
        }
    }
    return ~0u;
}

TEST(LineSpaceBuild, SelectionIsACutByDepthAndThreshold) {
    const Bvh bvh = soupBvh(3000, 6);
    const std::vector<TriangleRange> ranges = subtreeTriangleRanges(bvh);
    for (const uint32_t depth : {0u, 2u, 5u, 9u}) {
        for (const uint32_t threshold : {1u, 8u, 64u}) {
            const std::vector<uint32_t> nodes = selectLineSpaceNodes(bvh, depth, threshold);
            std::vector<int> covered(bvh.triangles.size(), 0);
            for (const uint32_t node : nodes) {
                const uint32_t d = nodeDepth(bvh, node);
                EXPECT_LE(d, depth);
                // Above depth D only small subtrees or leaves end the cut.
                EXPECT_TRUE(d == depth || ranges[node].count < threshold || bvh.isLeaf(node));
                for (uint32_t i = 0; i < ranges[node].count; ++i) {
                    ++covered[ranges[node].first + i];
                }
            }
            EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }))
                << "D=" << depth << " T=" << threshold;
        }
    }
    EXPECT_EQ(selectLineSpaceNodes(bvh, 0, 8), std::vector<uint32_t>{0u});
}

TEST(LineSpaceBuild, DeterministicAcrossThreadCountsAndEqualToNodeBuilder) {
    const Bvh bvh = soupBvh(2500, 7);
    LineSpaceParams params;
    params.n = 3;
    params.depth = 4;
    params.threads = 1;
    const LineSpaces one = buildLineSpaces(bvh, params);
    params.threads = 3;
    const LineSpaces three = buildLineSpaces(bvh, params);
    EXPECT_EQ(one.bvhNodes, three.bvhNodes);
    EXPECT_EQ(one.binaryWords, three.binaryWords);
    EXPECT_EQ(one.candidates.words(), three.candidates.words());
    EXPECT_EQ(one.candidates.offsets(), three.candidates.offsets());
    EXPECT_EQ(one.candidates.data(), three.candidates.data());
    const double dilation = shaftDilationForScene(bvh.rootBounds());
    for (uint32_t space = 0; space < one.bvhNodes.size(); space += 3) {
        const std::vector<uint32_t> words = computeBinaryLineSpace(bvh, one.bvhNodes[space], params.n, dilation);
        const uint32_t perSpace = one.binaryWordsPerSpace();
        EXPECT_TRUE(std::equal(words.begin(), words.end(), one.binaryWords.begin() + space * perSpace));
        EXPECT_EQ(one.spaceOfBvhNode[one.bvhNodes[space]], space);
    }
    const LineSpaceStats& s = one.stats;
    EXPECT_EQ(s.spaceCount, one.bvhNodes.size());
    EXPECT_EQ(s.binaryShafts, uint64_t(s.spaceCount) * lsShaftCount(params.n, true));
    EXPECT_GT(s.binaryFilled, 0u);
    EXPECT_LT(s.binaryFilled, s.binaryShafts);
    EXPECT_LE(s.candidateFilled, 2 * s.binaryFilled);
    EXPECT_EQ(s.totalBytes(), 4 * one.binaryWords.size() + one.candidates.bytes() + 32ull * s.spaceCount);
    EXPECT_THROW(
        [&] {
            LineSpaceParams bad;
            bad.n = 0;
            buildLineSpaces(bvh, bad);
        }(),
        InputError);
}

class LineSpaceCacheTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() /
               ("chcrt_ls_cache_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::remove_all(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::filesystem::path dir_;
};

void expectSame(const LineSpaces& a, const LineSpaces& b) {
    EXPECT_EQ(a.bvhNodes, b.bvhNodes);
    EXPECT_EQ(a.spaceOfBvhNode, b.spaceOfBvhNode);
    EXPECT_EQ(a.binaryWords, b.binaryWords);
    EXPECT_EQ(a.candidates.words(), b.candidates.words());
    EXPECT_EQ(a.candidates.offsets(), b.candidates.offsets());
    EXPECT_EQ(a.candidates.data(), b.candidates.data());
    EXPECT_EQ(a.stats.totalBytes(), b.stats.totalBytes());
    EXPECT_EQ(a.stats.binaryFilled, b.stats.binaryFilled);
}

TEST_F(LineSpaceCacheTest, RoundTripAndCorruptionDetection) {
    const Bvh bvh = soupBvh(1200, 8);
    LineSpaceParams params;
    params.n = 3;
    params.depth = 3;
    CacheOutcome outcome{};
    const LineSpaces built = loadOrBuildLineSpaces(bvh, params, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Built);
    const std::filesystem::path file = lineSpaceCachePath(dir_, lineSpaceInputHash(bvh), params);
    ASSERT_TRUE(std::filesystem::exists(file));
    // No temporary files are left behind.
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_), std::filesystem::directory_iterator()), 1);

    const LineSpaces loaded = loadOrBuildLineSpaces(bvh, params, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Loaded);
    expectSame(built, loaded);

    // Every kind of damage is detected: a flipped byte anywhere (header or payload), truncation, extra bytes.
    const auto size = std::filesystem::file_size(file);
    std::vector<char> original(size);
    std::ifstream(file, std::ios::binary).read(original.data(), std::streamsize(size));
    auto writeFile = [&](const std::vector<char>& bytes) {
        std::ofstream(file, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
    };
    const uint64_t hash = lineSpaceInputHash(bvh);
    for (const size_t position : {size_t(0), size_t(9), size_t(30), size_t(60), size / 2, size - 9, size - 1}) {
        std::vector<char> damaged = original;
        damaged[position] ^= 0x10;
        writeFile(damaged);
        LineSpaces out;
        EXPECT_EQ(loadLineSpaceCache(file, bvh, hash, params, out), CacheLoad::Corrupt) << "byte " << position;
    }
    for (const size_t length : {size_t(0), size_t(20), size - 4}) {
        writeFile(std::vector<char>(original.begin(), original.begin() + std::ptrdiff_t(length)));
        LineSpaces out;
        EXPECT_EQ(loadLineSpaceCache(file, bvh, hash, params, out), CacheLoad::Corrupt) << "length " << length;
    }
    std::vector<char> longer = original;
    longer.push_back(0);
    writeFile(longer);
    LineSpaces out;
    EXPECT_EQ(loadLineSpaceCache(file, bvh, hash, params, out), CacheLoad::Corrupt);

    // A corrupt file is rebuilt (and replaced), giving the same result.
    const LineSpaces rebuilt = loadOrBuildLineSpaces(bvh, params, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::RebuiltCorrupt);
    expectSame(built, rebuilt);
    loadOrBuildLineSpaces(bvh, params, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Loaded);

    // Other parameters or another BVH use other files; a file renamed to the wrong key is not trusted.
    LineSpaceParams other = params;
    other.n = 4;
    loadOrBuildLineSpaces(bvh, other, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Built);
    const Bvh otherBvh = soupBvh(1200, 9);
    EXPECT_NE(lineSpaceInputHash(otherBvh), hash);
    std::filesystem::copy_file(file, lineSpaceCachePath(dir_, lineSpaceInputHash(otherBvh), params));
    loadOrBuildLineSpaces(otherBvh, params, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::RebuiltCorrupt);
}

TEST_F(LineSpaceCacheTest, BinaryOnlyRoundTripAndNoCacheDirectory) {
    const Bvh bvh = soupBvh(600, 10);
    LineSpaceParams params;
    params.n = 2;
    params.depth = 2;
    params.candidates = false;
    CacheOutcome outcome{};
    const LineSpaces built = loadOrBuildLineSpaces(bvh, params, dir_, nullProgress(), &outcome);
    EXPECT_EQ(built.candidates.filledCount(), 0u);
    const LineSpaces loaded = loadOrBuildLineSpaces(bvh, params, dir_, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Loaded);
    expectSame(built, loaded);
    loadOrBuildLineSpaces(bvh, params, {}, nullProgress(), &outcome);
    EXPECT_EQ(outcome, CacheOutcome::Built);
}

} // namespace
} // namespace chcrt::ls
