#pragma once
// Internal helpers shared by scene.cpp and the loaders, on raw vertex/triangle arrays so a loader can clean one
// glTF mesh before instancing it. Not part of the public interface (scene.h, scene_loader.h).
#include "renderer/scene/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace chcrt::detail {

// A triangle is degenerate when two of its indices repeat or its edge cross product is exactly zero (zero
// area in float). Triangles with non-finite vertices are NOT degenerate here: validation must see them.
bool isDegenerateTriangle(const std::vector<glm::vec3>& positions, const glm::uvec3& triangle);

// Removes degenerate triangles in place (and the matching entries of `triangleMaterials` when it is not
// null); returns how many were removed. Indices must be in range.
uint64_t removeDegenerateTriangles(const std::vector<glm::vec3>& positions, std::vector<glm::uvec3>& triangles,
                                   std::vector<uint32_t>* triangleMaterials);

// Area-weighted smooth vertex normals: the sum of each adjacent triangle's unnormalised cross product (which
// is 2 * area * unit normal), normalised; (0, 1, 0) where that sum is zero. Indices must be in range.
std::vector<glm::vec3> computeVertexNormals(const std::vector<glm::vec3>& positions,
                                            const std::vector<glm::uvec3>& triangles);

// "<file>: <what>" as an InputError, the one error form every loader uses.
[[noreturn]] void throwFileError(const std::filesystem::path& file, const std::string& what);

// Reads a whole file; throws "<file>: no such file" (or a read error) as InputError.
std::string readWholeFile(const std::filesystem::path& file);

// Lower-case extension with its dot (".glb"), for dispatch.
std::string lowerCaseExtension(const std::filesystem::path& file);

// The common tail of every loader: checks finite positions and index ranges (naming the file), drops
// degenerate triangles, adds a default grey material when there is none, generates normals when
// scene.normals does not match scene.positions, sets name and triangle stats, then validateScene().
void finishLoadedScene(Scene& scene, const std::filesystem::path& file);

// Formats a vector for error messages: "(1, nan, 3)".
std::string formatVec3(const glm::vec3& v);

} // namespace chcrt::detail
