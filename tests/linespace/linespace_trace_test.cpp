// Line Space traversal on the GPU (shaders/linespace/linespace_traverse.glsl through LineSpaceTracer) against
// pure BVH tracing on procedural scenes, for every ray type:
//  - exact skipping (bvh+ls-exact) gives exactly the pure tracer's hits (bits of t and id; hit/miss for any-hit)
//    and the same shaded frame, while testing fewer triangles (the skipping really happens);
//  - shadow termination (SS §4.1) only adds occlusion: an empty shaft is skipped exactly and an occupied one
//    counts as occluded, so every ray occluded for pure BVH is occluded for Line Space tracing;
//  - candidate hits (RC Algorithm 1) lie within the ray's [tmin, tmax] and name a scene triangle;
//  - on a convex sphere, candidate hits (all false self-occlusion) vanish with faces=front and nearly so with
//    faces=front-start (the default).
#include "tests/render/render_fixture.h"

#include "linespace/linespace_build.h"
#include "linespace/linespace_gpu.h"
#include "linespace/linespace_tracer.h"
#include "renderer/scene/camera_path.h"
#include "shaders/shared/linespace_bindings.h"
#include "tests/linespace/linespace_test_util.h"

#include <array>
#include <cmath>
#include <cstdio>
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
        uint64_t sum = 0;
        for (const glm::uvec4& c : readUvec4Image(t.hits[0].cost.id(), t.width, t.height)) sum += c.z;
        return sum;
    }
    ls::LineSpaces spaces_;
};

