#pragma once
// Appends flat-shaded primitives (quads, boxes, cylinders) to a Scene. Every face gets its own vertices
// carrying the face normal, so normals are flat and never shared across faces of different orientation.
// Triangles wind counter-clockwise seen from the side their normal points to.
//
// The generators budget triangles exactly, so each primitive's cost is available up front
// (boxCost, cylinderCost) and matches what the add* call emits.
//
// What it is not: a general mesh library. No welding, no texture coordinates, no instancing.
#include "renderer/core/progress.h"
#include "renderer/scene/scene.h"

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

namespace chcrt::procedural {

// Face selection for boxes: one bit per outward normal direction.
enum BoxFace : uint32_t {
    kPosX = 1u << 0,
    kNegX = 1u << 1,
    kPosY = 1u << 2,
    kNegY = 1u << 3,
    kPosZ = 1u << 4,
    kNegZ = 1u << 5,
    kAllFaces = 63u,
    kNoBottom = kAllFaces & ~uint32_t(kNegY),  // resting on the ground: the bottom is never seen
    kSides = kPosX | kNegX | kPosZ | kNegZ,
};

class MeshBuilder {
public:
    // `progress`: updated with the triangle count as primitives are added (the caller begins and ends its step).
    explicit MeshBuilder(Scene& scene, Progress& progress = nullProgress()) : scene_(scene), progress_(progress) {}

    // Reserves the output arrays (generators know their counts; vertices <= 2 * triangles for boxes/quads).
    void reserve(uint64_t triangles, uint64_t vertices);
    uint64_t triangleCount() const { return scene_.triangles.size(); }
    Scene& scene() { return scene_; } // for hand-made geometry (analytic scenes)

    uint32_t addMaterial(const std::string& name, const glm::vec3& linearColor);

    // Quad p0 p1 p2 p3, counter-clockwise seen from the front; normal = normalize(cross(p1 - p0, p3 - p0)).
    void addQuad(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3,
                 uint32_t material);

    // Axis-aligned box [lower, upper] with outward normals; `faces` selects which faces to emit.
    void addBox(const glm::vec3& lower, const glm::vec3& upper, uint32_t material, uint32_t faces = kAllFaces);

    // Box centred at `center` with half-axis vectors (mutually orthogonal, right-handed), all 6 faces.
    void addOrientedBox(const glm::vec3& center, const glm::vec3& halfX, const glm::vec3& halfY,
                        const glm::vec3& halfZ, uint32_t material);

    // Cylinder (prism with `segments` flat sides) from `a` to `b`; caps are triangle fans.
    void addCylinder(const glm::vec3& a, const glm::vec3& b, float radius, uint32_t segments, uint32_t material,
                     bool caps);

    static constexpr uint64_t boxCost(uint32_t faces = kAllFaces) {
        return 2u * uint64_t(std::popcount(faces & kAllFaces));
    }
    static constexpr uint64_t cylinderCost(uint32_t segments, bool caps) {
        return 2u * uint64_t(segments) + (caps ? 2u * uint64_t(segments - 2) : 0u);
    }

private:
    const std::vector<glm::vec2>& circle(uint32_t segments);
    void reportProgress();

    Scene& scene_;
    Progress& progress_;
    uint64_t nextReport_ = 0; // triangle count at which progress_ is updated next
    std::vector<std::vector<glm::vec2>> circles_; // unit circle tables by segment count
};

} // namespace chcrt::procedural
