// Writes the seed corpora of the fuzz harnesses (tests/data/fuzz/<harness>/seed_*): small valid inputs of each
// reader, made the way the tests make theirs (generator scenes, prepareScene, the cache writers). Run it again
// when a format changes: build-fuzz/bin/fuzz_make_seeds tests/data/fuzz
#include "linespace/linespace_cache.h"
#include "linespace/ntree_cache.h"
#include "renderer/outofcore/prepare.h"
#include "renderer/scene/camera_path.h"
#include "renderer/scene/procedural/procedural.h"
#include "tests/fuzz/cache_fuzz_scene.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace chcrt;

namespace {

void write(const fs::path& file, const std::string& bytes) {
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary) << bytes;
}

std::string read(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <typename T>
void append(std::string& s, T v) {
    s.append(reinterpret_cast<const char*>(&v), sizeof(v));
}

template <typename T>
void appendBigEndian(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (size_t i = sizeof(T); i-- > 0;) s.push_back(b[i]);
}

std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
        uint32_t v = uint8_t(in[i]) << 16;
        if (i + 1 < in.size()) v |= uint8_t(in[i + 1]) << 8;
        if (i + 2 < in.size()) v |= uint8_t(in[i + 2]);
        out += t[(v >> 18) & 63];
        out += t[(v >> 12) & 63];
        out += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
        out += i + 2 < in.size() ? t[v & 63] : '=';
    }
    return out;
}

void plySeeds(const fs::path& dir) {
    write(dir / "seed_ascii.ply",
          "ply\nformat ascii 1.0\ncomment a unit quad and a triangle with normals\nelement vertex 5\n"
          "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
          "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
          "0 0 0 0 1 0\n1 0 0 0 1 0\n1 0 1 0 1 0\n0 0 1 0 1 0\n0.5 1 0.5 0 0 1\n4 0 1 2 3\n3 0 1 4\n");
    // Binary, both byte orders: double positions, a uint8 colour, int32 list counts (as some exporters write).
    for (bool big : {false, true}) {
        std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                        " 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                        "property uchar red\nelement face 2\nproperty list int uint vertex_indices\nend_header\n";
        const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 1}};
        for (const auto& p : v) {
            for (double c : p) big ? appendBigEndian(s, c) : append(s, c);
            s.push_back(char(200));
        }
        const uint32_t faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (const auto& f : faces) {
            big ? appendBigEndian(s, int32_t(3)) : append(s, int32_t(3));
            for (int k = 0; k < 3; ++k) big ? appendBigEndian(s, f[k]) : append(s, f[k]);
        }
        write(dir / (big ? "seed_big.ply" : "seed_little.ply"), s);
    }
}

void objSeeds(const fs::path& dir) {
    write(dir / "seed_cube.obj",
          "# a cube with texture coordinates, normals, groups, a material and negative indices\nmtllib missing.mtl\n"
          "o cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 -1\nvn 0 0 1\ng front\nusemtl red\n"
          "f 1/1/1 2/2/1 3/3/1 4/4/1\nf 5//2 6//2 7//2\ng back\nusemtl blue\nf -1 -2 -3\nf 1/1 5/2 8/3 4/4\ns off\nl 1 2\n");
    write(dir / "seed_fan.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\nf 1 2 3 4 5\nf 1 3 5\n");
}

