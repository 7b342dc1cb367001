// Line Space traversal on the GPU (shaders/linespace/linespace_traverse.glsl through LineSpaceTracer) against
// pure BVH tracing on procedural scenes, for every ray type:
//  - exact skipping (bvh+ls-exact) gives exactly the pure tracer's hits (bits of t and id; hit/miss for any-hit)
//    and the same shaded frame, while testing fewer triangles (the skipping really happens);
//  - shadow termination (SS §4.1) only adds occlusion: an empty shaft is skipped exactly and an occupied one
//    counts as occluded, so every ray occluded for pure BVH is occluded for Line Space tracing;
//  - candidate hits (RC Algorithm 1) lie within the ray's [tmin, tmax] and name a scene triangle.
#include "tests/render/render_fixture.h"

#include "linespace/linespace_build.h"
#include "linespace/linespace_gpu.h"
#include "linespace/linespace_tracer.h"
#include "renderer/scene/camera_path.h"
#include "shaders/linespace/linespace_bindings.h"

#include <cstring>

namespace chcrt::test {
namespace {

struct TraceCase {
    const char* scene;
    uint32_t n;
    uint32_t depth;
};

class LineSpaceTraceTest : public RenderTest, public ::testing::WithParamInterface<TraceCase> {
protected:
    std::shared_ptr<ls::LineSpaceGpu> buildGpu(const TraceCase& c, bool candidates) {
        ls::LineSpaceParams params;
        params.n = c.n;
        params.depth = c.depth;
        params.candidates = candidates;
        spaces_ = ls::buildLineSpaces(bvh_, params);
        return std::make_shared<ls::LineSpaceGpu>(spaces_, bvh_, scene_);
    }
    // Sum of the triangles tested per ray (cost target .z) of the last pass.
    uint64_t trianglesTested(Renderer& renderer) {
        const FrameTargets& t = renderer.targets();
        std::vector<glm::uvec4> cost(size_t(t.width) * t.height);
        glGetTextureImage(t.hits[0].cost.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                          GLsizei(cost.size() * sizeof(cost[0])), cost.data());
        uint64_t sum = 0;
        for (const glm::uvec4& c : cost) sum += c.z;
        return sum;
    }
    ls::LineSpaces spaces_;
};

bool sameHit(const Hit& a, const Hit& b, bool anyHit) {
    const bool hitA = a.triangleId != CHCRT_NO_HIT_ID, hitB = b.triangleId != CHCRT_NO_HIT_ID;
    if (anyHit) return hitA == hitB;
    return a.triangleId == b.triangleId && std::memcmp(&a.t, &b.t, sizeof(float)) == 0;
}

TEST_P(LineSpaceTraceTest, ExactSkippingGivesPureBvhHits) {
    const TraceCase c = GetParam();
    RenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    ls::LineSpaceTracer tracer("bvh+ls-exact", buildGpu(c, false), ls::LineSpaceModes::allExact(), 30.0f);
    ASSERT_LT(spaces_.stats.binaryFilled, spaces_.stats.binaryShafts) << "no empty shaft: nothing to test";
    const CameraPath path = proceduralNearPath(spec_);
    uint64_t compared = 0, pureTriangles = 0, lsTriangles = 0;
    for (int frame : {0, 3}) {
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
            for (int sample = 0; sample < 2; ++sample) {
                renderer.generateRayPass(camera, type, sample, stats);
                renderer.useTracer(nullptr);
                renderer.traceRayPass(camera, type, sample, stats);
                const std::vector<Hit> reference = renderer.readHits(0);
                pureTriangles += trianglesTested(renderer);
                renderer.useTracer(&tracer);
                renderer.traceRayPass(camera, type, sample, stats);
                const std::vector<Hit> hits = renderer.readHits(0);
                lsTriangles += trianglesTested(renderer);
                renderer.useTracer(nullptr);
                const std::vector<Ray> rays = renderer.readRays(0);
                ASSERT_EQ(hits.size(), reference.size());
                for (size_t i = 0; i < hits.size(); ++i) {
                    if (!(rays[i].tmax > rays[i].tmin)) continue;
                    ++compared;
                    ASSERT_TRUE(sameHit(hits[i], reference[i], isAnyHit(type)))
                        << toString(type) << " frame " << frame << " pixel " << i << ": id " << hits[i].triangleId
                        << " t " << hits[i].t << " vs id " << reference[i].triangleId << " t " << reference[i].t;
                }
            }
        }
        EXPECT_EQ(stats.cappedRays, 0u);
    }
    EXPECT_GT(compared, 10000u);
    EXPECT_LT(lsTriangles, pureTriangles) << "exact skipping skipped nothing";
}

TEST_P(LineSpaceTraceTest, ExactSkippingGivesTheSameShadedFrame) {
    const TraceCase c = GetParam();
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.samplesPerPixel = 2;
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    ls::LineSpaceTracer tracer("bvh+ls-exact", buildGpu(c, false), ls::LineSpaceModes::allExact(), 30.0f);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(1);
    renderer.useTracer(nullptr);
    renderer.renderFrame(camera);
    const ImageRgba32f reference = renderer.readHdrImage();
    renderer.useTracer(&tracer);
    renderer.renderFrame(camera);
    const ImageRgba32f image = renderer.readHdrImage();
    renderer.useTracer(nullptr);
    ASSERT_EQ(reference.pixels.size(), image.pixels.size());
    EXPECT_EQ(std::memcmp(reference.pixels.data(), image.pixels.data(), image.pixels.size() * sizeof(image.pixels[0])), 0);
}

TEST_P(LineSpaceTraceTest, ApproximateModesKeepTheirGuarantees) {
    const TraceCase c = GetParam();
    RenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    ls::LineSpaceModes modes; // bvh+ls defaults, with AO candidates (off by default) tested too
    modes.ao = ls::LineSpaceMode::CandidateExactStart;
    ls::LineSpaceTracer tracer("bvh+ls", buildGpu(c, true), modes, 30.0f);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(2);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    uint64_t occludedPure = 0, occludedLs = 0, candidateHits = 0;
    for (RayType type : {RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
        renderer.generateRayPass(camera, type, 0, stats);
        renderer.useTracer(nullptr);
        renderer.traceRayPass(camera, type, 0, stats);
        const std::vector<Hit> reference = renderer.readHits(0);
        renderer.useTracer(&tracer);
        renderer.traceRayPass(camera, type, 0, stats);
        const std::vector<Hit> hits = renderer.readHits(0);
        renderer.useTracer(nullptr);
        const std::vector<Ray> rays = renderer.readRays(0);
        for (size_t i = 0; i < hits.size(); ++i) {
            if (!(rays[i].tmax > rays[i].tmin)) continue;
            const bool pureHit = reference[i].triangleId != CHCRT_NO_HIT_ID;
            const bool lsHit = hits[i].triangleId != CHCRT_NO_HIT_ID;
            if (type == RayType::Shadow) {
                occludedPure += pureHit;
                occludedLs += lsHit;
                ASSERT_TRUE(!pureHit || lsHit) << "shadow termination lost an occluder at pixel " << i;
                continue;
            }
            if (!lsHit) continue;
            ASSERT_GE(hits[i].t, rays[i].tmin) << toString(type) << " pixel " << i;
            ASSERT_LE(hits[i].t, rays[i].tmax) << toString(type) << " pixel " << i;
            ASSERT_LT(hits[i].triangleId, scene_.triangles.size()) << toString(type) << " pixel " << i;
            ++candidateHits;
        }
    }
    EXPECT_EQ(stats.cappedRays, 0u);
    EXPECT_GT(occludedPure, 0u);
    EXPECT_GE(occludedLs, occludedPure);
    EXPECT_GT(candidateHits, 0u);
}

std::string caseName(const ::testing::TestParamInfo<TraceCase>& info) {
    std::string name = std::string(info.param.scene) + "_N" + std::to_string(info.param.n) + "_D" +
                       std::to_string(info.param.depth);
    for (char& ch : name) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    }
    return name;
}

INSTANTIATE_TEST_SUITE_P(ProceduralScenes, LineSpaceTraceTest,
                         ::testing::Values(TraceCase{"city:30k", 6, 10}, TraceCase{"interior:30k", 6, 10},
                                           TraceCase{"plant:30k", 3, 9}, TraceCase{"plane-and-box", 8, 3}),
                         caseName);

} // namespace
} // namespace chcrt::test
