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
glm::mat4 viewFromWorld(const CameraFrame& frame);
// Infinite reversed-Z perspective: depth = nearPlane / viewDistance.
glm::mat4 clipFromView(const CameraFrame& frame, float nearPlane);
// Near plane used for a scene: small against the scene and the camera's distance to it.
float nearPlaneFor(const Aabb& sceneBounds);

} // namespace chcrt
