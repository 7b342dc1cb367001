// WalkController: the viewer's camera controls, driven without a window.
#include "app/viewer/walk_controller.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chcrt::app {
namespace {

Aabb unitBox(float size) {
    Aabb box;
    box.grow(glm::vec3(-size));
    box.grow(glm::vec3(size));
    return box;
}

Camera lookingDownMinusZ() {
    Camera c;
    c.eye = {1.0f, 2.0f, 3.0f};
    c.target = {1.0f, 2.0f, -7.0f};
    c.fovYDegrees = 50.0f;
    return c;
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float tolerance = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(WalkController, KeepsTheStartingCameraUntilInput) {
    WalkController walk(lookingDownMinusZ(), unitBox(20.0f));
    const Camera c = walk.camera();
    expectNear(c.eye, {1, 2, 3});
    expectNear(c.target, {1, 2, -7}); // the original target distance is kept for --target
    EXPECT_EQ(c.fovYDegrees, 50.0f);
    EXPECT_FALSE(walk.update(WalkInput{}, 1.0));
    expectNear(walk.camera().eye, {1, 2, 3});
}

TEST(WalkController, WasdMovesAlongTheViewAndStrafesSideways) {
    WalkController walk(lookingDownMinusZ(), unitBox(20.0f));
    walk.setSpeed(2.0f);
    WalkInput forward;
    forward.forward = true;
    EXPECT_TRUE(walk.update(forward, 0.5));
    expectNear(walk.camera().eye, {1, 2, 2}); // 2 units/s for 0.5 s along -Z
    WalkInput right;
    right.right = true;
    walk.update(right, 1.0);
    expectNear(walk.camera().eye, {3, 2, 2}); // +X is to the right when looking down -Z
    WalkInput up;
    up.up = true;
    up.fast = true;
    walk.update(up, 0.1);
    expectNear(walk.camera().eye, {3, 2 + 2 * WalkController::kFastFactor * 0.1f, 2});
    WalkInput both; // opposite keys cancel
    both.forward = both.back = true;
    EXPECT_FALSE(walk.update(both, 1.0));
}

TEST(WalkController, MouseLookTurnsAndClampsPitch) {
    WalkController walk(lookingDownMinusZ(), unitBox(20.0f));
    WalkInput look;
    look.lookPixels = {std::acos(0.0f) / WalkController::kRadiansPerPixel, 0}; // a quarter turn right
    EXPECT_TRUE(walk.update(look, 0.0));
    const Camera c = walk.camera();
    expectNear(glm::normalize(c.target - c.eye), {1, 0, 0}, 1e-4f);
    WalkInput down;
    down.lookPixels = {0, 1e6f}; // far past straight down
    walk.update(down, 0.0);
    EXPECT_NEAR(walk.pitchRadians(), -glm::radians(WalkController::kMaxPitchDegrees), 1e-5f);
    const Camera d = walk.camera();
    EXPECT_LT(glm::normalize(d.target - d.eye).y, -0.99f);
}

TEST(WalkController, ScrollScalesSpeed) {
    WalkController walk(lookingDownMinusZ(), unitBox(20.0f));
    const float base = walk.speed();
    EXPECT_GT(base, 0.0f);
    WalkInput scroll;
    scroll.scrollSteps = 2;
    walk.update(scroll, 0.0);
    EXPECT_NEAR(walk.speed(), base * WalkController::kSpeedStep * WalkController::kSpeedStep, 1e-5f * base);
    scroll.scrollSteps = -2;
    walk.update(scroll, 0.0);
    EXPECT_NEAR(walk.speed(), base, 1e-5f * base);
}

TEST(WalkController, FrameSceneFitsTheBoundingSphereInView) {
    WalkController walk(lookingDownMinusZ(), unitBox(10.0f));
    walk.frameScene();
    const Camera c = walk.camera();
    const glm::vec3 direction = glm::normalize(c.target - c.eye);
    // Keeps the heading (-Z), looking down by kFramePitchDegrees.
    const float pitch = glm::radians(WalkController::kFramePitchDegrees);
    expectNear(direction, {0, -std::sin(pitch), -std::cos(pitch)}, 1e-5f);
    const float radius = std::sqrt(3.0f) * 10.0f;
    const float distance = glm::length(c.eye);
    // The sphere's angular radius seen from the eye is within half the vertical field of view.
    EXPECT_LE(std::asin(radius / distance), glm::radians(c.fovYDegrees) * 0.5f);
    expectNear(c.target, {0, 0, 0}, 1e-3f);
}

TEST(WalkController, SetCameraRoundTripsDirection) {
    WalkController walk(lookingDownMinusZ(), unitBox(20.0f));
    for (int i = 0; i < 100; ++i) {
        const float a = 0.37f * float(i), b = 0.011f * float(i % 50) - 0.27f;
        Camera c;
        c.eye = {float(i), 1.0f, -float(i)};
        c.target = c.eye + 3.0f * glm::vec3(std::sin(a) * std::cos(b), std::sin(b), -std::cos(a) * std::cos(b));
        walk.setCamera(c);
        expectNear(walk.camera().eye, c.eye);
        expectNear(walk.camera().target, c.target, 1e-4f);
    }
}

} // namespace
} // namespace chcrt::app
