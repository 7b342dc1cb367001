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
