#include "renderer/scene/scene_loader.h"

#include "renderer/scene/mesh_utils.h"

#include <fstream>
#include <string>

namespace chcrt {

namespace {

// The format a file's first bytes announce ("ply", "glTF"), or "" for text without a magic (OBJ, .gltf JSON).
std::string formatByMagic(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    char magic[4] = {};
    in.read(magic, sizeof magic);
    const std::string head(magic, size_t(in.gcount()));
    if (head.rfind("ply", 0) == 0) return ".ply";
    if (head == "glTF") return ".glb";
    return "";
}

} // namespace

Scene loadSceneFile(const std::filesystem::path& file, Progress& progress) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) detail::throwFileError(file, "no such file");
    const std::string ext = detail::lowerCaseExtension(file);
    // A PLY or GLB under another name would otherwise parse as garbage ("scene has no triangles").
    const std::string announced = formatByMagic(file);
    if (ext == ".obj" && !announced.empty()) {
        detail::throwFileError(file, "is a " + announced.substr(1) + " file by its content, not OBJ: rename it " + announced);
    }
    if (ext == ".ply" && announced == ".glb") detail::throwFileError(file, "is a glb file by its content, not PLY: rename it .glb");
    if (ext == ".gltf" || ext == ".glb") return loadGltf(file, progress);
    if (ext == ".ply") return loadPly(file, progress);
    if (ext == ".obj") return loadObj(file, progress);
    detail::throwFileError(file, "unknown scene file extension '" + file.extension().string() +
                                     "' (expected .gltf, .glb, .ply or .obj)");
}

} // namespace chcrt