TEST_P(LineSpaceTraceTest, ExactSkippingGivesPureBvhHits) {
    const TraceCase c = GetParam();
    const RenderSettings settings = smallTraceSettings();
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
    const RenderSettings settings = smallTraceSettings();
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
        const OracleComparison traced = traceAgainstPureBvh(renderer, tracer, camera, type, 0, stats);
        renderer.useTracer(nullptr);
        const std::vector<Hit>& reference = traced.reference;
        const std::vector<Hit>& hits = traced.traced;
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

// Without Line Space nodes that are BVH leaves, candidate passes compile the leaf test out
// (CHCRT_LS_CANDIDATE_NO_LEAVES): every pixel's hit, bits of t and cost must equal those of the same tracer with
// the leaf test kept, for AO, diffuse and (any-hit) shadow rays with candidates.
class LineSpaceLeafTestVariantTest : public LineSpaceTraceTest {};

TEST_P(LineSpaceLeafTestVariantTest, CandidatePassesWithoutTheUnreachableLeafTestGiveTheSameHits) {
    const TraceCase c = GetParam();
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    // A shallow cut, so that no Line Space node is a leaf; the case's own depth must have leaf spaces for the
    // variant to matter there (checked below).
    TraceCase shallow = c;
    shallow.depth = 3;
    const std::shared_ptr<ls::LineSpaceGpu> gpu = buildGpu(shallow, true);
    ASSERT_FALSE(gpu->hasLeafSpaces()) << c.scene << " has leaf Line Spaces even at depth 3";
    ls::LineSpaceModes modes;
    modes.ao = modes.diffuse = modes.shadow = ls::LineSpaceMode::Candidate;
    ls::LineSpaceTracer without("bvh+ls", gpu, modes, 30.0f), with("bvh+ls", gpu, modes, 30.0f);
    with.keepUnreachableLeafTest = true;
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(2);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    uint64_t hitsSeen = 0;
    for (RayType type : {RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
        renderer.generateRayPass(camera, type, 0, stats);
        std::vector<Hit> hits[2];
        std::vector<glm::uvec4> cost[2];
        for (int k = 0; k < 2; ++k) {
            renderer.useTracer(k == 0 ? &without : &with);
            renderer.traceRayPass(camera, type, 0, stats);
            hits[k] = renderer.readHits(0);
            const FrameTargets& t = renderer.targets();
            cost[k] = readUvec4Image(t.hits[0].cost.id(), t.width, t.height);
        }
        renderer.useTracer(nullptr);
        for (size_t i = 0; i < hits[0].size(); ++i) {
            ASSERT_EQ(hits[0][i].triangleId, hits[1][i].triangleId) << toString(type) << " pixel " << i;
            ASSERT_EQ(std::memcmp(&hits[0][i].t, &hits[1][i].t, sizeof(float)), 0) << toString(type) << " pixel " << i;
            ASSERT_EQ(cost[0][i], cost[1][i]) << toString(type) << " pixel " << i;
            hitsSeen += hits[0][i].triangleId != CHCRT_NO_HIT_ID ? 1 : 0;
        }
    }
    EXPECT_GT(hitsSeen, 0u);
    EXPECT_EQ(stats.cappedRays, 0u);
    // At the case's own depth the cut ends in leaves somewhere (so the leaf test stays in those passes).
    EXPECT_TRUE(buildGpu(c, false)->hasLeafSpaces()) << c.scene << " D=" << c.depth;
}

// A closed convex mesh with smooth normals: no ray leaving its surface can hit it again, so every candidate hit
// there is false self-occlusion (the neighbouring triangles' extended planes of RC Algorithm 1). A ray leaving a
// convex surface meets those planes from behind, so faces=front removes this error, faces=front-start (only in
// the start node) nearly all of it; faces=both (the paper's rule) has it.
class LineSpaceConvexTest : public RenderTest {};

Scene smoothSphere(uint32_t segments, uint32_t rings) {
    auto point = [&](uint32_t i, uint32_t j) {
        const float phi = 6.2831853f * float(i % segments) / float(segments), theta = 3.14159265f * float(j) / float(rings);
        return glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    };
    TriangleList triangles;
    for (uint32_t j = 0; j < rings; ++j) {
        for (uint32_t i = 0; i < segments; ++i) {
            const glm::vec3 a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
            for (std::array<glm::vec3, 3> t : {std::array<glm::vec3, 3>{a, b, c}, std::array<glm::vec3, 3>{a, c, d}}) {
                const glm::vec3 normal = glm::cross(t[1] - t[0], t[2] - t[0]);
                if (!(glm::length(normal) > 1e-7f)) continue; // degenerate at the poles
                if (glm::dot(normal, t[0] + t[1] + t[2]) < 0.0f) std::swap(t[1], t[2]); // counter-clockwise outside
                triangles.push_back(t);
            }
        }
    }
    Scene scene = makeScene(triangles);
    for (size_t v = 0; v < scene.positions.size(); ++v) scene.normals[v] = glm::normalize(scene.positions[v]);
    return scene;
}

TEST_F(LineSpaceConvexTest, FrontFacesOnlyRemovesSelfOcclusionOnAConvexSurface) {
    RenderSettings settings;
    settings.width = 96;
    settings.height = 96;
    settings.aoLengthFraction = 0.3f; // long enough to reach the neighbouring Line Space nodes
    AreaLight light;
    light.corner = {-1, 4, -1};
    light.edgeU = {2, 0, 0};
    light.edgeV = {0, 0, 2};
    light.radiance = glm::vec3(10.0f);
    Renderer& renderer = makeRenderer(smoothSphere(64, 32), light, settings);
    ls::LineSpaceParams params;
    params.n = 4;
    params.depth = 4;
    params.candidates = true;
    const ls::LineSpaces spaces = ls::buildLineSpaces(bvh_, params);
    auto gpu = std::make_shared<ls::LineSpaceGpu>(spaces, bvh_, scene_);
    ls::LineSpaceModes modes;
    modes.ao = modes.diffuse = ls::LineSpaceMode::Candidate; // the paper's rule: the start node acts as a leaf
    ASSERT_EQ(modes.candidateFaces, ls::CandidateFaces::FrontInStartNode); // the default
    ls::LineSpaceModes both = modes, front = modes;
    both.parse("faces=both");
    front.parse("faces=front");
    ls::LineSpaceTracer startTracer("bvh+ls", gpu, modes, 30.0f), bothTracer("bvh+ls", gpu, both, 30.0f),
        frontTracer("bvh+ls", gpu, front, 30.0f);
    Camera camera;
    camera.eye = glm::vec3(0.5f, 1.5f, 3.5f);
    camera.target = glm::vec3(0.0f);
    camera.fovYDegrees = 45.0f;
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    uint64_t rays = 0, pureHits = 0, frontHits = 0, startHits = 0, bothHits = 0;
    for (RayType type : {RayType::Ao, RayType::Diffuse}) {
        for (uint32_t sample = 0; sample < 2; ++sample) {
            renderer.generateRayPass(camera, type, sample, stats);
            auto hitsWith = [&](Tracer* tracer) {
                renderer.useTracer(tracer);
                renderer.traceRayPass(camera, type, sample, stats);
                renderer.useTracer(nullptr);
                uint64_t count = 0;
                for (const Hit& h : renderer.readHits(0)) count += h.triangleId != CHCRT_NO_HIT_ID;
                return count;
            };
            for (const Ray& r : renderer.readRays(0)) rays += r.tmax > r.tmin;
            pureHits += hitsWith(nullptr);
            frontHits += hitsWith(&frontTracer);
            startHits += hitsWith(&startTracer);
            bothHits += hitsWith(&bothTracer);
        }
    }
    EXPECT_GT(rays, 4000u);
    // Nothing to hit on a convex surface but grazing rays at the silhouette (offset origins; measured 2).
    EXPECT_LE(pureHits, rays / 1000);
    // The paper's rule darkens the sphere (measured 6,726 of 12,276 rays), faces=front does not (measured 0),
    // faces=front-start (the default) keeps what the neighbouring nodes add (measured 26).
    EXPECT_GT(bothHits, rays / 10);
    EXPECT_LE(frontHits, pureHits + rays / 1000) << "front " << frontHits << " both " << bothHits << " of " << rays;
    EXPECT_LE(startHits * 50, bothHits) << "front-start " << startHits << " both " << bothHits;
    std::printf("convex sphere: %llu rays, candidate hits faces=both %llu, front-start %llu, front %llu\n",
                static_cast<unsigned long long>(rays), static_cast<unsigned long long>(bothHits),
                static_cast<unsigned long long>(startHits), static_cast<unsigned long long>(frontHits));
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

// (Not plane-and-box: its few triangles end the cut in leaves already at depth 3.)
INSTANTIATE_TEST_SUITE_P(ProceduralScenes, LineSpaceLeafTestVariantTest,
                         ::testing::Values(TraceCase{"city:30k", 6, 10}, TraceCase{"interior:30k", 6, 10},
                                           TraceCase{"plant:30k", 3, 9}),
                         caseName);

} // namespace
} // namespace chcrt::test
