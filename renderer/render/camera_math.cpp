#include "renderer/render/camera_math.h"

#include <algorithm>
#include <cmath>

namespace chcrt {

CameraFrame makeCameraFrame(const Camera& camera, int width, int height) {
    CameraFrame frame;
    frame.eye = camera.eye;
    frame.forward = glm::normalize(camera.target - camera.eye);
    frame.right = glm::normalize(glm::cross(frame.forward, camera.up));
    frame.up = glm::cross(frame.right, frame.forward);
    frame.tanHalfFovY = std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    frame.aspect = float(width) / float(height);
    return frame;
}

PrimaryRayBasis primaryRayBasis(const CameraFrame& frame, int width, int height) {
    return {frame.eye, frame.forward, frame.right * frame.tanHalfFovY * frame.aspect, frame.up * frame.tanHalfFovY, width,
            height};
}

glm::mat4 viewFromWorld(const CameraFrame& f) {
    glm::mat4 m(1.0f);
    // Rows: right, up, -forward (OpenGL view space looks down -Z).
    for (int c = 0; c < 3; ++c) {
        m[c][0] = f.right[c];
        m[c][1] = f.up[c];
        m[c][2] = -f.forward[c];
    }
    m[3][0] = -glm::dot(f.right, f.eye);
    m[3][1] = -glm::dot(f.up, f.eye);
    m[3][2] = glm::dot(f.forward, f.eye);
    return m;
}

glm::mat4 clipFromView(const CameraFrame& f, float nearPlane) {
    glm::mat4 m(0.0f);
    m[0][0] = 1.0f / (f.tanHalfFovY * f.aspect);
    m[1][1] = 1.0f / f.tanHalfFovY;
    m[2][3] = -1.0f;     // w = -z_view
    m[3][2] = nearPlane; // z = near  => depth = near / -z_view, 1 at the near plane, 0 at infinity
    return m;
}

float nearPlaneFor(const Aabb& bounds) {
    return std::max(1e-3f, 1e-5f * bounds.diagonal());
}

} // namespace chcrt
