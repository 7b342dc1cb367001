#pragma once
// A scene as the renderer sees it: one flattened, world-space, indexed triangle soup with per-vertex normals
// and texture coordinates, per-triangle materials, textures and optional cameras. Instanced meshes are
// flattened (every instance's triangles are stored, and counted, in `triangles`); SceneStats keeps the
// unique/instanced split so reports stay honest about that cost.
//
// What it is not: a scene graph. Loaders (glTF, PLY, OBJ) and the procedural generators produce this form.
#include "renderer/core/aabb.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace chcrt {

struct Material {
    glm::vec4 baseColorFactor{0.8f, 0.8f, 0.8f, 1.0f}; // linear RGB(A), multiplied with the texture
    int32_t baseColorTexture = -1;                      // index into Scene::textures, -1 = none
    std::string name;
};

// 8-bit sRGB-encoded RGBA image, rows top to bottom (as decoded from PNG/JPEG).
struct Texture {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<uint8_t> rgba8; // width * height * 4
    std::string name;
};

// A camera: eye, target, up and vertical field of view in degrees (the form camera paths use too).
struct Camera {
    glm::vec3 eye{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovYDegrees = 60.0f;
};

struct NamedCamera {
    std::string name;
    Camera camera;
};

// A one-sided rectangular area light: points corner + a*edgeU + b*edgeV for a, b in [0, 1], emitting
// `radiance` towards normal() = normalize(cross(edgeU, edgeV)).
struct AreaLight {
    glm::vec3 corner{0.0f};
    glm::vec3 edgeU{1.0f, 0.0f, 0.0f};
    glm::vec3 edgeV{0.0f, 0.0f, 1.0f}; // with these defaults the light faces down (-Y)
    glm::vec3 radiance{10.0f};         // linear RGB
    glm::vec3 normal() const { return glm::normalize(glm::cross(edgeU, edgeV)); }
    float area() const { return glm::length(glm::cross(edgeU, edgeV)); }
    Aabb bounds() const {
        Aabb box;
        for (const glm::vec3& p : {corner, corner + edgeU, corner + edgeV, corner + edgeU + edgeV}) box.grow(p);
        return box;
    }
};

struct SceneStats {
    uint64_t uniqueTriangles = 0;    // triangles in distinct meshes (before instancing)
    uint64_t instancedTriangles = 0; // triangles after flattening instances (= triangles.size())
    uint32_t meshCount = 0;          // distinct meshes
    uint32_t instanceCount = 0;      // mesh instances (nodes referencing meshes)
    uint64_t degenerateTrianglesDropped = 0; // zero-area or repeated-index triangles removed by loaders
};

struct Scene {
    std::string name; // file stem or generator name, for reports

    // Per vertex, world space. normals has the same size as positions (generated when the source has none);
    // texcoords is either empty or the same size as positions.
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> texcoords;

    // Per triangle: vertex indices and material index (into materials, which is never empty for a valid scene).
    std::vector<glm::uvec3> triangles;
    std::vector<uint32_t> triangleMaterials;

    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<NamedCamera> cameras; // from glTF; empty otherwise

    SceneStats stats;
    // What a loader could not use but loaded without (a missing texture file, faces of fewer than three
    // vertices): one line each, printed by the commands as warnings and refused by --strict.
    std::vector<std::string> warnings;

    // Scene units per metre and up axis are normalised by loaders to metres and +Y up.
    size_t triangleCount() const { return triangles.size(); }
    Aabb bounds() const;
};

// Throws InputError unless the scene is renderable: at least one triangle, all indices in range, all
// positions finite, array sizes consistent, material indices in range.
void validateScene(const Scene& scene);

// Computes smooth per-vertex normals (area-weighted) into scene.normals. Used when a source has none.
void generateVertexNormals(Scene& scene);

// Removes zero-area and repeated-index triangles, counting them in stats.degenerateTrianglesDropped.
void dropDegenerateTriangles(Scene& scene);

// A default camera that frames the whole scene: looking at the bounds' centre from the front-above, at a
// distance that fits the bounding sphere into the vertical field of view. A large, open scene (100,000 triangles or
// more whose middle 90 % lie in a flat box: a town, a castle) is seen from inside its bounds instead: from the front
// edge of that dense part, above it, looking at its centre (scene.cpp says how). Files that store a camera use it
// (app/session.cpp), not this.
Camera defaultCamera(const Scene& scene, float fovYDegrees = 60.0f);

// A default area light for any scene: a square facing down, above the bounds, offset sideways so shadows
// are visible, with a side of ~1/4 of the scene's horizontal extent.
AreaLight defaultAreaLight(const Scene& scene);

} // namespace chcrt
