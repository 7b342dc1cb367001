// glTF 2.0 (.gltf, .glb) through tinygltf: the node hierarchy of one scene is walked with world = parent *
// local (glTF 2.0 §3.5.3), each referenced mesh is decoded and cleaned once, then every instance is flattened
// into world-space triangles. Only the base colour (factor and texture) of a material is kept.
#include "renderer/core/error.h"
#include "renderer/core/memory_budget.h"
#include "renderer/scene/gltf_accessors.h"
#include "renderer/scene/image_header.h"
#include "renderer/scene/mesh_utils.h"
#include "renderer/scene/scene_loader.h"

#include <tiny_gltf.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <utility>

namespace chcrt {

namespace {

using detail::throwFileError;

// One primitive of a mesh in the mesh's own space, decoded and cleaned once however often it is instanced.
struct LocalPrimitive {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals; // always filled (generated when the file has none)
    std::vector<glm::vec2> texcoords; // empty when the primitive has no TEXCOORD_0
    std::vector<glm::uvec3> triangles;
    int material = -1;
};

struct LocalMesh {
    std::vector<LocalPrimitive> primitives;
    uint64_t triangleCount = 0;
    uint64_t degenerateDropped = 0;
    uint64_t skippedPrimitives = 0; // points and lines: nothing to rasterise or trace
};

struct MeshInstance {
    int mesh = -1;
    glm::dmat4 worldFromMesh{1.0};
};

std::string oneLine(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    for (size_t pos = 0; (pos = text.find_first_of("\r\n", pos)) != std::string::npos;) text.replace(pos, 1, "; ");
    return text;
}

// Textures may have at most this many texels per side: the largest size OpenGL 4.5 guarantees
// (GL_MAX_TEXTURE_SIZE >= 16384).
constexpr uint64_t kMaxTextureSide = 16384;

// Why loadImageWithinLimits refused an image (empty: none refused).
struct ImageLimits {
    std::string refused;
};

// tinygltf's image loader (stb_image) behind a size check: an image whose header declares more than
// kMaxTextureSide texels on a side, or whose decoding (stb's output, tinygltf's copy of it and the RGBA8 texture)
// would not fit the memory budget, is refused before it is decoded: stb sizes its output from the header alone,
// so a few bytes could otherwise claim gigabytes.
bool loadImageWithinLimits(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int reqWidth,
                           int reqHeight, const unsigned char* bytes, int size, void* user) {
    ImageLimits& limits = *static_cast<ImageLimits*>(user);
    detail::ImageHeader header;
    if (size > 0 && detail::readImageHeader(bytes, size_t(size), header)) {
        const std::string name = "image " + std::to_string(index) + (image->name.empty() ? "" : " ('" + image->name + "')");
        const std::string texels = std::to_string(header.width) + " x " + std::to_string(header.height) + " texels";
        if (header.width > kMaxTextureSide || header.height > kMaxTextureSide) {
            limits.refused = name + " is " + texels + ", more than the " + std::to_string(kMaxTextureSide) +
                             " per side a texture may have (refused before decoding)";
            return false;
        }
        const uint64_t decodedTexel = header.sixteenBit ? 8 : 4;
        try {
            checkMemoryBudget(header.width * header.height * (2 * decodedTexel + 4), "decoding " + name + ", " + texels);
        } catch (const InputError& e) {
            limits.refused = e.what();
            return false;
        }
    }
    // No user data: tinygltf's loader then takes its default options (channels expanded to RGBA), as when it is
    // the parser's own loader.
    return tinygltf::LoadImageData(image, index, err, warn, reqWidth, reqHeight, bytes, size, nullptr);
}

// tinygltf's reads of the files a glTF names (buffers and images by URI), behind checks: a regular file only, sized
// within the memory budget before it is read. tinygltf's own reader sizes its buffer from the stream's end position,
// which for a directory is 2^63 - 1: an image URI "data%image/png;..." that decoded to "data", a directory, made it
// allocate that much (found by fuzzing; regression input gltf/regressions/crash_image_uri_names_a_directory.gltf).
// A refused image becomes tinygltf's "failed to load" warning, reported like a missing texture; a refused buffer
// fails the load.
bool readReferencedFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    const auto fail = [&](const std::string& why) {
        if (err != nullptr) *err += "'" + path + "': " + why + "\n";
        return false;
    };
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return fail("not a regular file");
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return fail(ec.message());
    try {
        checkMemoryBudget(uint64_t(size), "reading " + path);
    } catch (const InputError& e) {
        return fail(e.what());
    }
    std::ifstream in(path, std::ios::binary);
    out->resize(size_t(size));
    if (!in || !in.read(reinterpret_cast<char*>(out->data()), std::streamsize(size))) return fail("cannot be read");
    return true;
}

tinygltf::Model parseModel(const std::filesystem::path& file) {
    const std::string bytes = detail::readWholeFile(file);
    if (bytes.empty()) throwFileError(file, "file is empty");
    if (bytes.size() > std::numeric_limits<uint32_t>::max()) throwFileError(file, "file larger than 4 GiB");
    // The magic decides, not the extension, so a .gltf that is really binary still loads.
    const bool binary = detail::lowerCaseExtension(file) == ".glb" || bytes.compare(0, 4, "glTF") == 0;
    std::string baseDir = file.parent_path().string();
    if (baseDir.empty()) baseDir = ".";

    tinygltf::TinyGLTF parser;
    ImageLimits limits;
    parser.SetImageLoader(loadImageWithinLimits, &limits);
    parser.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &readReferencedFile,
                           &tinygltf::WriteWholeFile, nullptr});
    tinygltf::Model model;
    std::string error, warning;
    bool ok = false;
    try {
        ok = binary ? parser.LoadBinaryFromMemory(&model, &error, &warning,
                                                  reinterpret_cast<const unsigned char*>(bytes.data()),
                                                  static_cast<unsigned>(bytes.size()), baseDir)
                    : parser.LoadASCIIFromString(&model, &error, &warning, bytes.data(),
                                                 static_cast<unsigned>(bytes.size()), baseDir);
    } catch (const std::exception& e) {
        throwFileError(file, std::string("glTF parser failed: ") + e.what());
    }
    if (!ok && !limits.refused.empty()) throwFileError(file, limits.refused);
    if (!ok) throwFileError(file, "invalid glTF: " + oneLine(error.empty() ? "unknown error" : error));
    return model;
}

