#include "renderer/scene/mesh_utils.h"

#include "renderer/core/error.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

namespace chcrt::detail {

bool isDegenerateTriangle(const std::vector<glm::vec3>& positions, const glm::uvec3& triangle) {
    if (triangle.x == triangle.y || triangle.y == triangle.z || triangle.z == triangle.x) return true;
    const glm::vec3 p0 = positions[triangle.x];
    const glm::vec3 cross = glm::cross(positions[triangle.y] - p0, positions[triangle.z] - p0);
    // Compare the vector, not its squared length: tiny but real triangles would underflow when squared.
    // NaN compares unequal, so triangles with non-finite vertices are kept for validation to report.
    return cross.x == 0.0f && cross.y == 0.0f && cross.z == 0.0f;
}

uint64_t removeDegenerateTriangles(const std::vector<glm::vec3>& positions, std::vector<glm::uvec3>& triangles,
                                   std::vector<uint32_t>* triangleMaterials) {
    size_t kept = 0;
    for (size_t i = 0; i < triangles.size(); ++i) {
        if (isDegenerateTriangle(positions, triangles[i])) continue;
        triangles[kept] = triangles[i];
        if (triangleMaterials) (*triangleMaterials)[kept] = (*triangleMaterials)[i];
        ++kept;
    }
    const uint64_t removed = triangles.size() - kept;
    triangles.resize(kept);
    if (triangleMaterials) triangleMaterials->resize(kept);
    return removed;
}

std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<glm::uvec3>& triangles) {
    std::vector<glm::vec3> normals(positions.size(), glm::vec3(0.0f));
    for (const glm::uvec3& t : triangles) {
        const glm::vec3 p0 = positions[t.x];
        // The cross product's length is twice the area, so summing it weights by area.
        const glm::vec3 weighted = glm::cross(positions[t.y] - p0, positions[t.z] - p0);
        normals[t.x] += weighted;
        normals[t.y] += weighted;
        normals[t.z] += weighted;
    }
    for (glm::vec3& n : normals) {
        const float length = glm::length(n);
        n = (length > 0.0f && std::isfinite(length)) ? n / length : glm::vec3(0.0f, 1.0f, 0.0f);
    }
    return normals;
}

void throwFileError(const std::filesystem::path& file, const std::string& what) {
    throw InputError(file.string() + ": " + what);
}

std::string readWholeFile(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) throwFileError(file, "no such file");
    if (std::filesystem::is_directory(file, ec)) throwFileError(file, "is a directory, not a scene file");
    std::ifstream in(file, std::ios::binary);
    if (!in) throwFileError(file, "cannot open for reading");
    std::string bytes;
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) throwFileError(file, "cannot determine the file size");
    bytes.resize(static_cast<size_t>(size));
    in.seekg(0, std::ios::beg);
    in.read(bytes.data(), size);
    if (!in) throwFileError(file, "read error");
    return bytes;
}

std::string lowerCaseExtension(const std::filesystem::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

std::string formatVec3(const glm::vec3& v) {
    std::ostringstream out;
    out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}

namespace {

// Checks that must precede dropping degenerates: a NaN vertex must be an error, not silently dropped, and
// the degeneracy test reads positions through the indices.
void checkPositionsAndIndices(const Scene& scene, const std::filesystem::path& file) {
    for (size_t i = 0; i < scene.positions.size(); ++i) {
        const glm::vec3& p = scene.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throwFileError(file, "vertex " + std::to_string(i) + " has a non-finite position " + formatVec3(p));
    }
    const size_t vertexCount = scene.positions.size();
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::uvec3& t = scene.triangles[i];
        for (int k = 0; k < 3; ++k) {
            if (t[k] >= vertexCount)
                throwFileError(file, "triangle " + std::to_string(i) + " refers to vertex " + std::to_string(t[k]) +
                                         " but there are only " + std::to_string(vertexCount) + " vertices");
        }
    }
}

} // namespace

void finishLoadedScene(Scene& scene, const std::filesystem::path& file) {
    scene.name = file.stem().string();
    checkPositionsAndIndices(scene, file);
    if (scene.triangleMaterials.size() != scene.triangles.size())
        scene.triangleMaterials.assign(scene.triangles.size(), 0u);
    scene.stats.degenerateTrianglesDropped +=
        removeDegenerateTriangles(scene.positions, scene.triangles, &scene.triangleMaterials);
    if (scene.triangles.empty()) throwFileError(file, "scene has no triangles");
    if (scene.materials.empty()) {
        Material grey;
        grey.name = "default";
        scene.materials.push_back(grey);
    }
    if (scene.normals.size() != scene.positions.size()) generateVertexNormals(scene);
    scene.stats.instancedTriangles = scene.triangles.size();
    if (scene.stats.meshCount == 0) {
        // Single-mesh formats: nothing is instanced.
        scene.stats.uniqueTriangles = scene.triangles.size();
        scene.stats.meshCount = 1;
        scene.stats.instanceCount = 1;
    }
    try {
        validateScene(scene);
    } catch (const InputError& e) {
        throwFileError(file, e.what());
    }
}

} // namespace chcrt::detail
