// glTF loading: hierarchy and instancing, GLB = glTF, index types and strides, normals, materials,
// textures, cameras, primitive modes and scene selection. All files are generated at test time.
#include "renderer/core/error.h"
#include "renderer/scene/scene_loader.h"
#include "tests/scene/test_files.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chcrt {
namespace {

using nlohmann::json;
using test::GltfBuilder;
using test::TempDir;

constexpr int kUint8 = 5121, kUint16 = 5123, kUint32 = 5125;

// Rotation of `degrees` about an axis as a glTF quaternion (x, y, z, w).
json quaternion(const glm::vec3& axis, float degrees) {
    const float half = glm::radians(degrees) * 0.5f;
    const glm::vec3 v = glm::normalize(axis) * std::sin(half);
    return {v.x, v.y, v.z, std::cos(half)};
}

// Unit quad in the XY plane facing +Z, with explicit +Z normals.
const std::vector<glm::vec3> kQuadPositions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

int addQuadMesh(GltfBuilder& gltf, int indexType = kUint16, int material = -1) {
    const int positions = gltf.addPositions(kQuadPositions);
    const int normals = gltf.addVec3(std::vector<glm::vec3>(4, glm::vec3(0, 0, 1)));
    return gltf.addMesh({{"POSITION", positions}, {"NORMAL", normals}}, gltf.addIndices(kQuadIndices, indexType), material);
}

// The hierarchy of the brief: a translated parent with a rotated+scaled child and a plain child sharing
// mesh 0, plus a root node with a matrix transform and a non-indexed mesh without normals.
GltfBuilder hierarchyScene() {
    GltfBuilder gltf;
    const int quad = addQuadMesh(gltf);
    const int triangle = gltf.addMesh({{"POSITION", gltf.addPositions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})}});
    const int childA = gltf.addNode({{"name", "childA"}, {"mesh", quad}, {"rotation", quaternion({0, 1, 0}, 90)}, {"scale", {2, 2, 2}}});
    const int childB = gltf.addNode({{"name", "childB"}, {"mesh", quad}});
    const int parent = gltf.addNode({{"name", "parent"}, {"translation", {10, 0, 0}}, {"children", {childA, childB}}});
    const int other = gltf.addNode({{"name", "other"}, {"mesh", triangle},
                                    {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}}});
    gltf.setSceneRoots({parent, other});
    return gltf;
}

// The normal stored at the vertex nearest to p.
glm::vec3 normalAt(const Scene& scene, const glm::vec3& p) {
    size_t best = 0;
    for (size_t i = 1; i < scene.positions.size(); ++i)
        if (glm::distance(scene.positions[i], p) < glm::distance(scene.positions[best], p)) best = i;
    return scene.normals[best];
}

void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = 1e-5f) {
    EXPECT_NEAR(glm::distance(actual, expected), 0.0f, tolerance) << "actual (" << actual.x << ", " << actual.y << ", "
                                                                  << actual.z << ")";
}

// Every triangle's winding agrees with its vertex normals (front faces are counter-clockwise).
void expectWindingMatchesNormals(const Scene& scene) {
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::vec3 face = test::faceNormal(scene, i);
        for (int k = 0; k < 3; ++k) EXPECT_GT(glm::dot(face, scene.normals[scene.triangles[i][k]]), 0.0f) << "triangle " << i;
    }
}

