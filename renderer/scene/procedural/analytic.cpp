// The analytic test scenes (exact geometry documented in procedural.h), their single-camera paths and
// their lights.
#include "renderer/scene/procedural/procedural_internal.h"

namespace chcrt::procedural {

void generateAnalytic(const ProceduralSpec& spec, MeshBuilder& builder) {
    switch (spec.kind) {
    case ProceduralKind::PlaneAndBox: {
        const uint32_t ground = builder.addMaterial("ground", {0.8f, 0.8f, 0.8f});
        const uint32_t box = builder.addMaterial("box", {0.7f, 0.3f, 0.2f});
        builder.addQuad({-10, 0, -10}, {-10, 0, 10}, {10, 0, 10}, {10, 0, -10}, ground);
        builder.addBox({-1, 0, -1}, {1, 2, 1}, box, kAllFaces);
        break;
    }
    case ProceduralKind::ClosedBox: {
        // Faces point inwards: quads wound counter-clockwise seen from inside.
        const uint32_t floor = builder.addMaterial("floor", {0.8f, 0.8f, 0.8f});
        const uint32_t ceiling = builder.addMaterial("ceiling", {0.9f, 0.9f, 0.9f});
        const uint32_t wall = builder.addMaterial("wall", {0.6f, 0.6f, 0.6f});
        const uint32_t red = builder.addMaterial("wall-red", {0.7f, 0.1f, 0.1f});
        const uint32_t green = builder.addMaterial("wall-green", {0.1f, 0.6f, 0.1f});
        const float s = 5.0f, h = 10.0f;
        builder.addQuad({-s, 0, -s}, {-s, 0, s}, {s, 0, s}, {s, 0, -s}, floor);      // normal +Y
        builder.addQuad({-s, h, -s}, {s, h, -s}, {s, h, s}, {-s, h, s}, ceiling);    // normal -Y
        builder.addQuad({-s, 0, -s}, {s, 0, -s}, {s, h, -s}, {-s, h, -s}, wall);     // z = -5, normal +Z
        builder.addQuad({-s, 0, s}, {-s, h, s}, {s, h, s}, {s, 0, s}, wall);         // z = +5, normal -Z
        builder.addQuad({-s, 0, -s}, {-s, h, -s}, {-s, h, s}, {-s, 0, s}, red);      // x = -5, normal +X
        builder.addQuad({s, 0, -s}, {s, 0, s}, {s, h, s}, {s, h, -s}, green);        // x = +5, normal -X
        break;
    }
    default: { // OneTriangle
        const uint32_t white = builder.addMaterial("white", {0.8f, 0.8f, 0.8f});
        Scene& scene = builder.scene();
        scene.positions = {{-1, 0, -1}, {1, 0, -1}, {0, 0, 1}};
        scene.normals.assign(3, glm::vec3(0, 1, 0));
        scene.triangles = {{0, 2, 1}}; // counter-clockwise seen from +Y, agreeing with the normal
        scene.triangleMaterials = {white};
        break;
    }
    }
}

CameraPath analyticPath(const ProceduralSpec& spec) {
    Camera camera;
    switch (spec.kind) {
    case ProceduralKind::PlaneAndBox: camera.eye = {6, 5, 8}, camera.target = {0, 1, 0}; break;
    case ProceduralKind::ClosedBox: camera.eye = {0, 5, 4.5f}, camera.target = {0, 4, -5}; break;
    default: camera.eye = {0, 3, 3}, camera.target = {0, 0, 0}; break;
    }
    CameraPath path;
    path.name = toString(spec);
    path.fps = 30.0;
    path.fovYDegrees = camera.fovYDegrees;
    CameraKeyframe key;
    key.eye = camera.eye;
    key.target = camera.target;
    key.up = camera.up;
    path.keyframes.push_back(key);
    return path;
}

AreaLight analyticLight(const ProceduralSpec& spec) {
    // 2 x 2 m at y = 10 above the origin; inside the closed box it hangs just below the ceiling (y = 9.9)
    // so that it is not coplanar with it.
    const float height = spec.kind == ProceduralKind::ClosedBox ? 9.9f : 10.0f;
    return downwardLight({0.0f, height, 0.0f}, 2.0f, height);
}

} // namespace chcrt::procedural
