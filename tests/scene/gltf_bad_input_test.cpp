// Bad input through loadSceneFile/loadGltf: every failure is one InputError naming the file, never a crash.
#include "renderer/core/error.h"
#include "renderer/core/memory_budget.h"
#include "renderer/scene/scene_loader.h"
#include "tests/scene/test_files.h"

#include <gtest/gtest.h>

#include <limits>

namespace chcrt {
namespace {

using nlohmann::json;
using test::GltfBuilder;
using test::TempDir;

// The InputError message of loading `file`, or "" when it loads.
std::string loadError(const std::filesystem::path& file) {
    try {
        loadSceneFile(file);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

void expectLoadError(const std::filesystem::path& file, const std::string& fragment) {
    const std::string message = loadError(file);
    EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << "message does not start with the file: " << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << "'" << fragment << "' not in: " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "message is not one line: " << message;
}

GltfBuilder triangleScene(const std::vector<glm::vec3>& positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                          const std::vector<uint32_t>& indices = {0, 1, 2}) {
    GltfBuilder gltf;
    const int mesh = gltf.addMesh({{"POSITION", gltf.addPositions(positions)}}, gltf.addIndices(indices));
    gltf.setSceneRoots({gltf.addNode({{"mesh", mesh}})});
    return gltf;
}

TEST(SceneLoaderErrors, MissingFile) {
    TempDir dir;
    for (const char* name : {"absent.gltf", "absent.glb", "absent.ply", "absent.obj", "absent.xyz"}) {
        const std::filesystem::path file = dir / name;
        EXPECT_EQ(loadError(file), file.string() + ": no such file");
    }
    EXPECT_THROW(loadGltf(dir / "absent.gltf"), InputError);
    EXPECT_THROW(loadPly(dir / "absent.ply"), InputError);
    EXPECT_THROW(loadObj(dir / "absent.obj"), InputError);
}

TEST(SceneLoaderErrors, UnknownExtension) {
    TempDir dir;
    test::writeFile(dir / "scene.xyz", "v 0 0 0\n");
    expectLoadError(dir / "scene.xyz", "unknown scene file extension '.xyz'");
}

TEST(SceneLoaderErrors, ExtensionIsCaseInsensitive) {
    TempDir dir;
    EXPECT_EQ(loadSceneFile(triangleScene().writeGlb(dir / "UPPER.GLB")).triangleCount(), 1u);
}

TEST(GltfErrors, EveryTruncationOfAGlbIsAnInputError) {
    TempDir dir;
    const std::string glb = triangleScene().glbBytes();
    ASSERT_NO_THROW(loadSceneFile(triangleScene().writeGlb(dir / "full.glb")));
    const std::filesystem::path file = dir / "cut.glb";
    for (size_t length = 0; length < glb.size(); ++length) {
        test::writeFile(file, glb.substr(0, length));
        EXPECT_THROW(loadSceneFile(file), InputError) << "length " << length << " of " << glb.size();
    }
}

TEST(GltfErrors, CorruptedGlbLengthFieldsAreInputErrors) {
    TempDir dir;
    const std::string glb = triangleScene().glbBytes();
    const std::filesystem::path file = dir / "corrupt.glb";
    // Overwrite each header/chunk length field (bytes 8, 12 and the BIN chunk length) with hostile values.
    const size_t binChunk = 20 + (static_cast<unsigned char>(glb[12]) | static_cast<unsigned char>(glb[13]) << 8);
    for (size_t offset : {size_t(8), size_t(12), binChunk}) {
        for (uint32_t value : {0u, 1u, 3u, 0x7FFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFF0u}) {
            std::string bytes = glb;
            for (int k = 0; k < 4; ++k) bytes[offset + k] = static_cast<char>((value >> (8 * k)) & 0xFF);
            test::writeFile(file, bytes);
            EXPECT_THROW(loadSceneFile(file), InputError) << "offset " << offset << " value " << value;
        }
    }
}

TEST(GltfErrors, MalformedJson) {
    TempDir dir;
    test::writeFile(dir / "broken.gltf", R"({"asset": {"version": "2.0"}, "nodes": [)");
    expectLoadError(dir / "broken.gltf", "invalid glTF");
    test::writeFile(dir / "empty.gltf", "");
    expectLoadError(dir / "empty.gltf", "empty");
}

TEST(GltfErrors, EveryTruncationOfTheJsonIsAnInputError) {
    TempDir dir;
    const std::string text = test::readFile(triangleScene().writeGltf(dir.path(), "good"));
    const std::filesystem::path file = dir / "cut.gltf";
    for (size_t length = 0; length + 1 < text.size(); length += 3) {
        test::writeFile(file, text.substr(0, length));
        EXPECT_THROW(loadSceneFile(file), InputError) << "length " << length;
    }
}

TEST(GltfErrors, MissingExternalBuffer) {
    TempDir dir;
    const std::filesystem::path file = triangleScene().writeGltf(dir.path(), "nobin");
    std::filesystem::remove(dir / "nobin.bin");
    EXPECT_THROW(loadSceneFile(file), InputError);
}

// A buffer URI naming a directory: tinygltf's own reader sized its buffer from the directory stream's end (2^63 - 1
// on ext4; found by fuzzing through an image URI); the loader's reader refuses anything but a regular file.
TEST(GltfErrors, ABufferThatIsADirectoryIsRefused) {
    TempDir dir;
    const std::filesystem::path file = triangleScene().writeGltf(dir.path(), "dirbin");
    std::filesystem::remove(dir / "dirbin.bin");
    std::filesystem::create_directory(dir / "dirbin.bin");
    expectLoadError(file, "not a regular file");
}

TEST(GltfErrors, ZeroTriangles) {
    TempDir dir;
    GltfBuilder gltf;
    const int mesh = gltf.addMesh({{"POSITION", gltf.addPositions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})}}, -1, -1, 0);
    gltf.setSceneRoots({gltf.addNode({{"mesh", mesh}})});
    const std::filesystem::path file = gltf.writeGltf(dir.path(), "points");
    EXPECT_EQ(loadError(file), file.string() + ": scene has no triangles");
    GltfBuilder empty;
    empty.setSceneRoots({empty.addNode({{"name", "nothing"}})});
    expectLoadError(empty.writeGltf(dir.path(), "empty"), "scene has no triangles");
}

TEST(GltfErrors, AccessorCountBeyondItsBufferIsRefusedBeforeAllocating) {
    TempDir dir;
    for (const bool positions : {true, false}) {
        GltfBuilder gltf = triangleScene();
        const nlohmann::json& primitive = gltf.json["meshes"][0]["primitives"][0];
        const int accessor = positions ? primitive["attributes"]["POSITION"].get<int>() : primitive["indices"].get<int>();
        // 10^12 elements: reading them would need terabytes; the count is checked against the buffer view first.
        gltf.json["accessors"][accessor]["count"] = 1'000'000'000'000ull;
        expectLoadError(gltf.writeGlb(dir / "count.glb"), "with 1000000000000 elements exceeds its buffer view");
    }
}

// A textured quad whose image (embedded in the GLB) is `png`.
GltfBuilder texturedQuad(const std::string& png) {
    GltfBuilder gltf;
    const int imageView = gltf.addBufferView(png.data(), png.size());
    gltf.json["images"] = json::array({{{"bufferView", imageView}, {"mimeType", "image/png"}, {"name", "huge"}}});
    gltf.json["textures"] = json::array({{{"source", 0}}});
    gltf.json["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    const int positions = gltf.addPositions({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
    const int uvs = gltf.addVec2({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    gltf.setSceneRoots({gltf.addNode(
        {{"mesh", gltf.addMesh({{"POSITION", positions}, {"TEXCOORD_0", uvs}}, gltf.addIndices({0, 1, 2, 0, 2, 3}), 0)}})});
    return gltf;
}

// A valid 1 x 1 PNG whose IHDR chunk then claims width x height (stb_image reads no checksum): a few bytes that
// a decoder sizing its output from the header would turn into width * height * 4 bytes.
std::string pngClaiming(uint32_t width, uint32_t height) {
    std::string png = test::encodePngRgba8(1, 1, {1, 2, 3, 4});
    for (int i = 0; i < 4; ++i) {
        png[size_t(16 + i)] = char(width >> (24 - 8 * i));
        png[size_t(20 + i)] = char(height >> (24 - 8 * i));
    }
    return png;
}

// Restores the default memory budget when a test that set one ends.
struct BudgetScope {
    explicit BudgetScope(uint64_t bytes) { setMemoryBudgetBytes(bytes); }
    ~BudgetScope() { setMemoryBudgetBytes(0); }
};

TEST(GltfErrors, HugeTexturesAreRefusedBeforeDecoding) {
    TempDir dir;
    // 10^9 x 10^9 texels (4 * 10^18 bytes decoded), and one texel more than a side may have.
    expectLoadError(texturedQuad(pngClaiming(1'000'000'000, 1'000'000'000)).writeGlb(dir / "huge.glb"),
                    "image 0 ('huge') is 1000000000 x 1000000000 texels, more than the 16384 per side a texture may "
                    "have (refused before decoding)");
    expectLoadError(texturedQuad(pngClaiming(16385, 1)).writeGlb(dir / "wide.glb"), "is 16385 x 1 texels");
    // Within the side limit but not within the budget: 16384^2 texels decode to 1 GiB and are copied twice.
    const BudgetScope budget(uint64_t(256) << 20);
    expectLoadError(texturedQuad(pngClaiming(16384, 16384)).writeGlb(dir / "big.glb"),
                    "(decoding image 0 ('huge'), 16384 x 16384 texels: 3,072 MiB), more than the 256 MiB "
                    "--max-memory-mb allows");
}

TEST(GltfErrors, InstancingBeyondTheMemoryBudgetIsRefusedBeforeFlattening) {
    TempDir dir;
    GltfBuilder gltf = triangleScene();
    // 16384 instances of the triangle under one parent: 3 vertices of 32 bytes and a triangle of 16 each, 1.75 MiB.
    nlohmann::json children = nlohmann::json::array();
    for (int i = 0; i < 16384; ++i) children.push_back(gltf.addNode({{"mesh", 0}}));
    gltf.setSceneRoots({gltf.addNode({{"children", children}})});
    const std::filesystem::path file = gltf.writeGlb(dir / "instances.glb");
    EXPECT_EQ(loadSceneFile(file).triangleCount(), 16384u);
    const BudgetScope budget(uint64_t(1) << 20);
    expectLoadError(file, "(the scene's 16384 triangles after instancing: 2 MiB), more than the 1 MiB --max-memory-mb allows");
}

TEST(GltfErrors, NonFiniteVertices) {
    TempDir dir;
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                      -std::numeric_limits<float>::infinity()}) {
        const std::filesystem::path file = triangleScene({{0, 0, 0}, {1, bad, 0}, {0, 1, 0}}).writeGlb(dir / "nan.glb");
        expectLoadError(file, "non-finite position");
    }
}

TEST(GltfErrors, OutOfRangeIndices) {
    TempDir dir;
    expectLoadError(triangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 7}).writeGlb(dir / "index.glb"),
                    "only 3 vertices");
}

TEST(GltfErrors, AccessorsOutsideTheirBuffer) {
    TempDir dir;
    GltfBuilder gltf = triangleScene();
    gltf.json["accessors"][0]["count"] = 1000; // positions claim more than the buffer view holds
    expectLoadError(gltf.writeGlb(dir / "count.glb"), "exceeds");
    gltf = triangleScene();
    gltf.json["accessors"][0]["byteOffset"] = 32;
    EXPECT_THROW(loadSceneFile(gltf.writeGlb(dir / "offset.glb")), InputError);
    gltf = triangleScene();
    gltf.json["bufferViews"][0]["byteStride"] = 8; // smaller than a VEC3 of floats
    EXPECT_THROW(loadSceneFile(gltf.writeGlb(dir / "stride.glb")), InputError);
    gltf = triangleScene();
    gltf.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9;
    EXPECT_THROW(loadSceneFile(gltf.writeGlb(dir / "accessor.glb")), InputError);
    gltf = triangleScene();
    gltf.json["meshes"][0]["primitives"][0]["material"] = 3;
    EXPECT_THROW(loadSceneFile(gltf.writeGlb(dir / "material.glb")), InputError);
    gltf = triangleScene();
    gltf.json["accessors"][0].erase("bufferView");
    EXPECT_THROW(loadSceneFile(gltf.writeGlb(dir / "noview.glb")), InputError);
    gltf = triangleScene();
    gltf.json["nodes"][0]["mesh"] = 4;
    EXPECT_THROW(loadSceneFile(gltf.writeGlb(dir / "mesh.glb")), InputError);
}

TEST(GltfErrors, SparseAccessorsAreRejectedClearly) {
    TempDir dir;
    GltfBuilder gltf = triangleScene();
    const uint32_t sparseIndex = 1;
    const glm::vec3 sparseValue(2, 0, 0);
    const int indicesView = gltf.addBufferView(&sparseIndex, 4);
    const int valuesView = gltf.addBufferView(&sparseValue, 12);
    gltf.json["accessors"][0]["sparse"] = {{"count", 1},
                                           {"indices", {{"bufferView", indicesView}, {"componentType", 5125}}},
                                           {"values", {{"bufferView", valuesView}}}};
    expectLoadError(gltf.writeGlb(dir / "sparse.glb"), "sparse");
}

TEST(GltfErrors, NodeCycles) {
    TempDir dir;
    GltfBuilder gltf = triangleScene();
    gltf.json["nodes"].push_back({{"children", {0}}});
    gltf.json["nodes"][0]["children"] = {1};
    expectLoadError(gltf.writeGlb(dir / "cycle.glb"), "cycle");
}

// Each node has at most one parent (glTF 2.0 §3.5.2): a node listed twice as a child, or both as a root and as a
// child, is refused; 24 nodes each listing the next four times over would otherwise be 4^23 instances.
TEST(GltfErrors, NodesReachedTwiceAreRefused) {
    TempDir dir;
    GltfBuilder twice = triangleScene();
    twice.setSceneRoots({twice.addNode({{"children", {0, 0}}})});
    expectLoadError(twice.writeGlb(dir / "twice.glb"), "node 0 is reached twice");
    GltfBuilder rootAndChild = triangleScene();
    rootAndChild.setSceneRoots({0, rootAndChild.addNode({{"children", {0}}})});
    expectLoadError(rootAndChild.writeGlb(dir / "root.glb"), "node 0 is reached twice");
    GltfBuilder fanout = triangleScene();
    int next = 0;
    for (int level = 0; level < 23; ++level) next = fanout.addNode({{"children", {next, next, next, next}}});
    fanout.setSceneRoots({next});
    expectLoadError(fanout.writeGlb(dir / "fanout.glb"), "is reached twice");
}

} // namespace
} // namespace chcrt

