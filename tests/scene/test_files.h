#pragma once
// Writers for small scene files generated at test time: a temporary directory, a glTF/GLB builder, a minimal
// PNG encoder and helpers to compare scenes. Test support only.
#include "renderer/scene/scene.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace chcrt::test {

// A fresh directory under the system temp directory, removed with everything in it on destruction.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

void writeFile(const std::filesystem::path& file, const std::string& bytes);
std::string readFile(const std::filesystem::path& file);

// An 8-bit RGBA PNG with uncompressed (stored) deflate blocks: enough for tinygltf's stb_image.
std::string encodePngRgba8(uint32_t width, uint32_t height, const std::vector<uint8_t>& rgba);

// Builds a glTF document and its binary buffer; the test edits `json` (nodes, meshes, materials) directly.
class GltfBuilder {
public:
    GltfBuilder();
    nlohmann::json json;

    // Appends bytes to the binary buffer as a new buffer view (4-byte aligned); returns its index.
    int addBufferView(const void* data, size_t bytes, size_t byteStride = 0);
    int addAccessor(int bufferView, int componentType, size_t count, const std::string& type, size_t byteOffset = 0);
    int addPositions(const std::vector<glm::vec3>& positions);
    int addVec3(const std::vector<glm::vec3>& values);
    int addVec2(const std::vector<glm::vec2>& values);
    // componentType: 5121 (uint8), 5123 (uint16) or 5125 (uint32).
    int addIndices(const std::vector<uint32_t>& indices, int componentType = 5125);
    // Adds a mesh with one primitive; attributes maps names ("POSITION") to accessors. Returns the mesh index.
    int addMesh(const nlohmann::json& attributes, int indices = -1, int material = -1, int mode = -1);
    int addNode(const nlohmann::json& node);
    void setSceneRoots(const std::vector<int>& roots);

    // .gltf with an external .bin next to it; returns the .gltf path.
    std::filesystem::path writeGltf(const std::filesystem::path& dir, const std::string& stem) const;
    std::string glbBytes() const;
    std::filesystem::path writeGlb(const std::filesystem::path& file) const;

    const std::string& binary() const { return bin_; }

private:
    std::string bin_;
};

// True when `scene` has a vertex within `tolerance` of `p`.
bool hasVertexNear(const Scene& scene, const glm::vec3& p, float tolerance = 1e-5f);

// The unnormalised geometric normal of triangle i (from its winding).
glm::vec3 faceNormal(const Scene& scene, size_t triangle);

} // namespace chcrt::test
