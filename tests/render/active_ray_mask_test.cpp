// The active-ray mask (RayTextures::active, renderer/render/trace_pass.h): ray generation marks exactly the rays
// with tmax > tmin, and a tracing pass that skips the unmarked pixels writes the same hit and cost images, bit
// for bit and for every pixel, as the same pass without the mask.
#include "render_fixture.h"

#include "renderer/render/bvh_tracer.h"

#include <cstring>

namespace chcrt::test {
namespace {

// Fills both hit attachments with a pattern no tracer writes, so that unwritten pixels show.
void poison(const HitTargets& hits) {
    const GLuint garbage[4] = {0xDEADBEEFu, 0x12345678u, 0xCAFEBABEu, 0x0BADF00Du};
    glClearTexImage(hits.hit.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, garbage);
    glClearTexImage(hits.cost.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, garbage);
}

class ActiveRayMaskTest : public RenderTest, public ::testing::WithParamInterface<RayType> {};

TEST_P(ActiveRayMaskTest, MaskMarksActiveRaysAndMaskedTracingWritesEveryPixelAsUnmasked) {
    const RayType type = GetParam();
    RenderSettings settings;
    settings.width = 80;
    settings.height = 64;
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    renderer.generateRayPass(camera, type, 0, stats);
    renderer.traceRayPass(camera, type, 0, stats); // binds the scene for tracing
    const int w = settings.width, h = settings.height;
    const RayTextures& generated = renderer.targets().rays[0];

    // The mask equals tmax > tmin for every pixel.
    const std::vector<Ray> rays = renderer.readRays(0);
    std::vector<float> mask(size_t(w) * h);
    glGetTextureImage(generated.active.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(mask.size() * sizeof(float)),
                      mask.data());
    size_t active = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const bool isActive = rays[i].tmax > rays[i].tmin;
        active += isActive ? 1 : 0;
        ASSERT_EQ(mask[i], isActive ? 1.0f : 0.0f) << "pixel " << i;
    }
    // The view has sky (inactive secondary rays) and geometry; primary rays are all active.
    EXPECT_GT(active, 0u);
    if (type == RayType::Primary) {
        EXPECT_EQ(active, rays.size());
    } else {
        EXPECT_LT(active, rays.size());
    }

    // The same rays traced into targets of our own, with the mask and without it.
    FrameTargets own(w, h);
    glCopyImageSubData(generated.origin.id(), GL_TEXTURE_2D, 0, 0, 0, 0, own.rays[0].origin.id(), GL_TEXTURE_2D, 0, 0,
                       0, 0, w, h, 1);
    glCopyImageSubData(generated.direction.id(), GL_TEXTURE_2D, 0, 0, 0, 0, own.rays[0].direction.id(),
                       GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
    glCopyImageSubData(generated.active.id(), GL_TEXTURE_2D, 0, 0, 0, 0, own.rays[0].active.id(), GL_TEXTURE_2D, 0,
                       0, 0, 0, w, h, 1);
    BvhTracer tracer;
    TraceRequest request;
    request.rayType = type;
    request.anyHit = isAnyHit(type);
    request.camera = camera;
    TraceStats traceStats;
    ASSERT_NE(own.hits[0].maskedFor, 0u);
    poison(own.hits[0]);
    tracer.trace(request, own.rays[0], own.hits[0], w, h, traceStats);
    const std::vector<glm::uvec4> maskedHit = readUvec4Image(own.hits[0].hit.id(), w, h);
    const std::vector<glm::uvec4> maskedCost = readUvec4Image(own.hits[0].cost.id(), w, h);
    own.hits[0].maskedFor = 0; // no mask: every fragment is shaded
    poison(own.hits[0]);
    tracer.trace(request, own.rays[0], own.hits[0], w, h, traceStats);
    const std::vector<glm::uvec4> fullHit = readUvec4Image(own.hits[0].hit.id(), w, h);
    const std::vector<glm::uvec4> fullCost = readUvec4Image(own.hits[0].cost.id(), w, h);
    ASSERT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    size_t differing = 0, poisoned = 0;
    for (size_t i = 0; i < maskedHit.size(); ++i) {
        differing += maskedHit[i] != fullHit[i] || maskedCost[i] != fullCost[i] ? 1 : 0;
        for (int c = 0; c < 4; ++c) poisoned += maskedHit[i][c] == 0xDEADBEEFu || maskedHit[i][c] == 0x12345678u ? 1 : 0;
    }
    EXPECT_EQ(differing, 0u);
    EXPECT_EQ(poisoned, 0u);
    // The masked result is also the renderer's own (which traced with the mask).
    const std::vector<Hit> rendererHits = renderer.readHits(0);
    ASSERT_EQ(rendererHits.size(), maskedHit.size());
    for (size_t i = 0; i < rendererHits.size(); ++i) {
        uint32_t tBits = 0;
        std::memcpy(&tBits, &rendererHits[i].t, sizeof(tBits));
        ASSERT_EQ(tBits, maskedHit[i].x) << "pixel " << i;
        ASSERT_EQ(rendererHits[i].triangleId, maskedHit[i].y) << "pixel " << i;
    }
}

std::string rayTypeName(const ::testing::TestParamInfo<RayType>& param) { return toString(param.param); }

INSTANTIATE_TEST_SUITE_P(RayTypes, ActiveRayMaskTest,
                         ::testing::Values(RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse),
                         rayTypeName);

} // namespace
} // namespace chcrt::test
