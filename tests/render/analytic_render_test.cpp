// Renders with known answers: a plane lit by a rectangular light (radiance by numerical integration on the
// CPU), a point whose view of the light is fully blocked (exactly zero direct light), determinism for a seed.
#include "render_fixture.h"

#include "renderer/core/image_io.h"

#include <cmath>

namespace chcrt::test {
namespace {

constexpr float kPi = 3.14159265358979f;

void addQuad(Scene& scene, glm::vec3 corner, glm::vec3 edgeU, glm::vec3 edgeV, uint32_t material) {
    const uint32_t base = uint32_t(scene.positions.size());
    const glm::vec3 normal = glm::normalize(glm::cross(edgeU, edgeV));
    for (glm::vec3 p : {corner, corner + edgeU, corner + edgeU + edgeV, corner + edgeV}) {
        scene.positions.push_back(p);
        scene.normals.push_back(normal);
    }
    scene.triangles.push_back({base, base + 1, base + 2});
    scene.triangles.push_back({base, base + 2, base + 3});
    scene.triangleMaterials.insert(scene.triangleMaterials.end(), 2, material);
}

// A 20 x 20 grey ground plane at y = 0 (normal +Y); optionally an 8 x 8 occluder at y = 2 above the origin.
Scene planeScene(bool withOccluder) {
    Scene scene;
    scene.name = "lit-plane";
    Material grey;
    grey.baseColorFactor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    scene.materials.push_back(grey);
    addQuad(scene, {-10, 0, 10}, {20, 0, 0}, {0, 0, -20}, 0);
    if (withOccluder) addQuad(scene, {-4, 2, 4}, {8, 0, 0}, {0, 0, -8}, 0);
    scene.stats.uniqueTriangles = scene.stats.instancedTriangles = scene.triangles.size();
    return scene;
}

// A 2 x 2 light at y = 4 centred above the origin, facing down.
AreaLight overheadLight() {
    AreaLight light;
    light.corner = {-1, 4, -1};
    light.edgeU = {2, 0, 0}; // cross(edgeU, edgeV) = (0,-4,0): facing down
    light.edgeV = {0, 0, 2};
    light.radiance = glm::vec3(10.0f);
    return light;
}

// Irradiance at point p with normal +Y from the light, by midpoint integration over a 400 x 400 grid.
double irradianceFromLight(const AreaLight& light, glm::vec3 p) {
    const int n = 400;
    const glm::vec3 lightNormal = light.normal();
    const double cellArea = double(light.area()) / (n * n);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const glm::vec3 q = light.corner + (float(i) + 0.5f) / n * light.edgeU + (float(j) + 0.5f) / n * light.edgeV;
            const glm::vec3 d = q - p;
            const float dist2 = glm::dot(d, d);
            const glm::vec3 w = d / std::sqrt(dist2);
            sum += double(std::max(w.y, 0.0f)) * std::max(-glm::dot(lightNormal, w), 0.0f) / dist2 * cellArea;
        }
    }
    return sum * light.radiance.x;
}

RenderSettings directOnlySettings() {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 64;
    settings.samplesPerPixel = 64;
    settings.effects = EffectSet{true, false, false};
    settings.skyAmbient = 0.0f;
    settings.rotationDegrees = 360.0f;
    return settings;
}

Camera cameraLookingAtOrigin(glm::vec3 eye) {
    Camera camera;
    camera.eye = eye;
    camera.target = glm::vec3(0.0f);
    camera.fovYDegrees = 40.0f;
    return camera;
}

TEST_F(RenderTest, LitPlaneRadianceMatchesNumericalIntegration) {
    const AreaLight light = overheadLight();
    Renderer& renderer = makeRenderer(planeScene(false), light, directOnlySettings());
    renderer.renderFrame(cameraLookingAtOrigin({0, 6, 8}));
    const FrameTargets& targets = renderer.targets();
    // Several pixels along the image's vertical centre line: different distances and angles to the light.
    for (int y : {16, 32, 48}) {
        const glm::vec4 position = readTexel(targets.gbufferPosition.id(), 32, y);
        ASSERT_EQ(position.w, 1.0f) << "pixel should see the plane";
        const double expected = 0.5 / kPi * irradianceFromLight(light, glm::vec3(position));
        ASSERT_GT(expected, 0.05) << "the test scene must be lit";
        const glm::vec4 rendered = readTexel(targets.outputHdr.id(), 32, y);
        EXPECT_NEAR(rendered.r, expected, 0.03 * expected) << "pixel y=" << y;
        EXPECT_NEAR(rendered.g, rendered.r, 1e-6);
    }
}

