#include "tests/scene/test_files.h"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>
#include <unistd.h>

namespace chcrt::test {

TempDir::TempDir() {
    static std::atomic<int> counter{0};
    std::random_device seedSource;
    path_ = std::filesystem::temp_directory_path() /
            ("chcrt_scene_tests_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" +
             std::to_string(seedSource()));
    std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

void writeFile(const std::filesystem::path& file, const std::string& bytes) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + file.string());
}

std::string readFile(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

namespace {

void putBigEndian32(std::string& out, uint32_t value) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((value >> shift) & 0xFF));
}

uint32_t crc32(const std::string& bytes) {
    uint32_t crc = 0xFFFFFFFFu;
    for (unsigned char byte : bytes) {
        crc ^= byte;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return crc ^ 0xFFFFFFFFu;
}

void appendChunk(std::string& png, const char* type, const std::string& data) {
    putBigEndian32(png, static_cast<uint32_t>(data.size()));
    const std::string typed = std::string(type, 4) + data;
    png += typed;
    putBigEndian32(png, crc32(typed));
}

void appendLittleEndian32(std::string& out, uint32_t value) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<char>((value >> shift) & 0xFF));
}

} // namespace

std::string encodePngRgba8(uint32_t width, uint32_t height, const std::vector<uint8_t>& rgba) {
    std::string raw; // each row: filter byte 0 (None) + pixels
    for (uint32_t y = 0; y < height; ++y) {
        raw.push_back(0);
        raw.append(reinterpret_cast<const char*>(&rgba[size_t(y) * width * 4]), size_t(width) * 4);
    }
    std::string zlib = {0x78, 0x01};
    for (size_t pos = 0; pos < raw.size() || pos == 0; pos += 65535) {
        const size_t length = std::min<size_t>(65535, raw.size() - pos);
        zlib.push_back(pos + length >= raw.size() ? 1 : 0); // BFINAL, BTYPE = stored
        zlib.push_back(static_cast<char>(length & 0xFF));
        zlib.push_back(static_cast<char>(length >> 8));
        zlib.push_back(static_cast<char>(~length & 0xFF));
        zlib.push_back(static_cast<char>((~length >> 8) & 0xFF));
        zlib.append(raw, pos, length);
        if (raw.empty()) break;
    }
    uint32_t a = 1, b = 0; // Adler-32
    for (unsigned char byte : raw) {
        a = (a + byte) % 65521;
        b = (b + a) % 65521;
    }
    putBigEndian32(zlib, (b << 16) | a);

    std::string png = "\x89PNG\r\n\x1a\n";
    std::string header;
    putBigEndian32(header, width);
    putBigEndian32(header, height);
    header += std::string{8, 6, 0, 0, 0}; // 8 bits, RGBA, deflate, adaptive filtering, no interlace
    appendChunk(png, "IHDR", header);
    appendChunk(png, "IDAT", zlib);
    appendChunk(png, "IEND", "");
    return png;
}

GltfBuilder::GltfBuilder() {
    json = {{"asset", {{"version", "2.0"}}},
            {"nodes", nlohmann::json::array()},
            {"meshes", nlohmann::json::array()},
            {"accessors", nlohmann::json::array()},
            {"bufferViews", nlohmann::json::array()}};
}

int GltfBuilder::addBufferView(const void* data, size_t bytes, size_t byteStride) {
    while (bin_.size() % 4 != 0) bin_.push_back('\0');
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
    if (byteStride != 0) view["byteStride"] = byteStride;
    bin_.append(static_cast<const char*>(data), bytes);
    json["bufferViews"].push_back(view);
    return static_cast<int>(json["bufferViews"].size() - 1);
}

int GltfBuilder::addAccessor(int bufferView, int componentType, size_t count, const std::string& type, size_t byteOffset) {
    nlohmann::json accessor = {{"componentType", componentType}, {"count", count}, {"type", type}};
    if (bufferView >= 0) accessor["bufferView"] = bufferView;
    if (byteOffset != 0) accessor["byteOffset"] = byteOffset;
    json["accessors"].push_back(accessor);
    return static_cast<int>(json["accessors"].size() - 1);
}

