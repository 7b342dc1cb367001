#include "renderer/scene/scene_loader.h"

#include "renderer/scene/mesh_utils.h"

namespace chcrt {

Scene loadSceneFile(const std::filesystem::path& file, Progress& progress) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) detail::throwFileError(file, "no such file");
    const std::string ext = detail::lowerCaseExtension(file);
    if (ext == ".gltf" || ext == ".glb") return loadGltf(file, progress);
    if (ext == ".ply") return loadPly(file, progress);
    if (ext == ".obj") return loadObj(file, progress);
    detail::throwFileError(file, "unknown scene file extension '" + file.extension().string() +
                                     "' (expected .gltf, .glb, .ply or .obj)");
}

} // namespace chcrt
