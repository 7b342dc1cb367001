// CHC+RT with Line Space traversal in its subtree shader (methods chcrt+ls-exact / chcrt+ls; ChcrtOptions'
// subtree hooks compile shaders/culling/chcrt_subtrees.frag.glsl with LineSpaceGpu::defines and bind the pools):
//  - exact skipping in every subtree gives pure BVH's hits bit for bit (closest hit: t and id; any hit: hit/miss)
//    over consecutive frames (temporal coherence, all ray types), while culling really happens;
//  - shadow termination in the subtrees only adds occlusion to what pure BVH finds.
#include "tests/render/render_fixture.h"

#include "culling/chcrt_tracer.h"
#include "linespace/linespace_build.h"
#include "linespace/linespace_gpu.h"
#include "shaders/shared/linespace_bindings.h"
#include "renderer/scene/camera_path.h"

#include <cstring>

namespace chcrt::test {
namespace {

class ChcrtLineSpaceTest : public RenderTest {
protected:
    // CHC+RT always culling (no adaptive fallback), its subtrees traced with `closest` / `any` Line Space modes.
    ChcrtOptions lineSpaceOptions(ls::LineSpaceMode closest, ls::LineSpaceMode any) {
        ls::LineSpaceParams params;
        params.n = 6;
        params.depth = 10;
        spaces_ = ls::buildLineSpaces(bvh_, params);
        auto gpu = std::make_shared<ls::LineSpaceGpu>(spaces_, bvh_, scene_);
        ChcrtOptions options;
        options.adaptive = false;
        options.partition.maxSubtreeHeight = 8; // small subtrees and tiles, as the CHC+RT exactness tests: culling
        options.pairs.minTileSize = 16;         // happens at 96 x 72
        options.subtreeDefines = [gpu, closest, any](bool anyHit) { return gpu->defines(anyHit ? any : closest, 30.0f); };
        options.bindSubtreeResources = [gpu] { gpu->bind(); };
        return options;
    }
    ls::LineSpaces spaces_;
};

bool hitOf(const Hit& h) { return h.triangleId != CHCRT_NO_HIT_ID; }

TEST_F(ChcrtLineSpaceTest, ExactSkippingInSubtreesGivesPureBvhHits) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    ChcrtTracer chcrt(bvh_, lineSpaceOptions(ls::LineSpaceMode::Exact, ls::LineSpaceMode::Exact), "chcrt+ls-exact");
    ASSERT_LT(spaces_.stats.binaryFilled, spaces_.stats.binaryShafts);
    const CameraPath path = proceduralNearPath(spec_);
    uint64_t compared = 0, hits = 0;
    for (int frame = 0; frame < 3; ++frame) {
        const Camera camera = path.cameraAtFrame(frame * 2);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
            renderer.generateRayPass(camera, type, 0, stats);
            const OracleComparison traced = traceAgainstPureBvh(renderer, chcrt, camera, type, 0, stats);
            renderer.useTracer(nullptr);
            ASSERT_EQ(traced.reference.size(), traced.traced.size());
            for (size_t i = 0; i < traced.reference.size(); ++i) {
                ASSERT_TRUE(sameHit(traced.reference[i], traced.traced[i], isAnyHit(type)))
                    << toString(type) << " frame " << frame * 2 << " pixel " << i << ": id "
                    << traced.traced[i].triangleId << " vs " << traced.reference[i].triangleId;
                hits += hitOf(traced.reference[i]);
            }
            compared += traced.reference.size();
        }
        EXPECT_EQ(stats.cappedRays, 0u);
    }
    EXPECT_GT(hits, compared / 4);
    EXPECT_GT(chcrt.totalStats().pairsInvisible, 0u) << "nothing was culled";
}

TEST_F(ChcrtLineSpaceTest, ShadowTerminationInSubtreesOnlyAddsOcclusion) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    ChcrtTracer chcrt(bvh_, lineSpaceOptions(ls::LineSpaceMode::Exact, ls::LineSpaceMode::Shadow), "chcrt+ls");
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(2);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    renderer.generateRayPass(camera, RayType::Shadow, 0, stats);
    const OracleComparison traced = traceAgainstPureBvh(renderer, chcrt, camera, RayType::Shadow, 0, stats);
    renderer.useTracer(nullptr);
    const std::vector<Hit>& reference = traced.reference;
    const std::vector<Hit>& hits = traced.traced;
    uint64_t occludedPure = 0, occludedLs = 0, terminated = 0;
    for (size_t i = 0; i < hits.size(); ++i) {
        ASSERT_TRUE(!hitOf(reference[i]) || hitOf(hits[i])) << "lost an occluder at pixel " << i;
        occludedPure += hitOf(reference[i]);
        occludedLs += hitOf(hits[i]);
        terminated += hits[i].triangleId == CHCRT_LS_OCCLUDED_ID;
    }
    EXPECT_GT(occludedPure, 0u);
    EXPECT_GE(occludedLs, occludedPure);
    EXPECT_GT(terminated, 0u) << "no shaft terminated a ray: the subtrees did not use the Line Spaces";
    EXPECT_EQ(stats.cappedRays, 0u);
}

} // namespace
} // namespace chcrt::test