glm::dmat4 localTransform(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data()); // column-major, as glTF stores it
    glm::dmat4 transform(1.0);
    if (node.translation.size() == 3)
        transform = glm::translate(transform, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4) // glTF stores (x, y, z, w); glm::dquat takes (w, x, y, z)
        transform *= glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    if (node.scale.size() == 3) transform = glm::scale(transform, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return transform; // T * R * S (§3.5.3)
}

// Root nodes of the default scene, else scene 0, else every node that is nobody's child.
std::vector<int> rootNodes(const tinygltf::Model& model) {
    if (!model.scenes.empty()) {
        int sceneIndex = model.defaultScene;
        if (sceneIndex < 0 || static_cast<size_t>(sceneIndex) >= model.scenes.size()) sceneIndex = 0;
        return model.scenes[sceneIndex].nodes;
    }
    std::vector<bool> isChild(model.nodes.size(), false);
    for (const tinygltf::Node& node : model.nodes)
        for (int child : node.children)
            if (child >= 0 && static_cast<size_t>(child) < isChild.size()) isChild[child] = true;
    std::vector<int> roots;
    for (size_t i = 0; i < model.nodes.size(); ++i)
        if (!isChild[i]) roots.push_back(static_cast<int>(i));
    return roots;
}

NamedCamera cameraFromNode(const tinygltf::Model& model, const tinygltf::Node& node, const glm::dmat4& world) {
    const tinygltf::Camera& source = model.cameras[node.camera];
    NamedCamera named;
    named.name = !source.name.empty() ? source.name : !node.name.empty() ? node.name : "camera " + std::to_string(node.camera);
    // A glTF camera looks down its local -Z with +Y up (§3.10.1); the target is one unit ahead.
    const glm::dvec3 eye(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    const glm::dvec3 forward = glm::normalize(glm::dvec3(world * glm::dvec4(0.0, 0.0, -1.0, 0.0)));
    named.camera.eye = glm::vec3(eye);
    named.camera.target = glm::vec3(eye + forward);
    named.camera.up = glm::vec3(glm::normalize(glm::dvec3(world * glm::dvec4(0.0, 1.0, 0.0, 0.0))));
    named.camera.fovYDegrees = static_cast<float>(glm::degrees(source.perspective.yfov));
    return named;
}

// Walks the hierarchy from the roots, collecting mesh instances and perspective cameras. glTF's node hierarchy
// is a set of disjoint trees (§3.5.2: no cycles, at most one parent), so each node is reached once: a node
// reached again is refused, which also stops a few kilobytes of nodes that list one child many times over
// from multiplying into 4^23 instances.
std::vector<MeshInstance> collectInstances(const tinygltf::Model& model, Scene& scene) {
    std::vector<MeshInstance> instances;
    struct Pending {
        int node;
        glm::dmat4 parentWorld;
    };
    std::vector<Pending> stack;
    std::vector<bool> reached(model.nodes.size(), false);
    for (int root : rootNodes(model)) stack.push_back({root, glm::dmat4(1.0)});
    while (!stack.empty()) {
        const Pending item = stack.back();
        stack.pop_back();
        if (item.node < 0 || static_cast<size_t>(item.node) >= model.nodes.size())
            throw InputError("reference to missing node " + std::to_string(item.node));
        if (reached[item.node]) {
            throw InputError("node " + std::to_string(item.node) +
                             " is reached twice: the node hierarchy has a cycle or a node with two parents (glTF 2.0 "
                             "allows neither, §3.5.2)");
        }
        reached[item.node] = true;
        const tinygltf::Node& node = model.nodes[item.node];
        const glm::dmat4 world = item.parentWorld * localTransform(node);
        if (node.mesh >= 0) {
            if (static_cast<size_t>(node.mesh) >= model.meshes.size())
                throw InputError("node " + std::to_string(item.node) + " refers to missing mesh " + std::to_string(node.mesh));
            instances.push_back({node.mesh, world});
        }
        if (node.camera >= 0 && static_cast<size_t>(node.camera) < model.cameras.size() &&
            model.cameras[node.camera].type == "perspective")
            scene.cameras.push_back(cameraFromNode(model, node, world));
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back({*it, world});
    }
    return instances;
}

// Expands a primitive's index list into triangles by its mode (§3.7.2.1); false for points and lines.
bool assembleTriangles(int mode, const std::vector<uint32_t>& indices, std::vector<glm::uvec3>& triangles) {
    if (mode == -1 || mode == TINYGLTF_MODE_TRIANGLES) {
        for (size_t i = 0; i + 2 < indices.size(); i += 3) triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        // Every other strip triangle swaps its first two vertices to keep a consistent winding.
        for (size_t i = 0; i + 2 < indices.size(); ++i)
            triangles.push_back(i % 2 == 0 ? glm::uvec3(indices[i], indices[i + 1], indices[i + 2])
                                           : glm::uvec3(indices[i + 1], indices[i], indices[i + 2]));
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (size_t i = 1; i + 1 < indices.size(); ++i) triangles.emplace_back(indices[0], indices[i], indices[i + 1]);
    } else {
        return false;
    }
    return true;
}

template <typename Vec> std::vector<Vec> toVectors(const std::vector<float>& flat) {
    std::vector<Vec> out(flat.size() / Vec::length());
    if (!out.empty()) std::memcpy(out.data(), flat.data(), out.size() * sizeof(Vec));
    return out;
}

LocalPrimitive decodePrimitive(const tinygltf::Model& model, const tinygltf::Primitive& source, const std::string& where) {
    LocalPrimitive primitive;
    const auto attribute = [&](const char* name) {
        const auto it = source.attributes.find(name);
        return it == source.attributes.end() ? -1 : it->second;
    };
    const int positionAccessor = attribute("POSITION");
    if (positionAccessor < 0) throw InputError(where + " has no POSITION attribute");
    primitive.positions = toVectors<glm::vec3>(detail::readFloatAccessor(model, positionAccessor, 3, "POSITION"));
    for (size_t i = 0; i < primitive.positions.size(); ++i) {
        const glm::vec3& p = primitive.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError(where + ": vertex " + std::to_string(i) + " has a non-finite position " + detail::formatVec3(p));
    }
    const size_t vertexCount = primitive.positions.size();
    if (const int normals = attribute("NORMAL"); normals >= 0)
        primitive.normals = toVectors<glm::vec3>(detail::readFloatAccessor(model, normals, 3, "NORMAL"));
    if (const int texcoords = attribute("TEXCOORD_0"); texcoords >= 0)
        primitive.texcoords = toVectors<glm::vec2>(detail::readFloatAccessor(model, texcoords, 2, "TEXCOORD_0"));
    if ((!primitive.normals.empty() && primitive.normals.size() != vertexCount) ||
        (!primitive.texcoords.empty() && primitive.texcoords.size() != vertexCount))
        throw InputError(where + ": attribute counts differ from the POSITION count " + std::to_string(vertexCount));

    std::vector<uint32_t> indices;
    if (source.indices >= 0) {
        indices = detail::readIndexAccessor(model, source.indices);
        for (size_t i = 0; i < indices.size(); ++i)
            if (indices[i] >= vertexCount)
                throw InputError(where + ": index " + std::to_string(i) + " is " + std::to_string(indices[i]) +
                                 " but there are only " + std::to_string(vertexCount) + " vertices");
    } else {
        indices.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i) indices[i] = static_cast<uint32_t>(i);
    }
    assembleTriangles(source.mode, indices, primitive.triangles);
    if (source.material >= 0 && static_cast<size_t>(source.material) >= model.materials.size())
        throw InputError(where + " refers to missing material " + std::to_string(source.material));
    primitive.material = source.material;
    return primitive;
}

