#pragma once
// Shared set-up of the GL render tests: one headless EGL context per test process (ctest runs each test in its
// own process), scene + BVH + Renderer construction, and small read-back helpers.
#include "tests/render/hit_oracle.h"

#include "renderer/bvh/bvh.h"
#include "renderer/gl/context.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/procedural/procedural.h"
#include "renderer/scene/scene.h"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace chcrt::test {

// Reads a whole RGBA32UI texture (the hit and cost targets), rows bottom to top as GL stores them.
inline std::vector<glm::uvec4> readUvec4Image(GLuint texture, int width, int height) {
    std::vector<glm::uvec4> texels(size_t(width) * size_t(height));
    glGetTextureImage(texture, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, GLsizei(texels.size() * sizeof(glm::uvec4)),
                      texels.data());
    return texels;
}

class RenderTest : public ::testing::Test {
protected:
    void SetUp() override { context_ = createHeadlessContext(GlBackend::Egl, true); }
    void TearDown() override {
        renderer_.reset();
        context_.reset();
    }

    // Builds BVH and renderer for `scene` (kept alive in the fixture).
    Renderer& makeRenderer(Scene scene, const AreaLight& light, const RenderSettings& settings) {
        scene_ = std::move(scene);
        bvh_ = buildBvh(scene_);
        renderer_ = std::make_unique<Renderer>(scene_, bvh_, light, settings);
        return *renderer_;
    }
    Renderer& makeProceduralRenderer(const std::string& specText, const RenderSettings& settings) {
        ProceduralSpec spec;
        EXPECT_TRUE(parseProceduralSpec(specText, spec));
        spec_ = spec;
        return makeRenderer(generateProceduralScene(spec), proceduralAreaLight(spec), settings);
    }

    // The first camera of the procedural scene's near path, with its G-buffer rendered and sample 0 of `type`'s rays
    // generated: the set-up of the tests that trace one ray set.
    Camera raysAtNearPathStart(Renderer& renderer, RayType type, FrameStats& stats) const {
        const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
        renderer.renderGBuffer(camera, stats);
        renderer.generateRayPass(camera, type, 0, stats);
        return camera;
    }

    // Reads texel (x, y) (GL convention: y from the bottom) of an RGBA32F texture.
    static glm::vec4 readTexel(GLuint texture, int x, int y) {
        glm::vec4 value(0.0f);
        glGetTextureSubImage(texture, 0, x, y, 0, 1, 1, 1, GL_RGBA, GL_FLOAT, sizeof(value), &value);
        return value;
    }

    std::unique_ptr<GlContext> context_;
    Scene scene_;
    Bvh bvh_;
    ProceduralSpec spec_;
    std::unique_ptr<Renderer> renderer_;
};

} // namespace chcrt::test
