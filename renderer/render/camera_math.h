#pragma once
// Camera matrices. Rasterisation uses an infinite reversed-Z projection with a float depth buffer
// (glClipControl ZERO_TO_ONE, depth cleared to 0, GL_GREATER): depth precision stays nearly uniform, which large
// scenes seen from street level need.
#include "renderer/scene/scene.h"

#include <glm/glm.hpp>

namespace chcrt {

struct CameraFrame {
    glm::vec3 eye;
    glm::vec3 forward; // unit
    glm::vec3 right;   // unit
    glm::vec3 up;      // unit, orthogonal to forward and right
    float tanHalfFovY;
    float aspect; // width / height
};

CameraFrame makeCameraFrame(const Camera& camera, int width, int height);

// What the renderer's primary ray generation reads (shaders/render/raygen.frag.glsl, CHCRT_RAY_PRIMARY): the ray of
// pixel p of a width × height ray set starts at `eye` with direction normalize(forward + ndc.x·right + ndc.y·up),
// ndc = (p + 0.5) / (width, height) · 2 − 1, over [0, CHCRT_NO_HIT_T]. A tracer given it may bound the rays from it
// without reading them (culling/ray_bounds_grid.h, setCameraCells).
struct PrimaryRayBasis {
    glm::vec3 eye{0.0f}, forward{0.0f, 0.0f, -1.0f};
    glm::vec3 right{0.0f}, up{0.0f}; // scaled by the tangents of the half fields of view
    int width = 0, height = 0;
};
PrimaryRayBasis primaryRayBasis(const CameraFrame& frame, int width, int height);
glm::mat4 viewFromWorld(const CameraFrame& frame);
// Infinite reversed-Z perspective: depth = nearPlane / viewDistance.
glm::mat4 clipFromView(const CameraFrame& frame, float nearPlane);
// Near plane used for a scene: small against the scene and the camera's distance to it.
float nearPlaneFor(const Aabb& sceneBounds);

} // namespace chcrt