LocalMesh decodeMesh(const tinygltf::Model& model, int meshIndex) {
    const tinygltf::Mesh& source = model.meshes[meshIndex];
    LocalMesh mesh;
    for (size_t p = 0; p < source.primitives.size(); ++p) {
        const tinygltf::Primitive& sourcePrimitive = source.primitives[p];
        const int mode = sourcePrimitive.mode;
        if (mode != -1 && mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            mode != TINYGLTF_MODE_TRIANGLE_FAN) {
            ++mesh.skippedPrimitives;
            continue;
        }
        const std::string where = "mesh " + std::to_string(meshIndex) +
                                  (source.name.empty() ? "" : " ('" + source.name + "')") + " primitive " +
                                  std::to_string(p);
        LocalPrimitive primitive = decodePrimitive(model, sourcePrimitive, where);
        mesh.degenerateDropped += detail::removeDegenerateTriangles(primitive.positions, primitive.triangles, nullptr);
        if (primitive.normals.empty()) primitive.normals = detail::computeVertexNormals(primitive.positions, primitive.triangles);
        mesh.triangleCount += primitive.triangles.size();
        mesh.primitives.push_back(std::move(primitive));
    }
    return mesh;
}

// The cofactor matrix transforms normals like the inverse transpose (it is det * M^-T) but stays finite
// for singular M; its sign is fixed below so mirrored normals still follow the flipped winding.
glm::mat3 cofactor(const glm::mat3& m) {
    return glm::mat3(glm::cross(m[1], m[2]), glm::cross(m[2], m[0]), glm::cross(m[0], m[1]));
}

