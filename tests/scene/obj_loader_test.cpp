// OBJ: face vertex forms, negative indices, quads, (v, vt, vn) de-duplication, generated normals,
// materials from mtllib, and strict errors.
#include "renderer/core/error.h"
#include "renderer/scene/scene_loader.h"
#include "tests/scene/test_files.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

using test::TempDir;

std::filesystem::path writeObj(const TempDir& dir, const std::string& name, const std::string& text) {
    test::writeFile(dir / name, text);
    return dir / name;
}

std::string loadError(const std::filesystem::path& file) {
    try {
        loadSceneFile(file);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(ObjLoader, NegativeIndicesQuadsAndGeneratedNormals) {
    TempDir dir;
    // Two quads in the XZ plane facing +Y; the second uses relative (negative) indices, and lines mix
    // comments, groups and smoothing statements that are ignored.
    const std::string text = "# test\no quads\nv 0 0 0\nv 0 0 1\nv 1 0 1\nv 1 0 0\ng first\ns 1\nf 1 2 3 4\n"
                             "v 2 0 0\nv 2 0 1\nv 3 0 1\nv 3 0 0\r\nf -4 -3 -2 -1\r\n";
    const Scene scene = loadSceneFile(writeObj(dir, "quads.obj", text));
    EXPECT_EQ(scene.name, "quads");
    ASSERT_EQ(scene.triangleCount(), 4u);
    EXPECT_EQ(scene.positions.size(), 8u);
    EXPECT_EQ(scene.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(scene.triangles[1], glm::uvec3(0, 2, 3));
    EXPECT_EQ(scene.positions[scene.triangles[2].x], glm::vec3(2, 0, 0));
    EXPECT_EQ(scene.positions[scene.triangles[3].z], glm::vec3(3, 0, 0));
    for (const glm::vec3& n : scene.normals) EXPECT_NEAR(glm::distance(n, glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_TRUE(scene.texcoords.empty());
    ASSERT_EQ(scene.materials.size(), 1u);
}

TEST(ObjLoader, DeduplicatesVerticesByTriple) {
    TempDir dir;
    // A cube corner: three faces share vertex 1 but with different normals -> three output vertices.
    const std::string text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 0 1 1\nv 1 0 1\n"
                             "vn 0 0 -1\nvn -1 0 0\nvn 0 -1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                             "f 1//1 4//1 3//1 2//1\nf 1//2 5//2 6//2 4//2\nf 1//3 2//3 7//3 5//3\n"
                             "f 1/1/1 3/3/1 2/2/1\n";
    const Scene scene = loadSceneFile(writeObj(dir, "corner.obj", text));
    EXPECT_EQ(scene.triangleCount(), 7u);
    // Distinct (v, vt, vn): 4 + 4 + 4 from the quads, then (1/1/1), (3/3/1), (2/2/1) are new triples.
    EXPECT_EQ(scene.positions.size(), 15u);
    size_t atOrigin = 0;
    for (const glm::vec3& p : scene.positions) atOrigin += p == glm::vec3(0.0f);
    EXPECT_EQ(atOrigin, 4u);
    // Normals come from the file, per corner.
    EXPECT_EQ(scene.normals[scene.triangles[0].x], glm::vec3(0, 0, -1));
    EXPECT_EQ(scene.normals[scene.triangles[2].x], glm::vec3(-1, 0, 0));
    ASSERT_EQ(scene.texcoords.size(), scene.positions.size());
    EXPECT_EQ(scene.texcoords[scene.triangles[6].y], glm::vec2(1, 1));
}

TEST(ObjLoader, AllFaceVertexForms) {
    TempDir dir;
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.25\nvn 0 0 1\n"
                             "f 1 2 3\nf 1/1 2/1 3/1\nf 1//1 2//1 3//1\nf 1/1/1 2/1/1 3/-1/-1\n";
    const Scene scene = loadSceneFile(writeObj(dir, "forms.obj", text));
    EXPECT_EQ(scene.triangleCount(), 4u);
    EXPECT_EQ(scene.positions.size(), 12u); // four distinct (vt, vn) combinations per position
    EXPECT_EQ(scene.texcoords[scene.triangles[3].z], glm::vec2(0.5f, 0.25f));
    EXPECT_EQ(scene.texcoords[scene.triangles[0].z], glm::vec2(0.0f)); // none given
    for (const glm::vec3& n : scene.normals) EXPECT_NEAR(glm::distance(n, glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
}

TEST(ObjLoader, ReadsMaterialsFromMtllib) {
    TempDir dir;
    test::writeFile(dir / "colors.mtl", "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\nd 0.5\n");
    const std::string text = "mtllib colors.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                             "f 1 2 3\nusemtl blue\nf 2 4 3\nusemtl red\nf 1 2 4\nusemtl unknown\nf 1 4 3\n";
    const Scene scene = loadSceneFile(writeObj(dir, "materials.obj", text));
    ASSERT_EQ(scene.triangleCount(), 4u);
    const auto materialOf = [&](size_t t) { return scene.materials[scene.triangleMaterials[t]]; };
    EXPECT_EQ(materialOf(0).name, "default");
    EXPECT_EQ(materialOf(0).baseColorFactor, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
    EXPECT_EQ(materialOf(1).name, "blue");
    EXPECT_EQ(materialOf(1).baseColorFactor, glm::vec4(0, 0, 1, 0.5f));
    EXPECT_EQ(materialOf(2).baseColorFactor, glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(materialOf(3).name, "unknown");
    EXPECT_EQ(materialOf(3).baseColorFactor, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
}

TEST(ObjLoader, UnderflowIsZeroAndOverflowIsAnError) {
    TempDir dir;
    const Scene scene = loadSceneFile(writeObj(dir, "tiny.obj", "v 0 0 1e-999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_EQ(scene.positions[0], glm::vec3(0.0f));
    EXPECT_NE(loadError(writeObj(dir, "huge.obj", "v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).find("non-finite"),
              std::string::npos);
}

TEST(ObjLoader, DropsDegenerateFaces) {
    TempDir dir;
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 1 2 4\nf 1 2\n";
    const Scene scene = loadSceneFile(writeObj(dir, "degenerate.obj", text));
    EXPECT_EQ(scene.triangleCount(), 1u);
    EXPECT_EQ(scene.stats.degenerateTrianglesDropped, 3u);
}

TEST(ObjLoader, StrictErrors) {
    TempDir dir;
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4: vertex index 4 out of range (3 defined so far)"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "vertex index 0 out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "vertex index -4 out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2 2 3\n", "texture coordinate index 2 out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2 3\n", "normal index 1 out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "line 4: bad vertex index 'x'"},
        {"v 0 0\n", "line 1: 'v' needs 3 numbers"},
        {"v 0 zero 0\n", "bad number 'zero'"},
        {"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", "vertex 1 has a non-finite position"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 inf\nf 1 2 3\n", "non-finite position"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "scene has no triangles"},
        {"", "scene has no triangles"},
    };
    for (const auto& [text, fragment] : cases) {
        const std::filesystem::path file = writeObj(dir, "bad.obj", text);
        const std::string message = loadError(file);
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(fragment), std::string::npos) << "'" << fragment << "' not in: " << message;
    }
}

} // namespace
} // namespace chcrt
