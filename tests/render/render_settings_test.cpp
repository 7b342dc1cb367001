#include "renderer/core/error.h"
#include "renderer/render/camera_math.h"
#include "renderer/render/render_settings.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

TEST(RenderSettings, ParsesRayTypesAndEffects) {
    EXPECT_EQ(parseRayType("primary"), RayType::Primary);
    EXPECT_EQ(parseRayType("diffuse"), RayType::Diffuse);
    EXPECT_THROW(parseRayType("gloss"), InputError);
    const EffectSet some = parseEffects("ao,shadow");
    EXPECT_TRUE(some.ao);
    EXPECT_TRUE(some.shadows);
    EXPECT_FALSE(some.diffuse);
    EXPECT_EQ(toString(some), "shadow,ao");
    EXPECT_EQ(toString(parseEffects("none")), "none");
    EXPECT_EQ(toString(parseEffects("all")), "shadow,ao,diffuse");
    EXPECT_THROW(parseEffects("shadow,caustics"), InputError);
    EXPECT_THROW(parseEffects(""), InputError);
    EXPECT_EQ(parsePrimaryVisibility("raster"), PrimaryVisibility::Raster);
    EXPECT_EQ(parsePrimaryVisibility("traced"), PrimaryVisibility::Traced);
    EXPECT_STREQ(toString(PrimaryVisibility::Traced), "traced");
    EXPECT_EQ(RenderSettings{}.primaryVisibility, PrimaryVisibility::Raster);
    EXPECT_THROW(parsePrimaryVisibility("rasterised"), InputError);
}

TEST(RenderSettings, RejectsOutOfRangeValues) {
    RenderSettings s;
    EXPECT_NO_THROW(validateSettings(s));
    s.width = 0;
    EXPECT_THROW(validateSettings(s), InputError);
    s = RenderSettings{};
    s.samplesPerPixel = 0;
    EXPECT_THROW(validateSettings(s), InputError);
    s = RenderSettings{};
    s.rotationDegrees = 400.0f;
    EXPECT_THROW(validateSettings(s), InputError);
    s = RenderSettings{};
    s.aoLengthFraction = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(validateSettings(s), InputError);
}

TEST(CameraMath, ProjectionMapsTheTargetToTheImageCentreAndReversesDepth) {
    Camera camera;
    camera.eye = {3, 4, 5};
    camera.target = {-1, 0.5f, 2};
    const CameraFrame frame = makeCameraFrame(camera, 640, 360);
    const glm::mat4 clipFromWorld = clipFromView(frame, 0.1f) * viewFromWorld(frame);
    const glm::vec4 centre = clipFromWorld * glm::vec4(camera.target, 1.0f);
    EXPECT_NEAR(centre.x / centre.w, 0.0f, 1e-5f);
    EXPECT_NEAR(centre.y / centre.w, 0.0f, 1e-5f);
    const float distance = glm::length(camera.target - camera.eye);
    EXPECT_NEAR(centre.z / centre.w, 0.1f / distance, 1e-6f); // reversed Z: near / view distance
    // A point up and to the right of the target lands in the upper right quadrant.
    const glm::vec4 corner = clipFromWorld * glm::vec4(camera.target + frame.right + frame.up, 1.0f);
    EXPECT_GT(corner.x / corner.w, 0.0f);
    EXPECT_GT(corner.y / corner.w, 0.0f);
    // The primary-ray basis used by ray generation agrees with the projection at the image's top-right corner.
    const glm::vec3 rayDirection = glm::normalize(frame.forward + frame.right * frame.tanHalfFovY * frame.aspect +
                                                  frame.up * frame.tanHalfFovY);
    const glm::vec4 projected = clipFromWorld * glm::vec4(camera.eye + rayDirection * 7.0f, 1.0f);
    EXPECT_NEAR(projected.x / projected.w, 1.0f, 1e-5f);
    EXPECT_NEAR(projected.y / projected.w, 1.0f, 1e-5f);
}

} // namespace
} // namespace chcrt

#include "renderer/render/halton.h"

namespace chcrt {
namespace {

TEST(Halton, FirstPointsAreTheRadicalInversesInBases2And3) {
    EXPECT_EQ(halton2D(0), glm::vec2(0.0f, 0.0f));
    EXPECT_EQ(halton2D(1), glm::vec2(0.5f, float(1.0 / 3.0)));
    EXPECT_EQ(halton2D(2), glm::vec2(0.25f, float(2.0 / 3.0)));
    EXPECT_EQ(halton2D(3), glm::vec2(0.75f, float(1.0 / 9.0)));
    EXPECT_NEAR(halton2D(4).y, 4.0 / 9.0, 1e-7);
    // Stratification: the first 16 points put 4 in each quarter of [0, 1) along x.
    int quarters[4] = {0, 0, 0, 0};
    for (uint32_t i = 0; i < 16; ++i) ++quarters[int(halton2D(i).x * 4.0f)];
    for (int q : quarters) EXPECT_EQ(q, 4);
}

} // namespace
} // namespace chcrt
