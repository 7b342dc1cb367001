// validateScene, generateVertexNormals, dropDegenerateTriangles, defaultCamera, defaultAreaLight, bounds.
#include "renderer/core/error.h"
#include "renderer/scene/scene.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <random>

namespace chcrt {
namespace {

// Two triangles forming a unit quad in the XZ plane, facing +Y.
Scene makeQuad() {
    Scene scene;
    scene.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}};
    scene.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.triangleMaterials = {0, 0};
    scene.materials.resize(1);
    generateVertexNormals(scene);
    return scene;
}

TEST(ValidateScene, AcceptsAValidScene) { EXPECT_NO_THROW(validateScene(makeQuad())); }

TEST(ValidateScene, RejectsEmptyScene) {
    Scene scene = makeQuad();
    scene.triangles.clear();
    scene.triangleMaterials.clear();
    try {
        validateScene(scene);
        FAIL() << "no exception";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "scene has no triangles");
    }
}

TEST(ValidateScene, RejectsInconsistentScenes) {
    {
        Scene scene = makeQuad();
        scene.triangles[1].z = 4; // one past the last vertex
        EXPECT_THROW(validateScene(scene), InputError);
    }
    {
        Scene scene = makeQuad();
        scene.normals.pop_back();
        EXPECT_THROW(validateScene(scene), InputError);
    }
    {
        Scene scene = makeQuad();
        scene.texcoords.resize(3);
        EXPECT_THROW(validateScene(scene), InputError);
    }
    {
        Scene scene = makeQuad();
        scene.triangleMaterials[0] = 1;
        EXPECT_THROW(validateScene(scene), InputError);
    }
    {
        Scene scene = makeQuad();
        scene.materials[0].baseColorTexture = 0; // no textures
        EXPECT_THROW(validateScene(scene), InputError);
    }
    {
        Scene scene = makeQuad();
        scene.materials.clear();
        EXPECT_THROW(validateScene(scene), InputError);
    }
}

TEST(ValidateScene, RejectsNonFinitePositions) {
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        Scene scene = makeQuad();
        scene.positions[2].y = bad;
        EXPECT_THROW(validateScene(scene), InputError);
    }
}

TEST(GenerateVertexNormals, PlanarMeshGetsItsFaceNormal) {
    const Scene scene = makeQuad();
    for (const glm::vec3& n : scene.normals) {
        EXPECT_NEAR(n.x, 0.0f, 1e-6f);
        EXPECT_NEAR(n.y, 1.0f, 1e-6f);
        EXPECT_NEAR(n.z, 0.0f, 1e-6f);
    }
}

