#pragma once
// Scene files: glTF 2.0 (.gltf, .glb) through tinygltf, PLY (ASCII and binary, as the Stanford models) and
// Wavefront OBJ. All produce a validated Scene (scene.h): flattened world-space triangles, materials, normals
// generated when missing, degenerate triangles dropped and counted. Errors throw InputError naming the file.
#include "renderer/core/progress.h"
#include "renderer/scene/scene.h"

#include <filesystem>

namespace chcrt {

// Dispatches on the extension (case-insensitive). Throws InputError for a missing file, an unknown
// extension, a malformed or truncated file, zero triangles, or non-finite vertices.
Scene loadSceneFile(const std::filesystem::path& file, Progress& progress = nullProgress());

Scene loadGltf(const std::filesystem::path& file, Progress& progress = nullProgress());
Scene loadPly(const std::filesystem::path& file, Progress& progress = nullProgress());
Scene loadObj(const std::filesystem::path& file, Progress& progress = nullProgress());

} // namespace chcrt