namespace chcrt {
namespace {

// Counts begin/end calls: every step a loader begins must end, on success and on error alike.
class CountingProgress final : public Progress {
public:
    void begin(const std::string&, uint64_t) override { ++begins; }
    void update(uint64_t) override { ++updates; }
    void end() override { ++ends; }
    int begins = 0, ends = 0, updates = 0;
};

TEST(SceneLoaderProgress, EveryBeginHasAnEndEvenOnErrors) {
    TempDir dir;
    const std::string goodObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const std::string goodPly = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    test::writeFile(dir / "good.obj", goodObj);
    test::writeFile(dir / "bad.obj", goodObj + "f 1 2 9\n");
    test::writeFile(dir / "good.ply", goodPly);
    test::writeFile(dir / "bad.ply", goodPly.substr(0, goodPly.size() - 3));
    triangleScene().writeGlb(dir / "good.glb");
    triangleScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 5}).writeGlb(dir / "bad.glb");
    for (const char* name : {"good.obj", "bad.obj", "good.ply", "bad.ply", "good.glb", "bad.glb"}) {
        CountingProgress progress;
        try {
            loadSceneFile(dir / name, progress);
        } catch (const InputError&) {
        }
        EXPECT_GT(progress.begins, 0) << name;
        EXPECT_EQ(progress.begins, progress.ends) << name;
    }
}

} // namespace
} // namespace chcrt