int GltfBuilder::addPositions(const std::vector<glm::vec3>& positions) { return addVec3(positions); }

int GltfBuilder::addVec3(const std::vector<glm::vec3>& values) {
    const int view = addBufferView(values.data(), values.size() * sizeof(glm::vec3));
    return addAccessor(view, 5126, values.size(), "VEC3");
}

int GltfBuilder::addVec2(const std::vector<glm::vec2>& values) {
    const int view = addBufferView(values.data(), values.size() * sizeof(glm::vec2));
    return addAccessor(view, 5126, values.size(), "VEC2");
}

int GltfBuilder::addIndices(const std::vector<uint32_t>& indices, int componentType) {
    std::string bytes;
    for (uint32_t index : indices) {
        if (componentType == 5121) bytes.push_back(static_cast<char>(index));
        else if (componentType == 5123) bytes.append(reinterpret_cast<const char*>(&index), 2); // little-endian host
        else bytes.append(reinterpret_cast<const char*>(&index), 4);
    }
    const int view = addBufferView(bytes.data(), bytes.size());
    return addAccessor(view, componentType, indices.size(), "SCALAR");
}

int GltfBuilder::addMesh(const nlohmann::json& attributes, int indices, int material, int mode) {
    nlohmann::json primitive = {{"attributes", attributes}};
    if (indices >= 0) primitive["indices"] = indices;
    if (material >= 0) primitive["material"] = material;
    if (mode >= 0) primitive["mode"] = mode;
    json["meshes"].push_back({{"primitives", nlohmann::json::array({primitive})}});
    return static_cast<int>(json["meshes"].size() - 1);
}

int GltfBuilder::addNode(const nlohmann::json& node) {
    json["nodes"].push_back(node);
    return static_cast<int>(json["nodes"].size() - 1);
}

void GltfBuilder::setSceneRoots(const std::vector<int>& roots) {
    json["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
    json["scene"] = 0;
}

std::filesystem::path GltfBuilder::writeGltf(const std::filesystem::path& dir, const std::string& stem) const {
    nlohmann::json document = json;
    if (!bin_.empty()) {
        document["buffers"] = nlohmann::json::array({{{"uri", stem + ".bin"}, {"byteLength", bin_.size()}}});
        writeFile(dir / (stem + ".bin"), bin_);
    }
    const std::filesystem::path file = dir / (stem + ".gltf");
    writeFile(file, document.dump(1));
    return file;
}

std::string GltfBuilder::glbBytes() const {
    nlohmann::json document = json;
    document["buffers"] = nlohmann::json::array({{{"byteLength", bin_.size()}}});
    std::string jsonChunk = document.dump();
    while (jsonChunk.size() % 4 != 0) jsonChunk.push_back(' ');
    std::string binChunk = bin_;
    while (binChunk.size() % 4 != 0) binChunk.push_back('\0');
    std::string glb = "glTF";
    appendLittleEndian32(glb, 2);
    appendLittleEndian32(glb, static_cast<uint32_t>(12 + 8 + jsonChunk.size() + 8 + binChunk.size()));
    appendLittleEndian32(glb, static_cast<uint32_t>(jsonChunk.size()));
    glb += "JSON";
    glb += jsonChunk;
    appendLittleEndian32(glb, static_cast<uint32_t>(binChunk.size()));
    glb += std::string("BIN\0", 4);
    glb += binChunk;
    return glb;
}

std::filesystem::path GltfBuilder::writeGlb(const std::filesystem::path& file) const {
    writeFile(file, glbBytes());
    return file;
}

bool hasVertexNear(const Scene& scene, const glm::vec3& p, float tolerance) {
    for (const glm::vec3& q : scene.positions)
        if (glm::all(glm::lessThanEqual(glm::abs(q - p), glm::vec3(tolerance)))) return true;
    return false;
}

glm::vec3 faceNormal(const Scene& scene, size_t triangle) {
    const glm::uvec3 t = scene.triangles[triangle];
    return glm::cross(scene.positions[t.y] - scene.positions[t.x], scene.positions[t.z] - scene.positions[t.x]);
}

} // namespace chcrt::test
