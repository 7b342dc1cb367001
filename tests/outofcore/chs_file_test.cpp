// The prepared scene format: round trip against the generated scene (geometry, materials, normals, traced
// hits), and refusal of truncated, corrupted and version-mismatched files.
#include "renderer/bvh/cpu_tracer.h"
#include "renderer/core/error.h"
#include "renderer/outofcore/chs_file.h"
#include "renderer/outofcore/compact_subtree.h"
#include "renderer/scene/procedural/procedural.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>
#include <random>
#include <thread>

namespace chcrt {
namespace {

using outofcore::ChsFile;
using outofcore::ChsHeader;

// Opens the file and reads every subtree (what must fail for any corruption).
void openAndReadAll(const std::filesystem::path& file) {
    const ChsFile chs(file);
    for (uint32_t i = 0; i < chs.header().subtreeCount; ++i) {
        chs.readSubtree(i);
        for (uint32_t level = 1; level <= chs.lodLevels(); ++level) { // LOD proxies (issue #19) are checksummed too
            if (chs.lodRecord(i, level).nodeCount != 0) chs.readSubtree(i, level);
        }
    }
}

// Rays from points around and inside the scene towards random points of it.
std::vector<Ray> sampleRays(const Aabb& b, int count) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays;
    const glm::vec3 e = b.extent();
    for (int i = 0; i < count; ++i) {
        const glm::vec3 from = b.lower - 0.2f * e + 1.4f * e * glm::vec3(u(rng), u(rng), u(rng));
        const glm::vec3 to = b.lower + e * glm::vec3(u(rng), 0.3f * u(rng), u(rng));
        Ray r;
        r.origin = from;
        r.direction = glm::normalize(to - from);
        r.tmin = 0.0f;
        r.tmax = 1e30f;
        rays.push_back(r);
    }
    return rays;
}

TEST(ChsFile, RoundTripEqualsGeneratedSceneAndHits) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    const outofcore::PrepareReport report = test::prepareSmall("city:20k", file, 1000);
    EXPECT_GT(report.subtrees, 10u); // small subtrees: the upper part is not trivial
    const Scene original = generateProceduralScene({ProceduralKind::City, 20000, 1});
    const Bvh originalBvh = buildBvh(original);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    EXPECT_EQ(loaded.source, "city:20000:seed=1");
    ASSERT_EQ(loaded.scene.triangleCount(), original.triangleCount());
    ASSERT_EQ(loaded.scene.materials.size(), original.materials.size());
    for (size_t m = 0; m < original.materials.size(); ++m)
        EXPECT_EQ(loaded.scene.materials[m].baseColorFactor, original.materials[m].baseColorFactor);
    for (size_t t = 0; t < original.triangleCount(); ++t) {
        for (int v = 0; v < 3; ++v) {
            ASSERT_EQ(loaded.scene.positions[loaded.scene.triangles[t][v]], original.positions[original.triangles[t][v]]);
            ASSERT_EQ(loaded.scene.normals[loaded.scene.triangles[t][v]], original.normals[original.triangles[t][v]]);
        }
        ASSERT_EQ(loaded.scene.triangleMaterials[t], original.triangleMaterials[t]);
    }
    EXPECT_NO_THROW(validateScene(loaded.scene));
    EXPECT_EQ(loaded.bvh.nodes.size(), originalBvh.nodes.size()); // same tree, spliced back together
    const AreaLight light = proceduralAreaLight({ProceduralKind::City, 20000, 1});
    EXPECT_EQ(loaded.light.corner, light.corner);
    EXPECT_EQ(loaded.light.radiance, light.radiance);

    const std::vector<Ray> rays = sampleRays(original.bounds(), 4000);
    std::vector<Hit> a(rays.size()), b(rays.size());
    traceCpu(originalBvh, rays, a, false);
    traceCpu(loaded.bvh, rays, b, false);
    int hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(a[i].triangleId, b[i].triangleId) << "ray " << i;
        ASSERT_EQ(a[i].t, b[i].t) << "ray " << i;
        hits += a[i].hit();
    }
    EXPECT_GT(hits, 1000);
}

