// The pure tracer's two shader stages (renderer/render/trace_stage.h): the compute pass writes the fragment pass's
// hit and cost targets bit for bit (t, id, barycentrics, costs) for every ray type on the procedural scenes, whole
// shaded frames come out identical, the compute pass honours the scissor box, and `auto` resolves by the rule.
// Also the loop cap's define (shaders/shared/render_layout.h): chosen from the renderer, kept on llvmpipe, and
// tracing without it finds the same hits.
#include "render_fixture.h"

#include "renderer/core/error.h"
#include "renderer/render/bvh_tracer.h"
#include "renderer/render/trace_pass.h"

#include <cstdlib>
#include <cstring>
#include <optional>

namespace chcrt::test {
namespace {

// Fills both hit attachments with a pattern no tracer writes, so that unwritten pixels show.
void poison(const HitTargets& hits) {
    const GLuint garbage[4] = {0xDEADBEEFu, 0x12345678u, 0xCAFEBABEu, 0x0BADF00Du};
    glClearTexImage(hits.hit.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, garbage);
    glClearTexImage(hits.cost.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, garbage);
}

struct Traced {
    std::vector<glm::uvec4> hit, cost;
};

// Traces the renderer's ray set 0 with `tracer` into poisoned hit set 0 and reads both targets back.
Traced traceWith(Renderer& renderer, Tracer& tracer, RayType type, const Camera& camera) {
    renderer.useTracer(&tracer);
    poison(renderer.targets().hits[0]);
    FrameStats stats;
    renderer.traceRayPass(camera, type, 0, stats);
    renderer.useTracer(nullptr);
    EXPECT_EQ(stats.cappedRays, 0u);
    const FrameTargets& t = renderer.targets();
    return {readUvec4Image(t.hits[0].hit.id(), t.width, t.height), readUvec4Image(t.hits[0].cost.id(), t.width, t.height)};
}

struct StageCase {
    const char* scene;
    RayType rayType;
};

class TraceStageTest : public RenderTest, public ::testing::WithParamInterface<StageCase> {};

TEST_P(TraceStageTest, ComputeHitsAndCostsEqualFragmentBitForBit) {
    const StageCase c = GetParam();
    RenderSettings settings;
    settings.width = 77; // not a multiple of the 8x8 work groups
    settings.height = 53;
    settings.rotationDegrees = 360.0f;
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    BvhTracer fragment(TraceStage::Fragment), compute(TraceStage::Compute);
    ASSERT_EQ(fragment.stage(), TraceStage::Fragment);
    ASSERT_EQ(compute.stage(), TraceStage::Compute);
    const CameraPath path = proceduralNearPath(spec_);
    size_t active = 0, hits = 0, pixels = 0;
    for (int frame : {0, path.frameCount() / 2}) {
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (int sample = 0; sample < 2; ++sample) {
            renderer.generateRayPass(camera, c.rayType, sample, stats);
            const Traced a = traceWith(renderer, fragment, c.rayType, camera);
            const Traced b = traceWith(renderer, compute, c.rayType, camera);
            const std::vector<Ray> rays = renderer.readRays(0);
            size_t differing = 0;
            for (size_t i = 0; i < a.hit.size(); ++i) {
                if (a.hit[i] != b.hit[i] || a.cost[i] != b.cost[i]) {
                    if (++differing <= 3) {
                        ADD_FAILURE() << c.scene << " frame " << frame << " pixel " << i << ": fragment (" << a.hit[i].x
                                      << ", " << a.hit[i].y << ") cost " << a.cost[i].x << " vs compute (" << b.hit[i].x
                                      << ", " << b.hit[i].y << ") cost " << b.cost[i].x;
                    }
                }
                active += rays[i].tmax > rays[i].tmin ? 1 : 0;
                hits += a.hit[i].y != CHCRT_NO_HIT_ID ? 1 : 0;
            }
            pixels += a.hit.size();
            EXPECT_EQ(differing, 0u) << c.scene << " frame " << frame << " sample " << sample;
        }
    }
    // Something to compare: active rays and hits, and for shadow rays inactive ones too (surfaces facing away from
    // the light, on every scene; AO and diffuse rays are inactive only where the sky shows, never in the interior).
    EXPECT_GT(active, pixels / 4);
    EXPECT_GT(hits, 0u);
    if (c.rayType == RayType::Shadow) {
        EXPECT_LT(active, pixels);
    }
}

std::string caseName(const ::testing::TestParamInfo<StageCase>& info) {
    std::string scene = info.param.scene;
    for (char& ch : scene) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    }
    return scene + "_" + toString(info.param.rayType);
}

INSTANTIATE_TEST_SUITE_P(
    ProceduralScenes, TraceStageTest,
    ::testing::Values(StageCase{"city:30k", RayType::Primary}, StageCase{"city:30k", RayType::Shadow},
                      StageCase{"city:30k", RayType::Ao}, StageCase{"city:30k", RayType::Diffuse},
                      StageCase{"interior:30k", RayType::Primary}, StageCase{"interior:30k", RayType::Shadow},
                      StageCase{"interior:30k", RayType::Ao}, StageCase{"interior:30k", RayType::Diffuse},
                      StageCase{"plant:30k", RayType::Primary}, StageCase{"plant:30k", RayType::Shadow},
                      StageCase{"plant:30k", RayType::Ao}, StageCase{"plant:30k", RayType::Diffuse}),
    caseName);

// Whole frames (every effect, the diffuse bounce's shadow rays included, traced primary visibility) are the same
// image in both stages.
TEST_F(RenderTest, ShadedFramesAreIdenticalInBothStages) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.samplesPerPixel = 2;
    settings.primaryVisibility = PrimaryVisibility::Traced;
    Renderer& renderer = makeProceduralRenderer("interior:20k", settings);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(3);
    BvhTracer fragment(TraceStage::Fragment), compute(TraceStage::Compute);
    renderer.useTracer(&fragment);
    renderer.renderFrame(camera);
    const ImageRgba32f a = renderer.readHdrImage();
    renderer.useTracer(&compute);
    renderer.renderFrame(camera);
    const ImageRgba32f b = renderer.readHdrImage();
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)));
    float sum = 0;
    for (float v : a.pixels) sum += v;
    EXPECT_GT(sum, 0.0f); // a lit frame, not two black ones
}