// Appends one instance of a mesh in world space. A mirroring transform (negative determinant) turns
// counter-clockwise front faces clockwise, so the winding is flipped to keep them front-facing.
void appendInstance(const LocalMesh& mesh, const glm::dmat4& worldFromMeshD, uint32_t defaultMaterial, Scene& scene) {
    const glm::mat4 worldFromMesh(worldFromMeshD);
    const glm::mat3 linear(worldFromMesh);
    const bool mirrored = glm::determinant(glm::dmat3(worldFromMeshD)) < 0.0;
    const glm::mat3 normalMatrix = cofactor(linear) * (mirrored ? -1.0f : 1.0f);
    for (const LocalPrimitive& primitive : mesh.primitives) {
        const uint32_t base = static_cast<uint32_t>(scene.positions.size());
        for (size_t i = 0; i < primitive.positions.size(); ++i) {
            scene.positions.push_back(glm::vec3(worldFromMesh * glm::vec4(primitive.positions[i], 1.0f)));
            const glm::vec3 n = normalMatrix * primitive.normals[i];
            const float length = glm::length(n);
            scene.normals.push_back(length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f, 1.0f, 0.0f));
            scene.texcoords.push_back(primitive.texcoords.empty() ? glm::vec2(0.0f) : primitive.texcoords[i]);
        }
        const uint32_t material = primitive.material >= 0 ? static_cast<uint32_t>(primitive.material) : defaultMaterial;
        for (const glm::uvec3& t : primitive.triangles) {
            scene.triangles.push_back(mirrored ? glm::uvec3(t.x, t.z, t.y) + base : t + base);
            scene.triangleMaterials.push_back(material);
        }
    }
}