TEST(ChsFile, SubtreesMatchDirectoryAndLimits) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file, 1500);
    const ChsFile chs(file);
    uint64_t triangles = 0;
    for (uint32_t i = 0; i < chs.header().subtreeCount; ++i) {
        const outofcore::SubtreeData d = chs.readSubtree(i);
        const outofcore::ChsSubtreeRecord& r = chs.subtrees()[i];
        EXPECT_EQ(d.nodes.size(), r.nodeCount);
        EXPECT_EQ(d.triangles.size(), r.triangleCount);
        EXPECT_TRUE(r.triangleCount <= 1500 || r.nodeCount == 1);
        EXPECT_LE(r.height, 24u);
        EXPECT_EQ(chs.upperNodes()[r.upperNode].subtree, i);
        if (i > 0) {
            EXPECT_LT(chs.subtrees()[i - 1].upperNode, r.upperNode); // directory in node order
        }
        triangles += r.triangleCount;
    }
    EXPECT_EQ(triangles, chs.header().triangleCount);
}

TEST(ChsFile, TruncationAtManyOffsetsIsRefused) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file);
    const std::vector<char> bytes = test::readBytes(file);
    std::vector<size_t> lengths = {0, 1, 7, 8, 100, sizeof(ChsHeader) - 1, sizeof(ChsHeader), sizeof(ChsHeader) + 1,
                                   bytes.size() - 1, bytes.size() - 33};
    for (int k = 1; k < 40; ++k) lengths.push_back(bytes.size() * size_t(k) / 40);
    const auto cut = dir.file("cut.chs");
    for (size_t length : lengths) {
        test::writeBytes(cut, std::vector<char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(length)));
        EXPECT_THROW(openAndReadAll(cut), InputError) << "truncated to " << length;
    }
    std::vector<char> longer = bytes;
    longer.push_back(0);
    test::writeBytes(cut, longer);
    EXPECT_THROW(openAndReadAll(cut), InputError);
}

TEST(ChsFile, FlippedBytesAnywhereAreDetected) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file);
    const std::vector<char> bytes = test::readBytes(file);
    ASSERT_NO_THROW(openAndReadAll(file));
    const auto bad = dir.file("bad.chs");
    std::vector<size_t> offsets;
    for (size_t o = 0; o < sizeof(ChsHeader); o += 3) offsets.push_back(o);
    for (int k = 0; k < 300; ++k) offsets.push_back(sizeof(ChsHeader) + (bytes.size() - sizeof(ChsHeader)) * size_t(k) / 300);
    offsets.push_back(bytes.size() - 1);
    for (size_t o : offsets) {
        std::vector<char> copy = bytes;
        copy[o] = char(copy[o] ^ 0x10);
        test::writeBytes(bad, copy);
        EXPECT_THROW(openAndReadAll(bad), InputError) << "byte " << o;
    }
}

// Writes one byte in place (same size), as another process overwriting the file would.
void overwriteByte(const std::filesystem::path& file, uint64_t offset, char value) {
    std::fstream out(file, std::ios::binary | std::ios::in | std::ios::out);
    out.seekp(std::streamoff(offset));
    out.put(value);
}