// With the scissor test on (Renderer::warmUp traces one pixel), the compute pass writes the scissor box only, as
// the fragment pass does.
TEST_F(RenderTest, ComputePassWritesOnlyTheScissorBox) {
    RenderSettings settings;
    settings.width = 40;
    settings.height = 30;
    Renderer& renderer = makeProceduralRenderer("city:20k", settings);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    FrameStats stats;
    renderer.generateRayPass(camera, RayType::Primary, 0, stats);
    BvhTracer fragment(TraceStage::Fragment), compute(TraceStage::Compute);
    const Traced whole = traceWith(renderer, fragment, RayType::Primary, camera);
    glEnable(GL_SCISSOR_TEST);
    glScissor(5, 7, 11, 9);
    const Traced boxed = traceWith(renderer, compute, RayType::Primary, camera);
    glDisable(GL_SCISSOR_TEST);
    size_t inside = 0;
    for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
            const size_t i = size_t(y) * settings.width + x;
            if (x >= 5 && x < 16 && y >= 7 && y < 16) {
                ++inside;
                EXPECT_EQ(boxed.hit[i], whole.hit[i]) << x << ", " << y;
            } else {
                EXPECT_EQ(boxed.hit[i].x, 0xDEADBEEFu) << x << ", " << y; // untouched
            }
        }
    }
    EXPECT_EQ(inside, 11u * 9u);
}

TEST_F(RenderTest, AutoStageFollowsTheRuleAndTheEnvironment) {
    const std::optional<std::string> saved =
        std::getenv("CHCRT_SHADER_STAGE") ? std::optional<std::string>(std::getenv("CHCRT_SHADER_STAGE")) : std::nullopt;
    ::unsetenv("CHCRT_SHADER_STAGE");
    const TraceStage rule = currentRendererTraits().software ? TraceStage::Fragment : TraceStage::Compute;
    EXPECT_EQ(resolveTraceStage(TraceStage::Auto), rule);
    EXPECT_EQ(resolveTraceStage(TraceStage::Fragment), TraceStage::Fragment);
    EXPECT_EQ(resolveTraceStage(TraceStage::Compute), TraceStage::Compute);
    ::setenv("CHCRT_SHADER_STAGE", "compute", 1);
    EXPECT_EQ(resolveTraceStage(TraceStage::Auto), TraceStage::Compute);
    EXPECT_EQ(BvhTracer(TraceStage::Auto).stage(), TraceStage::Compute);
    EXPECT_EQ(resolveTraceStage(TraceStage::Fragment), TraceStage::Fragment); // an explicit stage wins
    ::setenv("CHCRT_SHADER_STAGE", "vertex", 1);
    EXPECT_THROW(resolveTraceStage(TraceStage::Auto), InputError);
    if (saved) ::setenv("CHCRT_SHADER_STAGE", saved->c_str(), 1);
    else ::unsetenv("CHCRT_SHADER_STAGE");
    EXPECT_THROW(parseTraceStage("geometry"), InputError);
    EXPECT_EQ(parseTraceStage("compute"), TraceStage::Compute);
}

