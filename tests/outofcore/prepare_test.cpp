// Preparation: memory budgets, streaming a city in parts (same geometry as in core), grids of copies,
// determinism, atomic output.
#include "renderer/core/error.h"
#include "renderer/outofcore/chs_file.h"
#include "renderer/scene/procedural/procedural.h"
#include "renderer/scene/procedural/procedural_internal.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

namespace chcrt {
namespace {

using TriangleKey = std::array<float, 10>; // v0, v1, v2, material

std::vector<TriangleKey> triangleKeys(const Scene& s) {
    std::vector<TriangleKey> keys;
    for (size_t t = 0; t < s.triangleCount(); ++t) {
        TriangleKey k{};
        for (int v = 0; v < 3; ++v)
            for (int c = 0; c < 3; ++c) k[size_t(v * 3 + c)] = s.positions[s.triangles[t][v]][c];
        k[9] = float(s.triangleMaterials[t]);
        keys.push_back(k);
    }
    std::sort(keys.begin(), keys.end());
    return keys;
}

TEST(CityParts, UnionOfPartsIsTheGeneratedCity) {
    const ProceduralSpec spec{ProceduralKind::City, 150000, 3};
    const procedural::CityParts parts(spec);
    Scene joined;
    uint64_t planned = parts.groundTriangles();
    {
        procedural::MeshBuilder builder(joined);
        parts.generate(true, 0, 0, builder);
        EXPECT_EQ(joined.triangleCount(), parts.groundTriangles());
    }
    for (uint32_t b = 0; b < parts.buildingCount(); b += 5) {
        Scene part;
        procedural::MeshBuilder builder(part);
        const uint32_t end = std::min(b + 5, parts.buildingCount());
        parts.generate(false, b, end, builder);
        uint64_t expected = 0;
        for (uint32_t k = b; k < end; ++k) expected += parts.buildingTriangles(k);
        EXPECT_EQ(part.triangleCount(), expected);
        planned += expected;
        const uint32_t base = uint32_t(joined.positions.size());
        joined.positions.insert(joined.positions.end(), part.positions.begin(), part.positions.end());
        for (const glm::uvec3& t : part.triangles) joined.triangles.push_back(t + base);
        joined.triangleMaterials.insert(joined.triangleMaterials.end(), part.triangleMaterials.begin(),
                                        part.triangleMaterials.end());
    }
    const Scene city = generateProceduralScene(spec);
    EXPECT_EQ(planned, city.triangleCount());
    EXPECT_EQ(triangleKeys(joined), triangleKeys(city));
}

TEST(Prepare, StreamedCityHasTheGeneratedGeometry) {
    test::ScratchDir dir;
    const auto file = dir.file("streamed.chs");
    const outofcore::PrepareReport r = test::prepareSmall("city:200k", file, 4000, 20ull << 20);
    EXPECT_GT(r.chunks, 2u); // really streamed
    const outofcore::ChsFile chs(file);
    for (uint32_t i = 1; i < chs.header().subtreeCount; ++i)
        EXPECT_LT(chs.subtrees()[i - 1].upperNode, chs.subtrees()[i].upperNode);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    const Scene city = generateProceduralScene({ProceduralKind::City, 200000, 1});
    EXPECT_EQ(triangleKeys(loaded.scene), triangleKeys(city));
    EXPECT_NO_THROW(validateScene(loaded.scene));
}

TEST(Prepare, IsDeterministic) {
    test::ScratchDir dir;
    test::prepareSmall("city:200k", dir.file("a.chs"), 4000, 20ull << 20);
    test::prepareSmall("city:200k", dir.file("b.chs"), 4000, 20ull << 20);
    EXPECT_EQ(test::readBytes(dir.file("a.chs")), test::readBytes(dir.file("b.chs")));
    test::prepareSmall("plant:30k", dir.file("c.chs"));
    test::prepareSmall("plant:30k", dir.file("d.chs"));
    EXPECT_EQ(test::readBytes(dir.file("c.chs")), test::readBytes(dir.file("d.chs")));
}

TEST(Prepare, BudgetTooSmallIsAnErrorAndLeavesNoFile) {
    test::ScratchDir dir;
    const auto file = dir.file("small.chs");
    EXPECT_THROW(test::prepareSmall("city:200k", file, 4000, 256ull << 10), InputError);
    EXPECT_THROW(test::prepareSmall("plant:200k", file, 4000, 1ull << 20), InputError); // only cities stream
    EXPECT_FALSE(std::filesystem::exists(file));
    EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
}

TEST(Prepare, BadOptionsAreErrors) {
    test::ScratchDir dir;
    EXPECT_THROW(test::prepareSmall("city:20k", dir.file("x.chs"), 0), InputError);
    EXPECT_THROW(test::prepareSmall("grid:0x2:city:20k", dir.file("x.chs")), InputError);
    EXPECT_THROW(test::prepareSmall("grid:2:city:20k", dir.file("x.chs")), InputError);
    EXPECT_THROW(test::prepareSmall("city:20k", dir.file("missing-dir/x.chs")), InputError);
    EXPECT_FALSE(std::filesystem::exists(dir.file("x.chs")));
}

TEST(Prepare, GridOfCopiesMovesEachCopy) {
    test::ScratchDir dir;
    const auto file = dir.file("grid.chs");
    const outofcore::PrepareReport r = test::prepareSmall("grid:3x2:plane-and-box", file, 4);
    EXPECT_EQ(r.chunks, 6u);
    EXPECT_EQ(r.triangles, 6u * 14u);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    EXPECT_EQ(loaded.source, "grid:3x2:plane-and-box");
    const Scene one = generateProceduralScene({ProceduralKind::PlaneAndBox, 1, 1});
    const glm::vec3 pitch = 1.1f * one.bounds().extent();
    for (uint32_t copy = 0; copy < 6; ++copy) {
        const glm::vec3 offset(float(copy % 3) * pitch.x, 0.0f, float(copy / 3) * pitch.z);
        for (uint32_t t = 0; t < 14; ++t) {
            for (int v = 0; v < 3; ++v) {
                EXPECT_EQ(loaded.scene.positions[loaded.scene.triangles[copy * 14 + t][v]],
                          one.positions[one.triangles[t][v]] + offset);
            }
        }
    }
    const Aabb b = loaded.scene.bounds();
    EXPECT_NEAR(b.extent().x, 2.0f * pitch.x + one.bounds().extent().x, 1e-3f);
}

} // namespace
} // namespace chcrt
