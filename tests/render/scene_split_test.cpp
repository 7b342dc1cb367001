// Per-triangle data beyond one texture buffer (renderer/render/scene_gpu.h, render/triangle_data.glsl): a scene
// uploaded with a small per-buffer limit, so that each per-triangle array is split into several texture buffers,
// traces and shades exactly as the same scene in one buffer per array, in both shader stages; a scene needing more
// parts than the shaders read is refused with a clear message.
#include "render_fixture.h"

#include "renderer/core/error.h"
#include "renderer/render/bvh_tracer.h"
#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/render_layout.h"

#include <cstring>

namespace chcrt::test {
namespace {

TEST_F(RenderTest, SceneSplitAcrossTextureBuffersRendersTheSameBits) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.samplesPerPixel = 1;
    settings.primaryVisibility = PrimaryVisibility::Traced; // reads vertex normals and attributes by id
    Renderer& whole = makeProceduralRenderer("city:20k", settings);
    ASSERT_EQ(whole.sceneGpu().triangleBufferCount(), 1);
    // The programs of `whole` were compiled for one part; the split scene's renderer (made after the upload raised
    // CHCRT_TRIANGLE_BUFFERS) reads three.
    const uint64_t triangles = scene_.triangleCount();
    const uint64_t perPart = (triangles + 2) / 3; // three parts, the last one shorter
    auto split = std::make_unique<SceneGpu>(scene_, bvh_, perPart * CHCRT_TRI_TEXELS_PER_TRIANGLE);
    ASSERT_EQ(split->triangleBufferCount(), 3);
    EXPECT_EQ(processShaderDefine("CHCRT_TRIANGLE_BUFFERS"), "3");
    ProceduralSpec spec = spec_;
    Renderer parts(scene_, bvh_, proceduralAreaLight(spec), settings, std::move(split));

    const CameraPath path = proceduralNearPath(spec_);
    for (TraceStage stage : {TraceStage::Fragment, TraceStage::Compute}) {
        BvhTracer wholeTracer(stage);
        whole.useTracer(&wholeTracer);
        // The split renderer's tracer is made (compiled) after the split, like every tracer of a session.
        BvhTracer partsTracer(stage);
        parts.useTracer(&partsTracer);
        for (int frame : {0, path.frameCount() / 2}) {
            const Camera camera = path.cameraAtFrame(frame);
            whole.renderFrame(camera);
            parts.renderFrame(camera);
            const ImageRgba32f a = whole.readHdrImage(), b = parts.readHdrImage();
            ASSERT_EQ(a.pixels.size(), b.pixels.size());
            EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)))
                << toString(stage) << " frame " << frame;
            // Every ray type's hits, bit for bit.
            for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
                FrameStats stats;
                for (Renderer* r : {&whole, &parts}) {
                    r->renderGBuffer(camera, stats);
                    r->generateRayPass(camera, type, 0, stats);
                    r->traceRayPass(camera, type, 0, stats);
                }
                const std::vector<Hit> ha = whole.readHits(0), hb = parts.readHits(0);
                size_t differing = 0, hits = 0;
                for (size_t i = 0; i < ha.size(); ++i) {
                    differing += std::memcmp(&ha[i], &hb[i], sizeof(Hit)) != 0 ? 1 : 0;
                    hits += ha[i].hit() ? 1 : 0;
                }
                EXPECT_EQ(differing, 0u) << toString(stage) << " " << toString(type) << " frame " << frame;
                EXPECT_GT(hits, 0u);
            }
        }
        whole.useTracer(nullptr);
        parts.useTracer(nullptr);
    }
}

TEST_F(RenderTest, SceneNeedingMoreTextureBuffersThanTheShadersReadIsRefused) {
    RenderSettings settings;
    settings.width = 8;
    settings.height = 8;
    makeProceduralRenderer("city:20k", settings);
    const uint64_t perPart = scene_.triangleCount() / (CHCRT_MAX_TRIANGLE_BUFFERS + 2);
    try {
        SceneGpu tooMany(scene_, bvh_, perPart * CHCRT_TRI_TEXELS_PER_TRIANGLE);
        FAIL() << "no GlError";
    } catch (const GlError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("texture buffers"), std::string::npos) << message;
        EXPECT_NE(message.find("out of core"), std::string::npos) << message;
    }
}

} // namespace
} // namespace chcrt::test
