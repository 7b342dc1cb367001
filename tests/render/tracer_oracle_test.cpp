// The GLSL tracer against its oracles (Embree and a CPU BVH tracer check GLSL tracing), on the
// procedural scenes, for every ray type, with the tolerance of renderer/render/hit_comparison.h.
#include "render_fixture.h"

#include "renderer/bvh/cpu_tracer.h"
#include "renderer/reference/embree_tracer.h"
#include "renderer/render/bvh_tracer.h"
#include "renderer/render/hit_comparison.h"

namespace chcrt::test {
namespace {

struct OracleCase {
    const char* scene;
    RayType rayType;
};

class TracerOracleTest : public RenderTest, public ::testing::WithParamInterface<OracleCase> {};

TEST_P(TracerOracleTest, GlslHitsEqualEmbreeAndCpuHits) {
    const OracleCase c = GetParam();
    RenderSettings settings = smallTraceSettings();
    settings.rotationDegrees = 360.0f; // decorrelated rays cover more of the scene
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    const EmbreeTracer embree(scene_);
    HitTolerance tolerance;
    tolerance.absoluteT *= renderer.sceneDiagonal();
    const CameraPath path = proceduralNearPath(spec_);

    uint64_t activeRays = 0, hits = 0;
    for (int frame : {0, path.frameCount() / 2}) {
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (int sample = 0; sample < 2; ++sample) {
            renderer.generateRayPass(camera, c.rayType, sample, stats);
            renderer.traceRayPass(camera, c.rayType, sample, stats);
            const std::vector<Ray> rays = renderer.readRays(0);
            const std::vector<Hit> glsl = renderer.readHits(0);
            std::vector<Hit> reference(rays.size()), cpu(rays.size());
            embree.trace(rays, reference, false);
            traceCpu(bvh_, rays, cpu, isAnyHit(c.rayType));
            const HitComparison vsEmbree = compareHits(scene_, rays, glsl, reference, isAnyHit(c.rayType), tolerance);
            const HitComparison vsCpu = compareHits(scene_, rays, glsl, cpu, isAnyHit(c.rayType), tolerance);
            EXPECT_EQ(vsEmbree.differing, 0u) << c.scene << " frame " << frame << " sample " << sample;
            EXPECT_EQ(vsCpu.differing, 0u) << c.scene << " frame " << frame << " sample " << sample;
            // Border cases exist but must stay rare (they are rounding decisions, not bugs).
            EXPECT_LE(vsEmbree.edgeCases, vsEmbree.activeRays / 500 + 2);
            activeRays += vsEmbree.activeRays;
            hits += vsEmbree.hitsB;
        }
        EXPECT_EQ(stats.cappedRays, 0u);
    }
    // The comparison must have had something to compare: active rays, and both hits and misses overall.
    EXPECT_GT(activeRays, uint64_t(settings.width * settings.height) / 2);
    EXPECT_GT(hits, 0u);
    if (c.rayType == RayType::Shadow || c.rayType == RayType::Ao) {
        EXPECT_LT(hits, activeRays); // (full-length diffuse rays inside a closed interior all hit)
    }
}

std::string caseName(const ::testing::TestParamInfo<OracleCase>& info) {
    std::string scene = info.param.scene;
    for (char& ch : scene)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return scene + "_" + toString(info.param.rayType);
}

INSTANTIATE_TEST_SUITE_P(ProceduralScenes, TracerOracleTest,
                         ::testing::Values(OracleCase{"city:30k", RayType::Primary}, OracleCase{"city:30k", RayType::Shadow},
                                           OracleCase{"city:30k", RayType::Ao}, OracleCase{"city:30k", RayType::Diffuse},
                                           OracleCase{"interior:30k", RayType::Primary},
                                           OracleCase{"interior:30k", RayType::Shadow},
                                           OracleCase{"interior:30k", RayType::Ao},
                                           OracleCase{"interior:30k", RayType::Diffuse},
                                           OracleCase{"plant:30k", RayType::Primary}, OracleCase{"plant:30k", RayType::Shadow},
                                           OracleCase{"plant:30k", RayType::Ao}, OracleCase{"plant:30k", RayType::Diffuse}),
                         caseName);

TEST_F(RenderTest, LoopCapIsDetectedAndReported) {
    // With a cap of 8 iterations nearly every primary ray into a city is cut short: the renderer must say so.
    RenderSettings settings;
    settings.width = 32;
    settings.height = 32;
    Renderer& renderer = makeProceduralRenderer("city:20k", settings);
    BvhTracer cappedTracer(8u);
    renderer.useTracer(&cappedTracer);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    FrameStats stats;
    renderer.generateRayPass(camera, RayType::Primary, 0, stats);
    renderer.traceRayPass(camera, RayType::Primary, 0, stats);
    EXPECT_GT(stats.cappedRays, uint64_t(32 * 32) / 2);
}

TEST_F(RenderTest, LoopCapIsNeverReachedOnTheDeepestScene) {
    // The plant is the deepest, least regular procedural scene; full-length diffuse rays at full rotation are
    // the least coherent rays we trace. None may reach llvmpipe's loop limit (65,535 iterations per
    // shader invocation in total, ended silently).
    RenderSettings settings;
    settings.width = 64;
    settings.height = 64;
    settings.rotationDegrees = 360.0f;
    Renderer& renderer = makeProceduralRenderer("plant:300k", settings);
    const CameraPath path = proceduralNearPath(spec_);
    for (int frame : {0, path.frameCount() - 1}) {
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Diffuse, RayType::Ao, RayType::Shadow}) {
            renderer.generateRayPass(camera, type, 0, stats);
            renderer.traceRayPass(camera, type, 0, stats);
        }
        EXPECT_EQ(stats.cappedRays, 0u) << "frame " << frame;
    }
}

} // namespace
} // namespace chcrt::test
