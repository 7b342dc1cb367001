#include "app/viewer/walk_controller.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>

namespace chcrt::app {

bool WalkInput::any() const {
    return forward || back || left || right || up || down || lookPixels != glm::vec2(0.0f) || scrollSteps != 0.0f;
}

WalkController::WalkController(const Camera& start, const Aabb& sceneBounds) : bounds_(sceneBounds) {
    setCamera(start);
    const float diagonal = bounds_.empty() ? 1.0f : std::max(bounds_.diagonal(), 1e-3f);
    speed_ = diagonal / 40.0f;
}

void WalkController::setCamera(const Camera& camera) {
    eye_ = camera.eye;
    const glm::vec3 toTarget = camera.target - camera.eye;
    focusDistance_ = std::max(glm::length(toTarget), 1e-4f);
    const glm::vec3 f = toTarget / focusDistance_;
    yaw_ = std::atan2(f.x, -f.z);
    const float maxPitch = glm::radians(kMaxPitchDegrees);
    pitch_ = std::clamp(std::asin(std::clamp(f.y, -1.0f, 1.0f)), -maxPitch, maxPitch);
    fovYDegrees_ = camera.fovYDegrees;
}

glm::vec3 WalkController::forward() const {
    return {std::sin(yaw_) * std::cos(pitch_), std::sin(pitch_), -std::cos(yaw_) * std::cos(pitch_)};
}

Camera WalkController::camera() const {
    Camera c;
    c.eye = eye_;
    c.target = eye_ + focusDistance_ * forward();
    c.up = glm::vec3(0.0f, 1.0f, 0.0f);
    c.fovYDegrees = fovYDegrees_;
    return c;
}

void WalkController::setSpeed(float unitsPerSecond) {
    speed_ = std::clamp(unitsPerSecond, 1e-4f, 1e7f);
}

bool WalkController::update(const WalkInput& input, double seconds) {
    if (input.scrollSteps != 0.0f) setSpeed(speed_ * std::pow(kSpeedStep, input.scrollSteps));
    bool moved = false;
    // Mouse look: x turns about world up, y tilts (screen y grows downwards).
    if (input.lookPixels != glm::vec2(0.0f)) {
        const float maxPitch = glm::radians(kMaxPitchDegrees);
        yaw_ = std::remainder(yaw_ + input.lookPixels.x * kRadiansPerPixel, glm::two_pi<float>());
        pitch_ = std::clamp(pitch_ - input.lookPixels.y * kRadiansPerPixel, -maxPitch, maxPitch);
        moved = true;
    }
    // Fly: forward follows the view direction (pitch included), strafing stays horizontal, Q/E along world up.
    const glm::vec3 f = forward();
    const glm::vec3 right = glm::normalize(glm::vec3(std::cos(yaw_), 0.0f, std::sin(yaw_)));
    glm::vec3 direction(0.0f);
    direction += f * (float(input.forward) - float(input.back));
    direction += right * (float(input.right) - float(input.left));
    direction += glm::vec3(0.0f, 1.0f, 0.0f) * (float(input.up) - float(input.down));
    if (glm::dot(direction, direction) > 0.0f && seconds > 0.0) {
        const float step = speed_ * (input.fast ? kFastFactor : 1.0f) * float(seconds);
        eye_ += glm::normalize(direction) * step;
        moved = true;
    }
    return moved;
}

void WalkController::frameScene() {
    if (bounds_.empty()) return;
    const float radius = std::max(0.5f * bounds_.diagonal(), 1e-3f);
    const float halfFov = 0.5f * glm::radians(std::clamp(fovYDegrees_, 1.0f, 179.0f));
    const float distance = 1.05f * radius / std::sin(halfFov);
    // Look down on the scene at least as steeply as defaultCamera (25°): from the horizon a flat scene (a city)
    // would be a thin line.
    pitch_ = std::min(pitch_, -glm::radians(kFramePitchDegrees));
    eye_ = bounds_.center() - distance * forward();
    focusDistance_ = distance;
}

} // namespace chcrt::app