// Expands a decoded tinygltf image (1-4 channels, 8 or 16 bits) to RGBA8; 16-bit keeps the high byte.
bool convertImage(const tinygltf::Image& image, Texture& texture) {
    const int channels = image.component;
    const int bytesPerChannel = image.bits == 16 ? 2 : 1;
    if (image.width <= 0 || image.height <= 0 || channels < 1 || channels > 4 || (image.bits != 8 && image.bits != 16))
        return false;
    const size_t pixelCount = size_t(image.width) * size_t(image.height);
    if (image.image.size() < pixelCount * channels * bytesPerChannel) return false;
    texture.width = static_cast<uint32_t>(image.width);
    texture.height = static_cast<uint32_t>(image.height);
    texture.rgba8.resize(pixelCount * 4);
    const auto channel = [&](size_t pixel, int c) -> uint8_t {
        const size_t offset = (pixel * channels + c) * bytesPerChannel;
        if (bytesPerChannel == 1) return image.image[offset];
        uint16_t value;
        std::memcpy(&value, &image.image[offset], 2);
        return static_cast<uint8_t>(value >> 8);
    };
    for (size_t i = 0; i < pixelCount; ++i) {
        uint8_t* out = &texture.rgba8[i * 4];
        if (channels <= 2) { // grey (+ alpha)
            out[0] = out[1] = out[2] = channel(i, 0);
            out[3] = channels == 2 ? channel(i, 1) : 255;
        } else {
            for (int c = 0; c < 3; ++c) out[c] = channel(i, c);
            out[3] = channels == 4 ? channel(i, 3) : 255;
        }
    }
    return true;
}

// Materials keep glTF's indices; a base-colour texture becomes a Scene texture (one per image, shared).
void convertMaterials(const tinygltf::Model& model, Scene& scene) {
    std::map<int, int32_t> textureOfImage;
    for (const tinygltf::Material& source : model.materials) {
        Material material;
        material.name = source.name;
        const std::vector<double>& factor = source.pbrMetallicRoughness.baseColorFactor;
        if (factor.size() == 4) material.baseColorFactor = glm::vec4(factor[0], factor[1], factor[2], factor[3]);
        const int textureIndex = source.pbrMetallicRoughness.baseColorTexture.index;
        if (textureIndex >= 0 && static_cast<size_t>(textureIndex) < model.textures.size()) {
            const int imageIndex = model.textures[textureIndex].source;
            if (imageIndex >= 0 && static_cast<size_t>(imageIndex) < model.images.size()) {
                auto [it, inserted] = textureOfImage.try_emplace(imageIndex, -1);
                if (inserted) {
                    const tinygltf::Image& image = model.images[imageIndex];
                    Texture texture;
                    texture.name = !image.name.empty() ? image.name : image.uri;
                    if (convertImage(image, texture)) {
                        it->second = static_cast<int32_t>(scene.textures.size());
                        scene.textures.push_back(std::move(texture));
                    } else {
                        scene.warnings.push_back("base-colour texture '" + texture.name + "' (image " +
                                                 std::to_string(imageIndex) + ") is missing or cannot be decoded; "
                                                 "its materials use their base colour factor");
                    }
                }
                material.baseColorTexture = it->second; // -1 when the image could not be decoded
            }
        }
        scene.materials.push_back(std::move(material));
    }
}

