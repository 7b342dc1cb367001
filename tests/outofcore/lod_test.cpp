// Level-of-detail proxies (issue #19, renderer/outofcore/lod_proxies.h): proxies lie inside their subtree's box,
// reduce the triangles level by level with errors that do not shrink, keep one material and a distinct original id
// of that material per proxy triangle, survive the file round trip (checksums, records), and files without them are
// still version 1 and read as before.
#include "renderer/core/error.h"
#include "renderer/outofcore/chs_file.h"
#include "renderer/outofcore/lod_proxies.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace chcrt {
namespace {

using outofcore::ChsFile;
using outofcore::ChsLodRecord;

bool inside(const glm::vec3& v, const float (&lo)[3], const float (&hi)[3]) {
    for (int k = 0; k < 3; ++k) {
        if (v[k] < lo[k] || v[k] > hi[k]) return false;
    }
    return true;
}

class LodFile : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::ScratchDir;
        outofcore::PrepareOptions options;
        options.subtreeTriangles = 4000;
        options.lodLevels = 2;
        report_ = outofcore::prepareScene("city:100k", dir_->file("lod.chs"), options);
    }
    static void TearDownTestSuite() { delete dir_; }
    static test::ScratchDir* dir_;
    static outofcore::PrepareReport report_;
};
test::ScratchDir* LodFile::dir_ = nullptr;
outofcore::PrepareReport LodFile::report_;

TEST_F(LodFile, ProxiesLieInsideTheirSubtreesBoxAndShrinkLevelByLevel) {
    const ChsFile file(dir_->file("lod.chs"));
    ASSERT_EQ(file.header().version, outofcore::kChsVersionCompact); // compact subtrees and proxies
    ASSERT_TRUE(file.compact());
    ASSERT_EQ(file.lodLevels(), 2u);
    uint64_t kept[3] = {0, 0, 0}, triangles[3] = {0, 0, 0};
    for (uint32_t s = 0; s < file.subtrees().size(); ++s) {
        const outofcore::ChsSubtreeRecord& r = file.subtrees()[s];
        triangles[0] += r.triangleCount;
        uint32_t finer = r.triangleCount;
        float finerError = 0.0f;
        for (uint32_t level = 1; level <= 2; ++level) {
            const ChsLodRecord& lod = file.lodRecord(s, level);
            if (lod.nodeCount == 0) continue; // not kept: too little reduction over the finer level
            EXPECT_GE(lod.errorWorld, finerError) << "subtree " << s << " level " << level;
            finerError = lod.errorWorld;
            ++kept[level];
            triangles[level] += lod.triangleCount;
            EXPECT_LE(float(lod.triangleCount), outofcore::kLodMaxKeptShare * float(finer)) << s;
            finer = lod.triangleCount;
            const outofcore::SubtreeData proxy = file.readSubtree(s, level);
            ASSERT_EQ(proxy.triangles.size(), lod.triangleCount);
            ASSERT_EQ(proxy.normals.size(), 3 * proxy.triangles.size());
            for (const TriangleGpu& t : proxy.triangles) {
                for (const glm::vec3& v : {t.v0, t.v1, t.v2}) ASSERT_TRUE(inside(v, r.boundsMin, r.boundsMax)) << s;
            }
            // The proxy's own BVH root box lies inside the subtree's too (the culling hierarchy's boxes bound it).
            EXPECT_TRUE(inside(proxy.nodes[0].boundsMin, r.boundsMin, r.boundsMax));
            EXPECT_TRUE(inside(proxy.nodes[0].boundsMax, r.boundsMin, r.boundsMax));
        }
    }
    // The city simplifies: some subtrees within the collapse level's 0.2 % bound, most by clustering (the coarsest
    // level, towards 1/64 of the triangles; measured 1/8 here: small material groups stay whole).
    EXPECT_GT(kept[1], 0u);
    EXPECT_GT(kept[2], file.subtrees().size() / 2);
    EXPECT_LT(triangles[2], triangles[0] / 4);
    EXPECT_EQ(report_.proxies, kept[1] + kept[2]);
    EXPECT_GT(report_.proxyBytes, 0u);
    EXPECT_LT(report_.proxyBytes, report_.subtreeBytes / 2);
}

TEST_F(LodFile, ProxyTrianglesCarryDistinctOriginalIdsOfTheirMaterialFromTheSubtree) {
    const ChsFile file(dir_->file("lod.chs"));
    for (uint32_t s = 0; s < file.subtrees().size(); s += 3) {
        const outofcore::SubtreeData full = file.readSubtree(s);
        std::map<uint32_t, uint32_t> materialOf;
        for (const TriangleGpu& t : full.triangles) materialOf[t.originalId] = t.materialId;
        for (uint32_t level = 1; level <= file.lodLevels(); ++level) {
            if (file.lodRecord(s, level).nodeCount == 0) continue;
            const outofcore::SubtreeData proxy = file.readSubtree(s, level);
            std::set<uint32_t> ids;
            for (size_t k = 0; k < proxy.triangles.size(); ++k) {
                const TriangleGpu& t = proxy.triangles[k];
                const auto it = materialOf.find(t.originalId);
                ASSERT_NE(it, materialOf.end()) << "subtree " << s << " level " << level << ": id not in the subtree";
                EXPECT_EQ(it->second, t.materialId);
                EXPECT_TRUE(ids.insert(t.originalId).second) << "id used twice";
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(glm::length(proxy.normals[k * 3 + c]), 1.0f, 1e-3f);
            }
        }
    }
}