// The loop cap's define follows the renderer: on llvmpipe the counting is compiled in (and a lowered cap is
// detected: tracer_oracle_test.cpp), elsewhere it is compiled out.
TEST_F(RenderTest, LoopCapDefineFollowsTheRendererAndLlvmpipeKeepsIt) {
    const std::vector<ShaderDefine> defines = withImplicitDefines({});
    std::optional<std::string> loopCap;
    for (const ShaderDefine& d : defines) {
        if (d.name == "CHCRT_TRACE_LOOP_CAP") loopCap = d.value;
    }
    ASSERT_TRUE(loopCap.has_value());
    EXPECT_EQ(*loopCap, currentRendererTraits().loopCap ? "1" : "0");
    const GlInfo info = queryGlInfo();
    if (info.renderer.find("llvmpipe") != std::string::npos) {
        EXPECT_EQ(*loopCap, "1") << info.renderer;
    }
    // A program's own value wins.
    for (const ShaderDefine& d : withImplicitDefines({{"CHCRT_TRACE_LOOP_CAP", "0"}})) {
        if (d.name == "CHCRT_TRACE_LOOP_CAP") {
            EXPECT_EQ(d.value, "0");
        }
    }
}

// A tracer compiled with the given CHCRT_TRACE_LOOP_CAP, in either stage (the variant GPUs run when 0).
class LoopCapTracer final : public Tracer {
public:
    LoopCapTracer(TraceStage stage, const char* loopCap) : stage_(stage) {
        for (bool anyHit : {false, true}) {
            const std::vector<ShaderDefine> defines = {{"TRACE_ANY_HIT", anyHit ? "1" : "0"},
                                                       {"CHCRT_TRACE_LOOP_CAP", loopCap}};
            programs_[anyHit] =
                stage == TraceStage::Compute
                    ? ShaderProgram({{GL_COMPUTE_SHADER, "render/trace_bvh.comp.glsl"}}, defines)
                    : ShaderProgram({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                     {GL_FRAGMENT_SHADER, "render/trace_bvh.frag.glsl"}},
                                    defines);
        }
    }
    std::string name() const override { return "loop-cap-variant"; }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override {
        const ShaderProgram& program = programs_[request.anyHit ? 1 : 0];
        if (stage_ == TraceStage::Compute) {
            dispatchTracePass(program, rays, hits, width, height);
        } else {
            beginTracePass(rays, hits, width, height);
            program.use();
            drawFullscreenTriangle();
            endTracePass();
        }
        ++stats.passes;
    }

private:
    TraceStage stage_;
    ShaderProgram programs_[2];
};

TEST_F(RenderTest, TracingWithoutTheLoopCapFindsTheSameHits) {
    RenderSettings settings;
    settings.width = 48;
    settings.height = 40;
    settings.rotationDegrees = 360.0f;
    Renderer& renderer = makeProceduralRenderer("plant:30k", settings);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    for (TraceStage stage : {TraceStage::Fragment, TraceStage::Compute}) {
        LoopCapTracer capped(stage, "1"), uncapped(stage, "0");
        for (RayType type : {RayType::Primary, RayType::Diffuse, RayType::Ao}) {
            renderer.generateRayPass(camera, type, 0, stats);
            const Traced a = traceWith(renderer, capped, type, camera);
            const Traced b = traceWith(renderer, uncapped, type, camera);
            EXPECT_EQ(a.hit, b.hit) << toString(stage) << " " << toString(type);
            EXPECT_EQ(a.cost, b.cost) << toString(stage) << " " << toString(type);
        }
    }
}

TEST(RendererTraits, SoftwareAndLoopCapComeFromTheRendererString) {
    const RendererTraits llvmpipe = rendererTraits("llvmpipe (LLVM 15.0.6, 256 bits)");
    EXPECT_TRUE(llvmpipe.software);
    EXPECT_TRUE(llvmpipe.loopCap);
    const RendererTraits nvidia = rendererTraits("NVIDIA H200/PCIe/SSE2");
    EXPECT_FALSE(nvidia.software);
    EXPECT_FALSE(nvidia.loopCap);
    const RendererTraits amd = rendererTraits("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6, DRM 3.49)");
    EXPECT_FALSE(amd.software); // "LLVM" alone is not llvmpipe
    EXPECT_FALSE(amd.loopCap);
    EXPECT_TRUE(rendererTraits("softpipe").software);
    EXPECT_FALSE(rendererTraits("softpipe").loopCap);
    EXPECT_TRUE(rendererTraits("Google SwiftShader").software);
}

} // namespace
} // namespace chcrt::test
