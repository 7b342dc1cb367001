#pragma once
// Game-style walkthrough camera for the viewer: WASD/QE fly, mouse look, speed on the scroll wheel, shift for
// fast, R reset, F frame the scene. Pure logic on a yaw/pitch camera with world up = +Y (loaders normalise
// scenes to +Y up): no window or GL here, so tests drive it directly and scripted sessions are deterministic
// (they step it with a fixed time step).
#include "renderer/core/aabb.h"
#include "renderer/scene/scene.h"

#include <glm/glm.hpp>

namespace chcrt::app {

// What the user holds or moved during one frame.
struct WalkInput {
    bool forward = false, back = false, left = false, right = false, up = false, down = false;
    bool fast = false;        // shift: kFastFactor × speed
    glm::vec2 lookPixels{0};  // mouse motion with the right button held (x right, y down)
    float scrollSteps = 0;    // wheel steps or +/- presses: speed × kSpeedStep per step
    bool any() const;
};

class WalkController {
public:
    static constexpr float kFastFactor = 5.0f;
    static constexpr float kSpeedStep = 1.25f;
    static constexpr float kRadiansPerPixel = 0.0035f;
    static constexpr float kMaxPitchDegrees = 89.0f; // keeps forward away from the up axis
    static constexpr float kFramePitchDegrees = 25.0f; // F looks down at least this much

    WalkController() = default;
    // `sceneBounds` sets the default speed (a scene diagonal in ~40 s) and what F frames.
    WalkController(const Camera& start, const Aabb& sceneBounds);

    // Applies one frame of input over `seconds`; returns true when the camera moved.
    bool update(const WalkInput& input, double seconds);
    void setCamera(const Camera& camera);
    // Looks at the scene's bounding sphere from the current heading, from above (kFramePitchDegrees or steeper),
    // at the distance that fits the sphere in view.
    void frameScene();

    Camera camera() const;
    float speed() const { return speed_; } // scene units per second
    void setSpeed(float unitsPerSecond);
    float yawRadians() const { return yaw_; }
    float pitchRadians() const { return pitch_; }

private:
    glm::vec3 forward() const;

    Aabb bounds_;
    glm::vec3 eye_{0.0f};
    float yaw_ = 0.0f;   // about +Y; 0 looks down -Z
    float pitch_ = 0.0f; // above the horizon, radians
    float focusDistance_ = 1.0f; // distance of the printed --target from the eye (keeps the original target)
    float fovYDegrees_ = 60.0f;
    float speed_ = 1.0f;
};

} // namespace chcrt::app