TEST_F(LodFile, ACorruptedLodRecordIsRefusedWithOneLine) {
    std::vector<char> bytes = test::readBytes(dir_->file("lod.chs"));
    const ChsFile file(dir_->file("lod.chs"));
    // The first kept proxy of the coarsest level: flip one byte of its blob and its read fails (the subtree's not).
    uint32_t subtree = 0;
    while (subtree < file.subtrees().size() && file.lodRecord(subtree, 2).nodeCount == 0) ++subtree;
    ASSERT_LT(subtree, file.subtrees().size());
    const ChsLodRecord& r = file.lodRecord(subtree, 2);
    bytes[r.offset + 5] ^= 0x40;
    test::writeBytes(dir_->file("flipped.chs"), bytes);
    const ChsFile flipped(dir_->file("flipped.chs")); // metadata intact: opens
    EXPECT_NO_THROW(flipped.readSubtree(subtree));
    try {
        flipped.readSubtree(subtree, 2);
        FAIL() << "read a corrupted proxy";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("LOD 2 checksum mismatch"), std::string::npos) << e.what();
    }
}

TEST(LodPrepare, WithoutLevelsTheFileIsVersionOneAndHasNoProxies) {
    // Full layout: version 1 without proxies, 2 with them; compact: version 3 either way, the flag tells.
    for (const bool compact : {false, true}) {
        SCOPED_TRACE(compact ? "compact layout" : "full layout");
        test::ScratchDir dir;
        outofcore::PrepareOptions options;
        options.subtreeTriangles = 4000;
        options.lodLevels = 0;
        options.compact = compact;
        const outofcore::PrepareReport r = outofcore::prepareScene("city:30k", dir.file("v1.chs"), options);
        EXPECT_EQ(r.proxyBytes, 0u);
        const ChsFile file(dir.file("v1.chs"));
        EXPECT_EQ(file.header().version, compact ? outofcore::kChsVersionCompact : outofcore::kChsVersion);
        EXPECT_EQ(file.lodLevels(), 0u);
        EXPECT_THROW(file.lodRecord(0, 1), InputError);
        // The same scene with proxies: the same subtrees, byte for byte, with the proxies after each.
        options.lodLevels = 1;
        outofcore::prepareScene("city:30k", dir.file("v2.chs"), options);
        const ChsFile lod(dir.file("v2.chs"));
        EXPECT_EQ(lod.header().version, compact ? outofcore::kChsVersionCompact : outofcore::kChsVersionLod);
        ASSERT_EQ(lod.subtrees().size(), file.subtrees().size());
        for (uint32_t s = 0; s < file.subtrees().size(); ++s) {
            EXPECT_EQ(lod.subtrees()[s].checksum, file.subtrees()[s].checksum);
            EXPECT_EQ(lod.readSubtree(s).triangles.size(), file.readSubtree(s).triangles.size());
        }
    }
}

TEST(LodProxies, ABoxSoupWeldsAndSimplifiesWithinItsBounds) {
    // A finely tessellated flat quad of one material: coplanar, so the proxy's error is ~0 and it shrinks a lot.
    std::vector<TriangleGpu> triangles;
    std::vector<glm::vec3> normals;
    const int n = 32;
    uint32_t id = 100;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const glm::vec3 a(float(x), 0.0f, float(y)), b(float(x + 1), 0.0f, float(y)), c(float(x + 1), 0.0f, float(y + 1)),
                d(float(x), 0.0f, float(y + 1));
            triangles.push_back({a, id++, c, 0, b, 0});
            triangles.push_back({a, id++, d, 0, c, 0});
            for (int k = 0; k < 6; ++k) normals.emplace_back(0.0f, 1.0f, 0.0f);
        }
    }
    const std::vector<outofcore::LodProxy> proxies = outofcore::buildLodProxies(triangles, normals, {}, 2);
    ASSERT_EQ(proxies.size(), 2u);
    ASSERT_FALSE(proxies[0].empty());
    EXPECT_LE(proxies[0].triangles.size(), triangles.size() / 4);
    EXPECT_LT(proxies[0].errorWorld, 1e-3f);
    for (const outofcore::LodProxy& p : proxies) {
        for (const TriangleGpu& t : p.triangles) {
            for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
                EXPECT_TRUE(v.x >= 0 && v.x <= n && v.y == 0.0f && v.z >= 0 && v.z <= n);
            }
            EXPECT_GE(t.originalId, 100u);
            EXPECT_LT(t.originalId, id);
        }
    }
}

} // namespace
} // namespace chcrt