TEST_F(RenderTest, FullyOccludedPointReceivesNoDirectLight) {
    Renderer& renderer = makeRenderer(planeScene(true), overheadLight(), directOnlySettings());
    // From below the occluder (y = 1), looking at the origin, whose every path to the light crosses it.
    renderer.renderFrame(cameraLookingAtOrigin({0, 1, 5}));
    const glm::vec4 centre = readTexel(renderer.targets().outputHdr.id(), 32, 32);
    EXPECT_EQ(centre.r, 0.0f);
    EXPECT_EQ(centre.g, 0.0f);
    EXPECT_EQ(centre.b, 0.0f);
    // ...while a point on the plane far outside the occluder's shadow is lit.
    Camera outside = cameraLookingAtOrigin({0, 1, 5});
    outside.target = glm::vec3(0, 0, 8.0f); // paths to the light cross y = 2 at z > 4.5: past the occluder
    outside.eye = glm::vec3(0, 0.5f, 10.0f);
    renderer.renderFrame(outside);
    EXPECT_GT(readTexel(renderer.targets().outputHdr.id(), 32, 32).r, 0.0f);
}

TEST_F(RenderTest, RenderingIsDeterministicForASeed) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.samplesPerPixel = 2;
    Renderer& renderer = makeProceduralRenderer("city:20k", settings);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(10);
    renderer.renderFrame(camera);
    const ImageRgba32f first = renderer.readHdrImage();
    renderer.renderFrame(camera);
    const ImageRgba32f second = renderer.readHdrImage();
    EXPECT_EQ(first.pixels, second.pixels);
    settings.seed = 2;
    renderer.setSettings(settings);
    renderer.renderFrame(camera);
    const ImageRgba32f otherSeed = renderer.readHdrImage();
    EXPECT_NE(first.pixels, otherSeed.pixels);
    // The image is neither empty nor saturated: a shaded city.
    double sum = 0;
    for (size_t i = 0; i < first.pixels.size(); i += 4) sum += first.pixels[i];
    EXPECT_GT(sum / (first.width * first.height), 0.01);
}

// Frustum culling of clusters in the G-buffer pass must not change a single G-buffer texel: clusters that are
// skipped cannot produce fragments. Compared bit for bit on near and far views, and culling must really cull.
TEST_F(RenderTest, FrustumCullingLeavesTheGBufferBitIdentical) {
    RenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    Renderer& renderer = makeProceduralRenderer("city:100k", settings);
    auto readAll = [&](GLuint texture, GLenum format, GLenum type) {
        std::vector<uint32_t> data(size_t(settings.width) * settings.height * 4);
        glGetTextureImage(texture, 0, format, type, GLsizei(data.size() * 4), data.data());
        return data;
    };
    for (const CameraPath& path : {proceduralNearPath(spec_), proceduralFarPath(spec_)}) {
        for (int frame : {0, path.frameCount() / 2}) {
            const Camera camera = path.cameraAtFrame(frame);
            std::vector<uint32_t> images[2][3];
            uint64_t drawn[2] = {0, 0};
            for (int culling = 0; culling < 2; ++culling) {
                renderer.setFrustumCulling(culling == 1);
                FrameStats stats;
                renderer.renderGBuffer(camera, stats);
                drawn[culling] = stats.gbufferTriangles;
                const FrameTargets& t = renderer.targets();
                images[culling][0] = readAll(t.gbufferPosition.id(), GL_RGBA, GL_FLOAT);
                images[culling][1] = readAll(t.gbufferNormal.id(), GL_RGBA, GL_FLOAT);
                images[culling][2] = readAll(t.gbufferTriangle.id(), GL_RGBA_INTEGER, GL_UNSIGNED_INT);
            }
            EXPECT_EQ(drawn[0], scene_.triangleCount());
            if (path.name.find("near") != std::string::npos) {
                // Street level sees a small part of the city: most clusters lie outside the frustum.
                EXPECT_LT(drawn[1], drawn[0] * 3 / 4) << path.name << " frame " << frame;
            } else {
                EXPECT_LE(drawn[1], drawn[0]); // the bird's-eye path sees (nearly) everything
            }
            for (int i = 0; i < 3; ++i) EXPECT_EQ(images[0][i], images[1][i]) << path.name << " frame " << frame;
        }
    }
}

} // namespace
} // namespace chcrt::test