TEST(GltfLoader, FlattensHierarchyWithInstancing) {
    TempDir dir;
    const Scene scene = loadSceneFile(hierarchyScene().writeGltf(dir.path(), "hierarchy"));
    EXPECT_EQ(scene.name, "hierarchy");
    EXPECT_EQ(scene.stats.meshCount, 2u);
    EXPECT_EQ(scene.stats.instanceCount, 3u);
    EXPECT_EQ(scene.stats.uniqueTriangles, 3u);    // quad (2) + triangle (1)
    EXPECT_EQ(scene.stats.instancedTriangles, 5u); // quad twice + triangle
    EXPECT_EQ(scene.triangleCount(), 5u);
    EXPECT_EQ(scene.stats.degenerateTrianglesDropped, 0u);

    // childA: world = T(10,0,0) * R_y(90) * S(2); local (1,0,0) -> (2,0,0) -> (0,0,-2) -> (10,0,-2).
    for (const glm::vec3& p : {glm::vec3(10, 0, 0), glm::vec3(10, 0, -2), glm::vec3(10, 2, -2), glm::vec3(10, 2, 0)})
        EXPECT_TRUE(test::hasVertexNear(scene, p)) << p.x << " " << p.y << " " << p.z;
    expectNear(normalAt(scene, {10, 2, -2}), {1, 0, 0}); // R_y(90) turns +Z into +X
    // childB: only the parent's translation.
    for (const glm::vec3& p : {glm::vec3(11, 0, 0), glm::vec3(11, 1, 0), glm::vec3(10, 1, 0)})
        EXPECT_TRUE(test::hasVertexNear(scene, p));
    expectNear(normalAt(scene, {11, 1, 0}), {0, 0, 1});
    // The matrix node: translation (0, 5, 0) from the fourth column.
    for (const glm::vec3& p : {glm::vec3(0, 5, 0), glm::vec3(1, 5, 0), glm::vec3(0, 6, 0)})
        EXPECT_TRUE(test::hasVertexNear(scene, p));
    expectNear(normalAt(scene, {0, 6, 0}), {0, 0, 1}); // generated for the mesh without normals
    EXPECT_EQ(scene.positions.size(), 4u + 4u + 3u);
    expectWindingMatchesNormals(scene);
    // No materials in the file: one default grey.
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].baseColorFactor, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
    EXPECT_TRUE(scene.cameras.empty());
    EXPECT_TRUE(scene.texcoords.empty());
}

TEST(GltfLoader, GlbGivesTheSameSceneAsGltf) {
    TempDir dir;
    const GltfBuilder gltf = hierarchyScene();
    const Scene fromGltf = loadSceneFile(gltf.writeGltf(dir.path(), "scene"));
    const Scene fromGlb = loadSceneFile(gltf.writeGlb(dir / "scene.glb"));
    EXPECT_EQ(fromGlb.name, "scene");
    EXPECT_EQ(fromGlb.positions, fromGltf.positions);
    EXPECT_EQ(fromGlb.normals, fromGltf.normals);
    EXPECT_EQ(fromGlb.triangles, fromGltf.triangles);
    EXPECT_EQ(fromGlb.stats.uniqueTriangles, fromGltf.stats.uniqueTriangles);
    EXPECT_EQ(fromGlb.stats.instancedTriangles, fromGltf.stats.instancedTriangles);
}

// World-space corners of every triangle, in order.
std::vector<glm::vec3> triangleCorners(const Scene& scene) {
    std::vector<glm::vec3> corners;
    for (const glm::uvec3& t : scene.triangles)
        for (int k = 0; k < 3; ++k) corners.push_back(scene.positions[t[k]]);
    return corners;
}

TEST(GltfLoader, IndexTypesAndNonIndexedPrimitivesAgree) {
    TempDir dir;
    std::vector<std::vector<glm::vec3>> results;
    for (int indexType : {kUint8, kUint16, kUint32}) {
        GltfBuilder gltf;
        gltf.setSceneRoots({gltf.addNode({{"mesh", addQuadMesh(gltf, indexType)}})});
        results.push_back(triangleCorners(loadSceneFile(gltf.writeGlb(dir / ("quad" + std::to_string(indexType) + ".glb")))));
    }
    GltfBuilder unindexed;
    std::vector<glm::vec3> expanded;
    for (uint32_t i : kQuadIndices) expanded.push_back(kQuadPositions[i]);
    unindexed.setSceneRoots({unindexed.addNode({{"mesh", unindexed.addMesh({{"POSITION", unindexed.addPositions(expanded)}})}})});
    results.push_back(triangleCorners(loadSceneFile(unindexed.writeGlb(dir / "unindexed.glb"))));
    ASSERT_EQ(results[0].size(), 6u);
    for (size_t i = 1; i < results.size(); ++i) EXPECT_EQ(results[i], results[0]) << "variant " << i;
}