// A blob's checksum is computed on its first read and not again while the file stays the same; a read for the GPU
// alone (no vertex attributes) is only that cheap once the blob was verified, and any change of the file under the
// open descriptor makes the next read verify again (docs/outofcore.md, "Reading subtrees").
TEST(ChsFile, BlobsAreVerifiedOnFirstReadAndAgainAfterTheFileChanges) {
    for (const bool compact : {true, false}) {
        SCOPED_TRACE(compact ? "compact layout" : "full layout");
        test::ScratchDir dir;
        const auto file = dir.file("city.chs");
        test::prepareSmall("city:20k", file, 1000, 256ull << 20, compact);
        const ChsFile chs(file);
        ASSERT_GE(chs.header().subtreeCount, 3u);
        const outofcore::ChsSubtreeRecord& one = chs.subtrees()[1];
        // Where the GPU's part of the blob starts (its triangles) and where the vertex normals start.
        const uint64_t triangleAt =
            one.offset + (compact ? outofcore::compactNodeTexels(one.nodeCount) * 16 : uint64_t(one.nodeCount) * sizeof(BvhNodeGpu));
        const uint64_t normalsAt =
            compact ? triangleAt + uint64_t(one.triangleCount) * (16 + 4) + uint64_t(chs.vertexCount(1)) * 12
                    : triangleAt + uint64_t(one.triangleCount) * sizeof(TriangleGpu);

        // Never read: a read for the GPU reads and checks everything, so a bad normal is found.
        const char saved = test::readBytes(file)[normalsAt];
        overwriteByte(file, normalsAt, char(saved ^ 0x10));
        outofcore::SubtreeData d;
        EXPECT_THROW(chs.readSubtree(1, 0, d, false), InputError);
        overwriteByte(file, normalsAt, saved);

        // Verified once: the GPU's read skips the attributes and returns the same nodes and triangles.
        const outofcore::SubtreeData full = chs.readSubtree(1);
        EXPECT_TRUE(full.attributes);
        chs.readSubtree(1, 0, d, false, false);
        EXPECT_FALSE(d.attributes);
        EXPECT_TRUE(d.normals.empty());
        EXPECT_TRUE(test::sameContents(d, full));
        EXPECT_EQ(d.compact(), compact);

        // Changed in place after it was verified: the next read, whole or for the GPU, checks it again. File times
        // are kept at the kernel's tick (a few ms), so the change is made well after the last one.
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        overwriteByte(file, triangleAt, char(test::readBytes(file)[triangleAt] ^ 0x10));
        EXPECT_THROW(chs.readSubtree(1, 0, d, false), InputError);
        EXPECT_THROW(chs.readSubtree(1), InputError);
    }
}

// The primary resolve's read of a few triangles (ChsFile::readTriangles, gathered reads) gives what the whole
// subtree's read gives for them, whatever their order, spacing and repetition; an index out of the subtree or a blob
// not verified yet answers false.
TEST(ChsFile, TrianglesReadByIndexEqualTheWholeSubtrees) {
    for (const bool compact : {true, false}) {
        SCOPED_TRACE(compact ? "compact layout" : "full layout");
        test::ScratchDir dir;
        const auto file = dir.file("city.chs");
        test::prepareSmall("city:20k", file, 1000, 256ull << 20, compact);
        const ChsFile chs(file);
        std::vector<TriangleGpu> triangles;
        std::vector<glm::vec3> normals;
        const std::vector<uint32_t> one = {0};
        EXPECT_FALSE(chs.readTriangles(0, one, triangles.data(), normals.data())) << "not verified yet";
        std::mt19937 rng(3);
        for (uint32_t i = 0; i < chs.header().subtreeCount; ++i) {
            const outofcore::SubtreeData whole = chs.readSubtree(i);
            const auto n = uint32_t(whole.triangleCount());
            std::vector<std::vector<uint32_t>> sets = {{0}, {n - 1}, {n - 1, 0}, {5 % n, 5 % n, 5 % n}};
            std::vector<uint32_t> all(n);
            for (uint32_t k = 0; k < n; ++k) all[k] = k;
            sets.push_back(all);
            std::shuffle(all.begin(), all.end(), rng);
            sets.push_back(all);                                   // every triangle, in any order
            sets.emplace_back(all.begin(), all.begin() + n / 10); // a scattered tenth
            std::vector<uint32_t> strided;                         // runs broken by gaps beyond one read
            for (uint32_t k = 0; k < n; k += 300) strided.push_back(k);
            sets.push_back(strided);
            for (const std::vector<uint32_t>& locals : sets) {
                triangles.assign(locals.size(), TriangleGpu{});
                normals.assign(3 * locals.size(), glm::vec3(0.0f));
                ASSERT_TRUE(chs.readTriangles(i, locals, triangles.data(), normals.data()));
                for (size_t k = 0; k < locals.size(); ++k) {
                    const TriangleGpu expected = whole.triangle(locals[k]);
                    ASSERT_EQ(std::memcmp(&triangles[k], &expected, sizeof expected), 0)
                        << "subtree " << i << ", triangle " << locals[k];
                    ASSERT_EQ(std::memcmp(&normals[3 * k], &whole.normals[3 * size_t(locals[k])], 3 * sizeof(glm::vec3)),
                              0);
                }
            }
            const std::vector<uint32_t> beyond = {0, n};
            triangles.resize(2), normals.resize(6);
            EXPECT_FALSE(chs.readTriangles(i, beyond, triangles.data(), normals.data()));
        }
    }
}