TEST(GenerateVertexNormals, WeightsByAreaAndDefaultsUnusedVerticesToUp) {
    Scene scene;
    // Vertex 0 is shared by a triangle of area 2 facing +Y and a triangle of area 0.5 facing +Z.
    scene.positions = {{0, 0, 0}, {0, 0, 2}, {2, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}};
    scene.triangles = {{0, 1, 2}, {0, 3, 4}};
    generateVertexNormals(scene);
    ASSERT_EQ(scene.normals.size(), scene.positions.size());
    const glm::vec3 expected = glm::normalize(glm::vec3(0.0f, 2.0f, 0.5f));
    EXPECT_NEAR(glm::distance(scene.normals[0], expected), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(scene.normals[1], glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(scene.normals[4], glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    EXPECT_EQ(scene.normals[5], glm::vec3(0, 1, 0)); // referenced by no triangle
}

TEST(DropDegenerateTriangles, RemovesRepeatedIndicesAndZeroAreaKeepingMaterialsAligned) {
    Scene scene = makeQuad();
    scene.positions.push_back({2, 0, 0}); // collinear with vertices 0 and 3
    scene.normals.push_back({0, 1, 0});
    scene.materials.resize(3);
    scene.triangles = {{0, 1, 2}, {1, 1, 2}, {0, 3, 4}, {0, 2, 3}};
    scene.triangleMaterials = {0, 1, 1, 2};
    dropDegenerateTriangles(scene);
    EXPECT_EQ(scene.stats.degenerateTrianglesDropped, 2u);
    ASSERT_EQ(scene.triangles.size(), 2u);
    EXPECT_EQ(scene.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(scene.triangles[1], glm::uvec3(0, 2, 3));
    EXPECT_EQ(scene.triangleMaterials, (std::vector<uint32_t>{0, 2}));
}

TEST(DropDegenerateTriangles, KeepsTinyButRealTriangles) {
    Scene scene = makeQuad();
    for (glm::vec3& p : scene.positions) p *= 1e-12f; // squared cross product would underflow
    dropDegenerateTriangles(scene);
    EXPECT_EQ(scene.stats.degenerateTrianglesDropped, 0u);
    EXPECT_EQ(scene.triangles.size(), 2u);
}

TEST(SceneBounds, CoversAllPositions) {
    const Aabb box = makeQuad().bounds();
    EXPECT_EQ(box.lower, glm::vec3(0, 0, 0));
    EXPECT_EQ(box.upper, glm::vec3(1, 0, 1));
}

Scene sceneWithBounds(const glm::vec3& lower, const glm::vec3& upper) {
    Scene scene;
    scene.positions = {lower, upper};
    return scene;
}

// All eight corners of the bounds must project inside the view frustum (aspect 1, the tightest case for
// aspect >= 1) and in front of the camera.
void expectCornersVisible(const Scene& scene, float fovY) {
    const Camera camera = defaultCamera(scene, fovY);
    EXPECT_FLOAT_EQ(camera.fovYDegrees, fovY);
    EXPECT_EQ(camera.up, glm::vec3(0, 1, 0));
    EXPECT_GT(camera.eye.z, camera.target.z); // from the front (+Z)
    EXPECT_GT(camera.eye.y, camera.target.y); // and from above
    const glm::mat4 view = glm::lookAt(camera.eye, camera.target, camera.up);
    const glm::mat4 projection = glm::perspective(glm::radians(fovY), 1.0f, 1e-4f, 1e6f);
    const Aabb box = scene.bounds();
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p((corner & 1) ? box.upper.x : box.lower.x, (corner & 2) ? box.upper.y : box.lower.y,
                          (corner & 4) ? box.upper.z : box.lower.z);
        const glm::vec4 clip = projection * view * glm::vec4(p, 1.0f);
        ASSERT_GT(clip.w, 0.0f) << "corner behind the camera";
        EXPECT_LE(std::abs(clip.x), clip.w) << "corner " << corner << " outside horizontally";
        EXPECT_LE(std::abs(clip.y), clip.w) << "corner " << corner << " outside vertically";
    }
}

TEST(DefaultCamera, SeesAllCornersOfRandomBounds) {
    for (int i = 0; i < 200; ++i) {
        std::mt19937 rng(i);
        std::uniform_real_distribution<float> position(-100.0f, 100.0f), size(0.0f, 50.0f), fov(20.0f, 100.0f);
        const glm::vec3 lower(position(rng), position(rng), position(rng));
        const glm::vec3 upper = lower + glm::vec3(size(rng), size(rng), size(rng));
        expectCornersVisible(sceneWithBounds(lower, upper), fov(rng));
    }
}

TEST(DefaultCamera, HandlesFlatAndPointScenes) {
    expectCornersVisible(sceneWithBounds({-5, 0, -5}, {5, 0, 5}), 60.0f);
    const Camera camera = defaultCamera(sceneWithBounds({1, 2, 3}, {1, 2, 3}));
    EXPECT_GT(glm::distance(camera.eye, camera.target), 0.0f);
    EXPECT_EQ(camera.target, glm::vec3(1, 2, 3));
}

// `count` small triangles at random places in [lower, upper].
void addScatteredTriangles(Scene& scene, size_t count, const glm::vec3& lower, const glm::vec3& upper, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (size_t i = 0; i < count; ++i) {
        const glm::vec3 p = lower + (upper - lower) * glm::vec3(u(rng), u(rng), u(rng));
        const uint32_t v = uint32_t(scene.positions.size());
        scene.positions.insert(scene.positions.end(), {p, p + glm::vec3(0.2f, 0, 0), p + glm::vec3(0, 0.2f, 0)});
        scene.triangles.emplace_back(v, v + 1, v + 2);
    }
}

bool inside(const Aabb& box, const glm::vec3& p) {
    return glm::all(glm::greaterThanEqual(p, box.lower)) && glm::all(glm::lessThanEqual(p, box.upper));
}

// A town 200 × 200 m and 12 m high on an island whose cliff reaches 100 m down and 50 m out (the Intel castle's
// shape): framed whole it would be a small island seen from far outside. The default camera stands inside the
// bounds, above the town's front edge, and looks at the town's centre.
TEST(DefaultCamera, ALargeOpenSceneIsSeenFromInsideItsBounds) {
    Scene scene;
    addScatteredTriangles(scene, 120000, {0, 0, 0}, {200, 12, 200}, 1);
    const uint32_t v = uint32_t(scene.positions.size()); // the cliff: two big triangles
    scene.positions.insert(scene.positions.end(), {{-50, -100, -50}, {250, -100, -50}, {250, -100, 250}, {-50, 0, 250}});
    scene.triangles.emplace_back(v, v + 1, v + 2);
    scene.triangles.emplace_back(v, v + 2, v + 3);
    const Aabb bounds = scene.bounds();
    const Camera camera = defaultCamera(scene, 60.0f);
    EXPECT_TRUE(inside(bounds, camera.eye)) << camera.eye.x << " " << camera.eye.y << " " << camera.eye.z;
    EXPECT_TRUE(inside(Aabb{{0, 0, 0}, {200, 12, 200}}, camera.target)) << "looks at the town";
    EXPECT_NEAR(camera.target.x, 100.0f, 5.0f);
    EXPECT_NEAR(camera.target.z, 100.0f, 5.0f);
    EXPECT_GT(camera.eye.y, camera.target.y); // from above
    EXPECT_GT(camera.eye.z, camera.target.z); // from the front
    EXPECT_LE(camera.eye.z, 200.0f);          // at the town's edge, not beyond
    EXPECT_FLOAT_EQ(camera.fovYDegrees, 60.0f);
}

// As many triangles, but a compact object (as high as wide) or a small flat scene: framed whole, from outside.
TEST(DefaultCamera, CompactObjectsAndSmallScenesAreFramedWhole) {
    Scene object;
    addScatteredTriangles(object, 120000, {0, 0, 0}, {10, 10, 10}, 2);
    Scene small;
    addScatteredTriangles(small, 5000, {0, 0, 0}, {200, 12, 200}, 3);
    for (const Scene* scene : {&object, &small}) {
        const Camera camera = defaultCamera(*scene, 60.0f);
        EXPECT_FALSE(inside(scene->bounds(), camera.eye));
        EXPECT_EQ(camera.target, scene->bounds().center());
    }
}

TEST(DefaultAreaLight, SquareFacingDownAboveTheSceneWithTheDocumentedBrightness) {
    const Scene scene = sceneWithBounds({-10, 0, -6}, {10, 4, 6});
    const AreaLight light = defaultAreaLight(scene);
    EXPECT_NEAR(glm::distance(light.normal(), glm::vec3(0, -1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(light.edgeU), 5.0f, 1e-5f); // 1/4 of the larger horizontal extent (20)
    EXPECT_NEAR(glm::length(light.edgeV), 5.0f, 1e-5f);
    EXPECT_GT(light.corner.y, 4.0f);
    const glm::vec3 center = light.corner + 0.5f * (light.edgeU + light.edgeV);
    EXPECT_GT(glm::length(glm::vec2(center.x, center.z)), 1.0f) << "light should be offset sideways";

    // A white Lambertian plane at y = 0 below the scene centre reflects E / pi = 0.8 (scene.cpp). Integrate
    // the irradiance far finer than the implementation does.
    const glm::vec3 receiver(0, 0, 0);
    double irradiance = 0.0;
    constexpr int kSteps = 400;
    for (int i = 0; i < kSteps; ++i) {
        for (int j = 0; j < kSteps; ++j) {
            const glm::vec3 p = light.corner + ((i + 0.5f) / kSteps) * light.edgeU + ((j + 0.5f) / kSteps) * light.edgeV;
            const glm::vec3 d = p - receiver;
            const double r2 = glm::dot(d, d);
            const double cosTheta = d.y / std::sqrt(r2); // both cosines: the light faces straight down
            irradiance += light.radiance.x * cosTheta * cosTheta / r2 * (light.area() / (kSteps * kSteps));
        }
    }
    EXPECT_NEAR(irradiance / M_PI, 0.8, 0.8 * 0.01);
}

} // namespace
} // namespace chcrt