TEST(GltfLoader, ReadsInterleavedAttributesWithByteStride) {
    TempDir dir;
    GltfBuilder gltf;
    std::vector<float> interleaved; // position xyz, normal xyz
    for (const glm::vec3& p : kQuadPositions) interleaved.insert(interleaved.end(), {p.x, p.y, p.z, 0.0f, 0.0f, 1.0f});
    const int view = gltf.addBufferView(interleaved.data(), interleaved.size() * sizeof(float), 24);
    const int positions = gltf.addAccessor(view, 5126, 4, "VEC3");
    const int normals = gltf.addAccessor(view, 5126, 4, "VEC3", 12);
    const int mesh = gltf.addMesh({{"POSITION", positions}, {"NORMAL", normals}}, gltf.addIndices(kQuadIndices));
    gltf.setSceneRoots({gltf.addNode({{"mesh", mesh}})});
    const Scene scene = loadSceneFile(gltf.writeGltf(dir.path(), "strided"));
    EXPECT_EQ(scene.positions, kQuadPositions);
    for (const glm::vec3& n : scene.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

TEST(GltfLoader, GeneratesUnitNormalsForPlanarMeshWithoutNormals) {
    TempDir dir;
    GltfBuilder gltf;
    // A 3x3 grid in the XZ plane (counter-clockwise seen from +Y), rotated 90 degrees about X: +Y -> +Z.
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    for (int z = 0; z < 3; ++z)
        for (int x = 0; x < 3; ++x) positions.emplace_back(x, 0, z);
    for (uint32_t z = 0; z < 2; ++z) {
        for (uint32_t x = 0; x < 2; ++x) {
            const uint32_t i = z * 3 + x;
            indices.insert(indices.end(), {i, i + 3, i + 4, i, i + 4, i + 1});
        }
    }
    const int mesh = gltf.addMesh({{"POSITION", gltf.addPositions(positions)}}, gltf.addIndices(indices));
    const int flat = gltf.addNode({{"mesh", mesh}});
    const int rotated = gltf.addNode({{"mesh", mesh}, {"rotation", quaternion({1, 0, 0}, 90)}, {"translation", {0, 10, 0}}});
    gltf.setSceneRoots({flat, rotated});
    const Scene scene = loadSceneFile(gltf.writeGltf(dir.path(), "grid"));
    ASSERT_EQ(scene.normals.size(), 18u);
    for (size_t i = 0; i < scene.normals.size(); ++i) {
        EXPECT_NEAR(glm::length(scene.normals[i]), 1.0f, 1e-6f);
        expectNear(scene.normals[i], scene.positions[i].y < 5.0f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1));
    }
    expectWindingMatchesNormals(scene);
}

TEST(GltfLoader, MirroringTransformFlipsWinding) {
    TempDir dir;
    GltfBuilder gltf;
    const int quad = addQuadMesh(gltf);
    gltf.setSceneRoots({gltf.addNode({{"mesh", quad}, {"scale", {-1, 1, 1}}})});
    const Scene scene = loadSceneFile(gltf.writeGltf(dir.path(), "mirrored"));
    EXPECT_TRUE(test::hasVertexNear(scene, {-1, 1, 0}));
    for (const glm::vec3& n : scene.normals) expectNear(n, {0, 0, 1});
    for (size_t i = 0; i < scene.triangles.size(); ++i) EXPECT_GT(test::faceNormal(scene, i).z, 0.0f);
}

TEST(GltfLoader, NormalsUseTheInverseTransposeUnderNonUniformScale) {
    TempDir dir;
    GltfBuilder gltf;
    // A triangle in the plane x + y = 0 with its exact normal, scaled by (2, 1, 1).
    const int positions = gltf.addPositions({{0, 0, 0}, {0, 0, 1}, {1, -1, 0}});
    const int normals = gltf.addVec3(std::vector<glm::vec3>(3, glm::normalize(glm::vec3(1, 1, 0))));
    const int mesh = gltf.addMesh({{"POSITION", positions}, {"NORMAL", normals}});
    gltf.setSceneRoots({gltf.addNode({{"mesh", mesh}, {"scale", {2, 1, 1}}})});
    const Scene scene = loadSceneFile(gltf.writeGltf(dir.path(), "sheared"));
    const glm::vec3 expected = glm::normalize(test::faceNormal(scene, 0)); // (1/2, 1, 0) normalised
    expectNear(expected, glm::normalize(glm::vec3(0.5f, 1.0f, 0.0f)));
    for (const glm::vec3& n : scene.normals) expectNear(n, expected);
}

TEST(GltfLoader, ReadsBaseColorFactorAndTexture) {
    TempDir dir;
    GltfBuilder gltf;
    const std::vector<uint8_t> pixels = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 10, 20, 30, 128};
    const std::string png = test::encodePngRgba8(2, 2, pixels);
    const int imageView = gltf.addBufferView(png.data(), png.size());
    gltf.json["images"] = json::array({{{"bufferView", imageView}, {"mimeType", "image/png"}, {"name", "checker"}}});
    gltf.json["textures"] = json::array({{{"source", 0}}});
    gltf.json["materials"] = json::array(
        {{{"name", "plain"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 0.5}}}}},
         {{"name", "textured"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    const int positions = gltf.addPositions(kQuadPositions);
    const int uvs = gltf.addVec2({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    const int plain = gltf.addMesh({{"POSITION", positions}}, gltf.addIndices(kQuadIndices), 0);
    const int textured = gltf.addMesh({{"POSITION", positions}, {"TEXCOORD_0", uvs}}, gltf.addIndices(kQuadIndices), 1);
    gltf.setSceneRoots({gltf.addNode({{"mesh", plain}}), gltf.addNode({{"mesh", textured}, {"translation", {0, 0, 1}}})});
    const Scene scene = loadSceneFile(gltf.writeGlb(dir / "materials.glb"));

    ASSERT_EQ(scene.materials.size(), 2u);
    ASSERT_EQ(scene.triangleCount(), 4u);
    ASSERT_EQ(scene.texcoords.size(), scene.positions.size());
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const bool isTextured = scene.positions[scene.triangles[i].x].z > 0.5f;
        const Material& material = scene.materials[scene.triangleMaterials[i]];
        if (isTextured) {
            EXPECT_EQ(material.name, "textured");
            EXPECT_EQ(material.baseColorFactor, glm::vec4(1.0f)); // the glTF default
            EXPECT_EQ(material.baseColorTexture, 0);
        } else {
            EXPECT_EQ(material.name, "plain");
            EXPECT_EQ(material.baseColorFactor, glm::vec4(0.2f, 0.4f, 0.6f, 0.5f));
            EXPECT_EQ(material.baseColorTexture, -1);
        }
    }
    EXPECT_TRUE(std::find(scene.texcoords.begin(), scene.texcoords.end(), glm::vec2(1, 1)) != scene.texcoords.end());
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_EQ(scene.textures[0].width, 2u);
    EXPECT_EQ(scene.textures[0].height, 2u);
    EXPECT_EQ(scene.textures[0].rgba8, pixels);
    EXPECT_EQ(scene.textures[0].name, "checker");
    EXPECT_TRUE(scene.warnings.empty());
}

// A texture file that is not there loads (the material keeps its factor) but is named in the scene's warnings;
// the decoded one of the test above gives none.
TEST(GltfLoader, AMissingTextureFileIsAWarningNamingIt) {
    TempDir dir;
    GltfBuilder gltf;
    gltf.json["images"] = json::array({{{"uri", "textures/gone.png"}}});
    gltf.json["textures"] = json::array({{{"source", 0}}});
    gltf.json["materials"] = json::array({{{"name", "textured"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    const int positions = gltf.addPositions(kQuadPositions);
    const int uvs = gltf.addVec2({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    gltf.setSceneRoots({gltf.addNode({{"mesh", gltf.addMesh({{"POSITION", positions}, {"TEXCOORD_0", uvs}},
                                                           gltf.addIndices(kQuadIndices), 0)}})});
    const Scene scene = loadSceneFile(gltf.writeGltf(dir.path(), "missing_texture"));
    EXPECT_EQ(scene.triangleCount(), 2u);
    EXPECT_EQ(scene.materials.at(0).baseColorTexture, -1);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("missing_texture.gltf: base-colour texture 'textures/gone.png'"), std::string::npos)
        << scene.warnings[0];
}

TEST(GltfLoader, TurnsPerspectiveCameraNodesIntoCameras) {
    TempDir dir;
    GltfBuilder gltf;
    gltf.json["cameras"] = json::array({{{"type", "perspective"}, {"name", "main"},
                                         {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}});
    const int quad = gltf.addNode({{"mesh", addQuadMesh(gltf)}});
    const int camera = gltf.addNode({{"camera", 0}, {"translation", {1, 2, 3}}, {"rotation", quaternion({0, 1, 0}, 90)}});
    gltf.setSceneRoots({quad, gltf.addNode({{"children", {camera}}, {"translation", {0, 1, 0}}})});
    const Scene scene = loadSceneFile(gltf.writeGltf(dir.path(), "camera"));
    ASSERT_EQ(scene.cameras.size(), 1u);
    const NamedCamera& named = scene.cameras[0];
    EXPECT_EQ(named.name, "main");
    expectNear(named.camera.eye, {1, 3, 3});
    expectNear(glm::normalize(named.camera.target - named.camera.eye), {-1, 0, 0}); // -Z turned by R_y(90)
    expectNear(named.camera.up, {0, 1, 0});
    EXPECT_NEAR(named.camera.fovYDegrees, glm::degrees(0.5f), 1e-4f);
}

TEST(GltfLoader, SkipsPointsAndConvertsStripsAndFans) {
    TempDir dir;
    GltfBuilder gltf;
    const int positions = gltf.addPositions({{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {1, 0, 1}});
    const int fanPositions = gltf.addPositions({{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}});
    const int mesh = gltf.addMesh({{"POSITION", positions}}, -1, -1, 5); // triangle strip
    gltf.json["meshes"][mesh]["primitives"].push_back({{"attributes", {{"POSITION", positions}}}, {"mode", 0}});
    gltf.json["meshes"][mesh]["primitives"].push_back({{"attributes", {{"POSITION", positions}}}, {"mode", 1}});
    gltf.json["meshes"][mesh]["primitives"].push_back({{"attributes", {{"POSITION", fanPositions}}}, {"mode", 6}});
    gltf.setSceneRoots({gltf.addNode({{"mesh", mesh}})});
    const Scene scene = loadSceneFile(gltf.writeGltf(dir.path(), "modes"));
    ASSERT_EQ(scene.triangleCount(), 4u); // 2 from the strip, 2 from the fan; points and lines skipped
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::vec3 face = test::faceNormal(scene, i);
        EXPECT_GT(face.y, 0.0f) << "triangle " << i << " has inconsistent winding";
    }
}

TEST(GltfLoader, UsesTheDefaultSceneElseAllRootNodes) {
    TempDir dir;
    GltfBuilder gltf;
    const int quad = addQuadMesh(gltf);
    const int a = gltf.addNode({{"mesh", quad}});
    const int b = gltf.addNode({{"mesh", quad}, {"translation", {5, 0, 0}}});
    const int c = gltf.addNode({{"mesh", quad}, {"translation", {0, 5, 0}}, {"children", {b}}});
    gltf.json["scenes"] = json::array({{{"nodes", {a}}}, {{"nodes", {c}}}});
    gltf.json["scene"] = 1;
    const Scene second = loadSceneFile(gltf.writeGltf(dir.path(), "second"));
    EXPECT_EQ(second.stats.instanceCount, 2u);
    EXPECT_TRUE(test::hasVertexNear(second, {5, 5, 0})); // b under c
    EXPECT_FALSE(test::hasVertexNear(second, {0, 0, 0}));

    gltf.json.erase("scenes");
    gltf.json.erase("scene");
    const Scene roots = loadSceneFile(gltf.writeGltf(dir.path(), "roots")); // roots: a and c
    EXPECT_EQ(roots.stats.instanceCount, 3u);
    EXPECT_EQ(roots.stats.meshCount, 1u);
    EXPECT_EQ(roots.stats.uniqueTriangles, 2u);
    EXPECT_EQ(roots.stats.instancedTriangles, 6u);
}

TEST(GltfLoader, DropsAndCountsDegenerateTrianglesPerInstance) {
    TempDir dir;
    GltfBuilder gltf;
    const int positions = gltf.addPositions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}});
    // One good triangle, one with a repeated index, one collinear (zero area).
    const int mesh = gltf.addMesh({{"POSITION", positions}}, gltf.addIndices({0, 1, 2, 0, 0, 2, 0, 1, 3}));
    gltf.setSceneRoots({gltf.addNode({{"mesh", mesh}}), gltf.addNode({{"mesh", mesh}, {"translation", {0, 0, 1}}})});
    const Scene scene = loadSceneFile(gltf.writeGltf(dir.path(), "degenerate"));
    EXPECT_EQ(scene.triangleCount(), 2u);
    EXPECT_EQ(scene.stats.uniqueTriangles, 1u);
    EXPECT_EQ(scene.stats.degenerateTrianglesDropped, 4u); // two per instance
}

} // namespace
} // namespace chcrt