TEST(ChsFile, VersionMismatchIsRefusedWithClearMessage) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file);
    std::vector<char> bytes = test::readBytes(file);
    ChsHeader h;
    std::memcpy(&h, bytes.data(), sizeof(h));
    h.version = outofcore::kChsVersionCompact + 1;
    h.headerChecksum = outofcore::chsChecksum(&h, offsetof(ChsHeader, headerChecksum));
    std::memcpy(bytes.data(), &h, sizeof(h));
    test::writeBytes(file, bytes);
    try {
        ChsFile chs(file);
        FAIL() << "accepted a file of another version";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("version"), std::string::npos) << e.what();
    }
}

TEST(ChsFile, CountsBeyondTheFileAreRefusedBeforeAllocating) {
    test::ScratchDir dir;
    const auto file = dir.file("box.chs");
    test::prepareSmall("closed-box", file);
    const std::vector<char> good = test::readBytes(file);
    // 10^9 triangles would pass the in-core limit and size ~50 GB of vectors; 10^12 the reader's own arithmetic.
    for (uint64_t triangles : {uint64_t(1'000'000'000), uint64_t(1'000'000'000'000)}) {
        std::vector<char> bytes = good;
        ChsHeader h;
        std::memcpy(&h, bytes.data(), sizeof(h));
        h.triangleCount = triangles;
        h.headerChecksum = outofcore::chsChecksum(&h, offsetof(ChsHeader, headerChecksum));
        std::memcpy(bytes.data(), &h, sizeof(h));
        test::writeBytes(file, bytes);
        try {
            outofcore::loadPreparedScene(file);
            FAIL() << "accepted a header claiming " << triangles << " triangles";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("claims " + std::to_string(triangles) + " triangles"), std::string::npos)
                << e.what();
        }
    }
}

TEST(ChsFile, MissingAndForeignFilesAreRefused) {
    test::ScratchDir dir;
    EXPECT_THROW(ChsFile(dir.file("missing.chs")), InputError);
    test::writeBytes(dir.file("foreign.chs"), std::vector<char>(4096, 'x'));
    EXPECT_THROW(ChsFile(dir.file("foreign.chs")), InputError);
}

TEST(ChsChecksum, DependsOnEveryByteAndTheLength) {
    std::vector<unsigned char> data(1000);
    for (size_t i = 0; i < data.size(); ++i) data[i] = uint8_t(i * 7);
    const uint64_t base = outofcore::chsChecksum(data.data(), data.size());
    EXPECT_EQ(base, outofcore::chsChecksum(data.data(), data.size()));
    EXPECT_NE(base, outofcore::chsChecksum(data.data(), data.size() - 1));
    for (size_t i = 0; i < data.size(); i += 37) {
        data[i] ^= 1;
        EXPECT_NE(base, outofcore::chsChecksum(data.data(), data.size())) << i;
        data[i] ^= 1;
    }
}

} // namespace
} // namespace chcrt