// A mesh instanced by two nodes under a rotated, scaled parent; uint16 indices; a material with a texture whose
// image file is missing (or, in seed_textured.gltf, embedded); the buffer embedded as a data URI (.gltf) or as the
// GLB's BIN chunk.
void gltfSeeds(const fs::path& dir) {
    std::string bin;
    const float positions[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const float uvs[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
    bin.append(reinterpret_cast<const char*>(positions), sizeof(positions));
    bin.append(reinterpret_cast<const char*>(uvs), sizeof(uvs));
    bin.append(reinterpret_cast<const char*>(indices), sizeof(indices));
    bin.append(4, '\0');
    nlohmann::json j = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes",
         {{{"children", {1, 2}}, {"rotation", {0, 0.7071068, 0, 0.7071068}}, {"scale", {2, 2, 2}}},
          {{"mesh", 0}, {"translation", {0, 0, 1}}},
          {{"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 3, 0, 0, 1}}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}, {"material", 0}}}}}}},
        {"materials", {{{"name", "tex"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0.5, 0.5, 1}}, {"baseColorTexture", {{"index", 0}}}}}}}},
        {"textures", {{{"source", 0}}}},
        {"images", {{{"uri", "missing.png"}}}},
        {"accessors",
         {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
          {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
          {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
          {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 32}},
          {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 12}}}},
        {"buffers", {{{"byteLength", bin.size()}}}},
    };
    nlohmann::json embedded = j;
    embedded["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
    write(dir / "seed_instanced.gltf", embedded.dump());
    // The same with its texture embedded too (a 1 x 1 RGBA PNG), so that image headers and decoding are fuzzed.
    embedded["images"][0]["uri"] = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg==";
    write(dir / "seed_textured.gltf", embedded.dump());
    std::string json = j.dump();
    while (json.size() % 4 != 0) json.push_back(' ');
    std::string glb = "glTF";
    append(glb, uint32_t(2));
    append(glb, uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    append(glb, uint32_t(json.size()));
    glb += "JSON" + json;
    append(glb, uint32_t(bin.size()));
    glb += "BIN";
    glb.push_back('\0');
    glb += bin;
    write(dir / "seed_instanced.glb", glb);
}

void textSeeds(const fs::path& root) {
    int i = 0;
    for (const char* f : {"0-300:30", "3,5-9", "7", " 1 - 10 , 12 ", "5,1-6", "0-9999999:1000"}) {
        write(root / "frames" / ("seed_" + std::to_string(i++)), f);
    }
    i = 0;
    for (const char* s : {"city:10m:seed=3", "grid:4x4:plant:12.8m", "plant:500k:seed=3", "interior:1.5m", "city",
                          "plane-and-box", "closed-box", "one-triangle", "grid:2x3:city:10k:seed=7",
                          "one-triangle:seed=3"}) {
        write(root / "scene_spec" / ("seed_" + std::to_string(i++)), s);
    }
    ProceduralSpec spec;
    parseProceduralSpec("city:10k", spec);
    write(root / "camera_path" / "seed_city_near.json", cameraPathToJson(proceduralNearPath(spec)));
    CameraPath two;
    two.name = "two";
    two.fps = 24.0;
    two.fovYDegrees = 50.0f;
    two.keyframes = {{0.0, {0, 1, 5}, {0, 0, 0}, {0, 1, 0}}, {2.5, {5, 1, 0}, {0, 0, 0}, {0, 0, 1}}};
    write(root / "camera_path" / "seed_two_keys.json", cameraPathToJson(two));
}

void chsSeeds(const fs::path& dir, const fs::path& scratch) {
    // Full layout: version 1 (no LOD proxies) from the two small scenes, version 2 (a LOD directory and proxy blobs)
    // from a city small enough to stay a quick seed. Compact layout (version 3): a small scene and the same city.
    struct Seed {
        const char* scene;
        uint32_t lodLevels;
        bool compact;
        const char* name;
    };
    for (const Seed& seed : {Seed{"closed-box", 0u, false, "closed-box"}, Seed{"plane-and-box", 0u, false, "plane-and-box"},
                             Seed{"city:600", 2u, false, "city-600-lod"}, Seed{"closed-box", 0u, true, "closed-box-compact"},
                             Seed{"city:600", 2u, true, "city-600-lod-compact"}}) {
        outofcore::PrepareOptions options;
        options.subtreeTriangles = seed.lodLevels == 0 ? 4 : 200;
        options.memoryBytes = 64ull << 20;
        options.lodLevels = seed.lodLevels;
        options.compact = seed.compact;
        const fs::path file = scratch / (std::string(seed.name) + ".chs");
        outofcore::prepareScene(seed.scene, file, options);
        write(dir / ("seed_" + std::string(seed.name) + ".chs"), read(file));
    }
}

void cacheSeeds(const fs::path& root, const fs::path& scratch) {
    const Bvh& bvh = fuzz::cacheFuzzBvh();
    const ls::LineSpaceParams lp = fuzz::cacheFuzzLineSpaceParams();
    ls::saveLineSpaceCache(scratch / "ls", ls::lineSpaceInputHash(bvh), ls::buildLineSpaces(bvh, lp));
    const ls::NTreeParams np = fuzz::cacheFuzzNTreeParams();
    ls::saveNTreeCache(scratch / "nt", ls::nTreeInputHash(bvh), ls::buildNTree(bvh, np));
    // The harnesses take the payload: what follows the 56-byte header.
    write(root / "linespace_cache" / "seed_plane_and_box", read(scratch / "ls").substr(sizeof(ls::CacheFileHeader)));
    write(root / "ntree_cache" / "seed_plane_and_box", read(scratch / "nt").substr(sizeof(ls::CacheFileHeader)));
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUTPUT_DIR (tests/data/fuzz)\n", argv[0]);
        return 1;
    }
    const fs::path root = argv[1];
    const fs::path scratch = fs::temp_directory_path() / ("chcrt-seeds-" + std::to_string(::getpid()));
    fs::create_directories(scratch);
    plySeeds(root / "ply");
    objSeeds(root / "obj");
    gltfSeeds(root / "gltf");
    textSeeds(root);
    chsSeeds(root / "chs", scratch);
    cacheSeeds(root, scratch);
    fs::remove_all(scratch);
    return 0;
}