void buildScene(const tinygltf::Model& model, Scene& scene, Progress& progress, const std::string& label) {
    convertMaterials(model, scene);
    const std::vector<MeshInstance> instances = collectInstances(model, scene);

    std::map<int, LocalMesh> meshes; // decoded once per distinct mesh
    uint64_t vertexTotal = 0, triangleTotal = 0;
    for (const MeshInstance& instance : instances) {
        auto [it, inserted] = meshes.try_emplace(instance.mesh);
        if (inserted) it->second = decodeMesh(model, instance.mesh);
        for (const LocalPrimitive& p : it->second.primitives) vertexTotal += p.positions.size();
        triangleTotal += it->second.triangleCount;
    }
    // Instancing multiplies: a small file can describe more geometry than memory holds, or than 32-bit indices
    // can address; both are refused before the flattened arrays are sized.
    if (vertexTotal > std::numeric_limits<uint32_t>::max()) {
        throw InputError("the scene has " + std::to_string(vertexTotal) +
                         " vertices after instancing, more than 32-bit indices can address");
    }
    checkMemoryBudget(vertexTotal * (2 * sizeof(glm::vec3) + sizeof(glm::vec2)) +
                          triangleTotal * (sizeof(glm::uvec3) + sizeof(uint32_t)),
                      "the scene's " + std::to_string(triangleTotal) + " triangles after instancing");
    bool anyTexcoords = false;
    for (const auto& [index, mesh] : meshes) {
        scene.stats.uniqueTriangles += mesh.triangleCount;
        for (const LocalPrimitive& p : mesh.primitives) anyTexcoords |= !p.texcoords.empty();
    }
    // Primitives without a material use glTF's default material (§3.9.6); here one default grey.
    const uint32_t defaultMaterial = static_cast<uint32_t>(scene.materials.size());
    scene.materials.push_back(Material{glm::vec4(0.8f, 0.8f, 0.8f, 1.0f), -1, "default"});

    scene.positions.reserve(vertexTotal);
    scene.normals.reserve(vertexTotal);
    scene.texcoords.reserve(vertexTotal);
    scene.triangles.reserve(triangleTotal);
    scene.triangleMaterials.reserve(triangleTotal);
    progress.begin("Flattening " + label, instances.size());
    for (size_t i = 0; i < instances.size(); ++i) {
        const LocalMesh& mesh = meshes.at(instances[i].mesh);
        appendInstance(mesh, instances[i].worldFromMesh, defaultMaterial, scene);
        scene.stats.degenerateTrianglesDropped += mesh.degenerateDropped;
        if (i % 64 == 0) progress.update(i);
    }
    progress.end();
    if (!anyTexcoords) scene.texcoords.clear();
    scene.stats.meshCount = static_cast<uint32_t>(meshes.size());
    scene.stats.instanceCount = static_cast<uint32_t>(instances.size());
    // Drop the default material again when no primitive used it (keeps material lists as the file has them).
    bool defaultUsed = false;
    for (uint32_t m : scene.triangleMaterials) defaultUsed |= m == defaultMaterial;
    if (!defaultUsed && defaultMaterial > 0) scene.materials.pop_back();
}

} // namespace

Scene loadGltf(const std::filesystem::path& file, Progress& progress) {
    const std::string label = file.filename().string();
    progress.begin("Parsing " + label, 0);
    tinygltf::Model model;
    try {
        model = parseModel(file);
    } catch (...) {
        progress.end();
        throw;
    }
    progress.end();
    Scene scene;
    try {
        buildScene(model, scene, progress, label);
    } catch (const InputError& e) {
        throwFileError(file, e.what());
    }
    for (std::string& w : scene.warnings) w = file.string() + ": " + w;
    detail::finishLoadedScene(scene, file);
    return scene;
}

} // namespace chcrt
