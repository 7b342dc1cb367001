// RayBoundsGrid's GPU reduction (shaders/culling/ray_bounds.comp.glsl) against the rays it reduced: random bounded,
// inactive, infinite and NaN rays over a ray set whose size is not a multiple of the cell; segments clipped to the
// scene's box; closest-hit segments ending at their hits and any-hit rays with a hit left out.
#include "culling/camera_ray_bounds.h"
#include "culling/ray_bounds_grid.h"
#include "tests/render/render_fixture.h"
#include "renderer/gl/context.h"
#include "renderer/render/trace_pass.h"
#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/culling_layout.h"

#include <gtest/gtest.h>

#include <bit>
#include <limits>
#include <random>

namespace chcrt {
namespace {

constexpr int kW = 45, kH = 37, kCell = 16; // 3 × 3 cells, partial at the edges
const glm::vec3 kSceneMin(-40.0f), kSceneMax(40.0f);

struct RaySet {
    std::vector<glm::vec4> origins = std::vector<glm::vec4>(size_t(kW) * kH);
    std::vector<glm::vec4> directions = std::vector<glm::vec4>(size_t(kW) * kH);
    std::vector<glm::uvec4> hits = std::vector<glm::uvec4>(size_t(kW) * kH);
    GlTexture origin, direction, hit;

    RaySet() {
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(-50.0f, 50.0f), t(0.0f, 5.0f), coin(0.0f, 1.0f);
        for (size_t i = 0; i < origins.size(); ++i) {
            const float tmin = t(rng) * 0.01f;
            origins[i] = glm::vec4(u(rng) * 0.5f, u(rng) * 0.5f, u(rng) * 0.5f, tmin);
            directions[i] = glm::vec4(glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.01f)), tmin + 20.0f * t(rng));
            const auto miss = missHitTexel();
            hits[i] = coin(rng) < 0.5f ? glm::uvec4(miss[0], miss[1], miss[2], miss[3])
                                       : glm::uvec4(std::bit_cast<uint32_t>(tmin + t(rng)), 7u, 0u, 0u);
        }
        // Cell (1, 1): inactive rays only. Cell (2, 0): one infinite tmax. Cell (0, 2): one NaN origin.
        for (int y = kCell; y < 2 * kCell; ++y)
            for (int x = kCell; x < 2 * kCell; ++x) directions[size_t(y) * kW + x].w = origins[size_t(y) * kW + x].w;
        directions[size_t(3) * kW + 2 * kCell + 1].w = std::numeric_limits<float>::infinity();
        origins[size_t(2 * kCell + 1) * kW + 3].x = std::numeric_limits<float>::quiet_NaN();
        origin = createTexture2D(kW, kH, GL_RGBA32F);
        direction = createTexture2D(kW, kH, GL_RGBA32F);
        hit = createTexture2D(kW, kH, GL_RGBA32UI);
        glTextureSubImage2D(origin.id(), 0, 0, 0, kW, kH, GL_RGBA, GL_FLOAT, origins.data());
        glTextureSubImage2D(direction.id(), 0, 0, 0, kW, kH, GL_RGBA, GL_FLOAT, directions.data());
        glTextureSubImage2D(hit.id(), 0, 0, 0, kW, kH, GL_RGBA_INTEGER, GL_UNSIGNED_INT, hits.data());
    }
    bool valid(size_t i) const {
        return directions[i].w > origins[i].w && !std::isnan(origins[i].x) && !std::isinf(directions[i].w);
    }
};

bool insideScene(glm::vec3 p, glm::vec3 lower = kSceneMin, glm::vec3 upper = kSceneMax) {
    return glm::all(glm::greaterThanEqual(p, lower)) && glm::all(glm::lessThanEqual(p, upper));
}

// Every point of every ray's (shortened) segment inside the scene's box must be reachable from its pixel.
void expectSegmentsReachable(const RayBoundsGrid& grid, const RaySet& rays, bool withHits, bool anyHit) {
    for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
            const size_t i = size_t(y) * kW + x;
            if (!rays.valid(i)) continue;
            const bool hit = rays.hits[i].y != CHCRT_NO_HIT_ID;
            if (withHits && anyHit && hit) continue;
            const glm::vec4 o = rays.origins[i], d = rays.directions[i];
            const float end = withHits && hit ? std::bit_cast<float>(rays.hits[i].x) : d.w;
            for (int s = 0; s <= 16; ++s) {
                const glm::vec3 p = glm::vec3(o) + glm::vec3(d) * (o.w + (end - o.w) * float(s) / 16.0f);
                if (!insideScene(p)) continue;
                ASSERT_TRUE(grid.mayReach(Tile{x, y, 1, 1}, &p, &p, 1)) << x << ", " << y << " step " << s;
            }
        }
    }
}

TEST(RayBoundsGridGl, EverySegmentIsCoveredAndNothingFarFromThem) {
    auto context = createHeadlessContext(GlBackend::Egl, true);
    RaySet rays;
    for (int variant = 0; variant < 3; ++variant) {
        const bool withHits = variant > 0, anyHit = variant == 2;
        SCOPED_TRACE(variant);
        RayBoundsGrid grid(RayBoundsOptions{kCell, 4, 2});
        grid.update(rays.origin.id(), rays.direction.id(), withHits ? rays.hit.id() : 0, anyHit, kW, kH, kSceneMin,
                    kSceneMax);
        ASSERT_EQ(grid.cellsX(), 3);
        ASSERT_EQ(grid.cellsY(), 3);
        expectSegmentsReachable(grid, rays, withHits, anyHit);
        // Outside the scene's box nothing is reachable from a bounded cell; an infinite or NaN value reaches all.
        const glm::vec3 far(1000.0f), farUpper(1001.0f);
        EXPECT_FALSE(grid.mayReach(Tile{0, 0, kCell, kCell}, &far, &farUpper, 1));
        EXPECT_FALSE(grid.mayReach(Tile{kCell, kCell, kCell, kCell}, &far, &farUpper, 1)); // inactive only
        EXPECT_EQ(grid.cell(1, 1).state, 0);
        EXPECT_TRUE(grid.mayReach(Tile{2 * kCell, 0, kCell, kCell}, &far, &farUpper, 1)); // infinite tmax
        EXPECT_TRUE(grid.mayReach(Tile{0, 2 * kCell, kCell, kCell}, &far, &farUpper, 1)); // NaN origin
        EXPECT_FALSE(grid.mayReach(Tile{2 * kCell, 2 * kCell, kW, kH}, &far, &farUpper, 1)); // partial edge cell
    }
}

TEST(RayBoundsGridGl, HitsShortenTheSegmentsAndFinishAnyHitRays) {
    auto context = createHeadlessContext(GlBackend::Egl, true);
    RaySet rays;
    // Cell (0, 0): coherent rays along +x from near the origin, each hitting at t = 1 of a segment of 30.
    for (int y = 0; y < kCell; ++y) {
        for (int x = 0; x < kCell; ++x) {
            const size_t i = size_t(y) * kW + x;
            rays.origins[i] = glm::vec4(0.0f, 0.01f * float(x), 0.01f * float(y), 0.0f);
            rays.directions[i] = glm::vec4(1.0f, 0.0f, 0.0f, 30.0f);
            rays.hits[i] = glm::uvec4(std::bit_cast<uint32_t>(1.0f), 3u, 0u, 0u);
        }
    }
    glTextureSubImage2D(rays.origin.id(), 0, 0, 0, kW, kH, GL_RGBA, GL_FLOAT, rays.origins.data());
    glTextureSubImage2D(rays.direction.id(), 0, 0, 0, kW, kH, GL_RGBA, GL_FLOAT, rays.directions.data());
    glTextureSubImage2D(rays.hit.id(), 0, 0, 0, kW, kH, GL_RGBA_INTEGER, GL_UNSIGNED_INT, rays.hits.data());
    RayBoundsGrid own(RayBoundsOptions{kCell, 4, 2}), closest(RayBoundsOptions{kCell, 4, 2}), any(RayBoundsOptions{kCell, 4, 2});
    own.update(rays.origin.id(), rays.direction.id(), 0, false, kW, kH, kSceneMin, kSceneMax);
    closest.update(rays.origin.id(), rays.direction.id(), rays.hit.id(), false, kW, kH, kSceneMin, kSceneMax);
    any.update(rays.origin.id(), rays.direction.id(), rays.hit.id(), true, kW, kH, kSceneMin, kSceneMax);
    // A point 10 units along a ray of the cell: on its own segment, beyond its hit.
    const glm::vec3 p = glm::vec3(rays.origins[0]) + glm::vec3(rays.directions[0]) * (rays.origins[0].w + 10.0f);
    const glm::vec3 lo = p - glm::vec3(0.01f), hi = p + glm::vec3(0.01f);
    ASSERT_TRUE(insideScene(p));
    EXPECT_TRUE(own.cellMayReach(0, 0, &lo, &hi, 1));
    EXPECT_FALSE(closest.cellMayReach(0, 0, &lo, &hi, 1)) << "beyond every hit of the cell";
    EXPECT_EQ(any.cell(0, 0).state, 0) << "any-hit rays with a hit are finished";
    expectSegmentsReachable(closest, rays, true, false);
}

// With the hint pass's marks (CHCRT_CULLING_COMPACT_CELLS layout: a mark per cell, a dispatch command and count, the
// marked cells in the order they were marked) only the listed cells are reduced, each exactly as without marks, and
// every other cell is empty — also in a grid whose previous reduction had filled them.
TEST(RayBoundsGridGl, MarkedCellsAloneAreReducedAsWithoutMarks) {
    auto context = createHeadlessContext(GlBackend::Egl, true);
    RaySet rays;
    const int cells = 9;
    const std::vector<int> listed = {7, 2, 0}; // cells (1, 2), (2, 0), (0, 0)
    std::vector<uint32_t> marks(CHCRT_CULLING_MARKED_UINTS(cells), 0u);
    for (size_t k = 0; k < listed.size(); ++k) {
        marks[size_t(listed[k])] = 1u;
        marks[CHCRT_CULLING_MARKED_LIST(cells) + k] = uint32_t(listed[k]);
    }
    marks[CHCRT_CULLING_MARKED_HEADER(cells)] = 1u; // work groups
    marks[CHCRT_CULLING_MARKED_HEADER(cells) + 1] = marks[CHCRT_CULLING_MARKED_HEADER(cells) + 2] = 1u;
    marks[CHCRT_CULLING_MARKED_HEADER(cells) + 3] = uint32_t(listed.size());
    const GlBuffer markBuffer = createBuffer(marks.size() * 4, marks.data(), 0);
    for (bool anyHit : {false, true}) {
        SCOPED_TRACE(anyHit);
        RayBoundsGrid all(RayBoundsOptions{kCell, 4, 2}), marked(RayBoundsOptions{kCell, 4, 2});
        all.update(rays.origin.id(), rays.direction.id(), rays.hit.id(), anyHit, kW, kH, kSceneMin, kSceneMax);
        marked.update(rays.origin.id(), rays.direction.id(), rays.hit.id(), anyHit, kW, kH, kSceneMin, kSceneMax);
        marked.update(rays.origin.id(), rays.direction.id(), rays.hit.id(), anyHit, kW, kH, kSceneMin, kSceneMax,
                      markBuffer.id());
        for (int c = 0; c < cells; ++c) {
            const RayBoundsGrid::CellBoxes &a = all.cell(c % 3, c / 3), &m = marked.cell(c % 3, c / 3);
            if (marks[size_t(c)] == 0u) {
                EXPECT_EQ(m.state, 0) << "cell " << c << " is not marked";
                continue;
            }
            ASSERT_NE(a.state, 0) << "cell " << c;
            EXPECT_EQ(m.state, a.state) << "cell " << c;
            EXPECT_EQ(m.originLower, a.originLower) << "cell " << c;
            EXPECT_EQ(m.originUpper, a.originUpper) << "cell " << c;
            EXPECT_EQ(m.lower, a.lower) << "cell " << c;
            EXPECT_EQ(m.upper, a.upper) << "cell " << c;
            EXPECT_EQ(m.directionLower, a.directionLower) << "cell " << c;
            EXPECT_EQ(m.segmentEnd, a.segmentEnd) << "cell " << c;
        }
    }
}

// Shadow rays of a light sweep (TraceRequest::lightSweep): cells around every surface point's segments to the whole
// light box hold every segment from those points to any point of the light — of active rays and of inactive ones that
// kept their origin (an all-zero direction texel), which another ray set of the frame may trace —, through the pieces
// and the frustum alike; pixels without a surface point (sky) add nothing, a NaN origin makes its cell unbounded, and
// nothing beyond the light or behind the points is reached.
TEST(RayBoundsGridGl, LightSweepCellsHoldEverySegmentFromEverySurfacePointToTheLight) {
    auto context = createHeadlessContext(GlBackend::Egl, true);
    RaySet rays;
    const glm::vec3 lightMin(-12.0f, 30.0f, -6.0f), lightMax(4.0f, 30.0f, 9.0f); // a flat light above the points
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), spread(-20.0f, 20.0f);
    const auto lightPoint = [&](float u, float v) {
        return glm::vec3(lightMin.x + u * (lightMax.x - lightMin.x), lightMin.y, lightMin.z + v * (lightMax.z - lightMin.z));
    };
    enum Kind { Active, KeptOrigin, Sky };
    std::vector<Kind> kinds(rays.origins.size());
    for (size_t i = 0; i < rays.origins.size(); ++i) {
        const glm::vec3 origin(spread(rng), spread(rng) * 0.25f, spread(rng));
        const float pick = unit(rng);
        kinds[i] = pick < 0.6f ? Active : pick < 0.9f ? KeptOrigin : Sky;
        if (kinds[i] == Sky) {
            rays.origins[i] = glm::vec4(0.0f);
            rays.directions[i] = glm::vec4(0.0f, 0.0f, 1.0f, 0.0f);
        } else if (kinds[i] == KeptOrigin) {
            rays.origins[i] = glm::vec4(origin, 0.0f);
            rays.directions[i] = glm::vec4(0.0f);
        } else {
            const glm::vec3 toLight = lightPoint(unit(rng), unit(rng)) - origin;
            const float distance = glm::length(toLight);
            rays.origins[i] = glm::vec4(origin, 0.0f);
            rays.directions[i] = glm::vec4(toLight / distance, distance);
        }
    }
    // Cell (1, 1): sky only. Cell (2, 2): one kept origin is NaN.
    for (int y = kCell; y < 2 * kCell; ++y) {
        for (int x = kCell; x < 2 * kCell; ++x) {
            const size_t i = size_t(y) * kW + x;
            kinds[i] = Sky;
            rays.origins[i] = glm::vec4(0.0f);
            rays.directions[i] = glm::vec4(0.0f, 0.0f, 1.0f, 0.0f);
        }
    }
    const size_t nan = size_t(2 * kCell + 2) * kW + 2 * kCell + 2;
    kinds[nan] = KeptOrigin;
    rays.origins[nan] = glm::vec4(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f, 0.0f);
    rays.directions[nan] = glm::vec4(0.0f);
    glTextureSubImage2D(rays.origin.id(), 0, 0, 0, kW, kH, GL_RGBA, GL_FLOAT, rays.origins.data());
    glTextureSubImage2D(rays.direction.id(), 0, 0, 0, kW, kH, GL_RGBA, GL_FLOAT, rays.directions.data());
    for (bool frustum : {true, false}) {
        SCOPED_TRACE(frustum);
        RayBoundsOptions options{kCell, 4, 2};
        options.frustum = frustum;
        RayBoundsGrid grid(options);
        grid.updateLightSweep(rays.origin.id(), rays.direction.id(), kW, kH, kSceneMin, kSceneMax, lightMin, lightMax);
        EXPECT_EQ(grid.cell(1, 1).state, 0) << "sky only";
        EXPECT_EQ(grid.cell(2, 2).state, 2) << "a NaN origin";
        size_t checked = 0;
        for (int y = 0; y < kH; ++y) {
            for (int x = 0; x < kW; ++x) {
                const size_t i = size_t(y) * kW + x;
                if (kinds[i] == Sky || i == nan) continue;
                ASSERT_EQ(grid.cell(x / kCell, y / kCell).state, (x / kCell == 2 && y / kCell == 2) ? 2 : 1);
                const glm::vec3 o(rays.origins[i]);
                for (int k = 0; k < 6; ++k) { // the light's corners, then random points on it
                    const glm::vec3 target = k < 4 ? lightPoint(float(k & 1), float(k >> 1)) : lightPoint(unit(rng), unit(rng));
                    for (int step = 0; step <= 16; ++step) {
                        const glm::vec3 p = o + (target - o) * (float(step) / 16.0f);
                        ASSERT_TRUE(grid.mayReach(Tile{x, y, 1, 1}, &p, &p, 1))
                            << x << ", " << y << " light point " << k << " step " << step;
                        ++checked;
                    }
                }
            }
        }
        EXPECT_GT(checked, 20000u);
        // Beyond the light and below every point: out of reach of every bounded cell.
        const glm::vec3 above(-4.0f, 34.0f, 1.0f), aboveUpper(-3.0f, 35.0f, 2.0f);
        const glm::vec3 below(-4.0f, -30.0f, 1.0f), belowUpper(-3.0f, -29.0f, 2.0f);
        for (int cy = 0; cy < 3; ++cy) {
            for (int cx = 0; cx < 3; ++cx) {
                if (grid.cell(cx, cy).state != 1) continue;
                EXPECT_FALSE(grid.cellMayReach(cx, cy, &above, &aboveUpper, 1)) << cx << ", " << cy;
                EXPECT_FALSE(grid.cellMayReach(cx, cy, &below, &belowUpper, 1)) << cx << ", " << cy;
            }
        }
    }
}

// The bounds made from the camera (camera_ray_bounds.h) hold what the GPU reduction makes of the renderer's own
// primary rays (the ray generation shader's arithmetic, whatever the driver does with it): per cell, every end point
// box, the direction box and the segment range, before the grid's padding, within a sixteenth of that padding. Near and
// far views of a city, partial cells at the edges, several cell sizes and piece counts.
using CameraRayBoundsGl = test::RenderTest;

TEST_F(CameraRayBoundsGl, HoldTheReductionOfTheRenderersPrimaryRays) {
    RenderSettings settings;
    settings.width = 75;
    settings.height = 53;
    Renderer& renderer = makeProceduralRenderer("city:20k", settings);
    const glm::vec3 boxMin(bvh_.nodes[0].boundsMin), boxMax(bvh_.nodes[0].boundsMax);
    size_t bounded = 0;
    for (const CameraPath& path : {proceduralNearPath(spec_), proceduralFarPath(spec_)}) {
        for (int frame : {0, 5}) {
            const Camera camera = path.cameraAtFrame(frame);
            FrameStats stats;
            renderer.generateRayPass(camera, RayType::Primary, 0, stats);
            const RayTextures& rays = renderer.targets().rays[0];
            const PrimaryRayBasis basis =
                primaryRayBasis(makeCameraFrame(camera, settings.width, settings.height), settings.width, settings.height);
            for (auto [cellSize, pieces] : {std::pair{16, 4}, std::pair{8, 3}, std::pair{4, 8}}) {
                SCOPED_TRACE(path.name + " frame " + std::to_string(frame) + " cell " + std::to_string(cellSize));
                RayBoundsGrid grid(RayBoundsOptions{cellSize, pieces, 2});
                grid.reduce(rays.origin.id(), rays.direction.id(), 0, false, settings.width, settings.height, boxMin,
                            boxMax);
                const size_t stride = size_t(CHCRT_CULLING_BOUNDS_STRIDE(pieces));
                const std::vector<glm::vec4> fromCamera = cameraRayBounds(basis, cellSize, pieces, boxMin, boxMax);
                std::vector<glm::vec4> reduced(fromCamera.size());
                glGetNamedBufferSubData(grid.buffer(), 0, GLsizeiptr(reduced.size() * sizeof(glm::vec4)), reduced.data());
                for (size_t c = 0; c < reduced.size() / stride; ++c) {
                    const glm::vec4* gpu = &reduced[c * stride];
                    const glm::vec4* cpu = &fromCamera[c * stride];
                    if (gpu[0].x == float(CHCRT_CULLING_CELL_EMPTY)) continue;
                    ASSERT_EQ(gpu[0].x, float(CHCRT_CULLING_CELL_BOUNDED)) << "cell " << c;
                    ASSERT_EQ(cpu[0].x, float(CHCRT_CULLING_CELL_BOUNDED)) << "cell " << c;
                    ++bounded;
                    EXPECT_GE(cpu[0].y, gpu[0].y * (1.0f - 1e-6f)) << "cell " << c; // the extent that sizes the pad
                    EXPECT_GE(cpu[0].z, gpu[0].z) << "cell " << c;
                    const float tolerance = std::max(1.0f, gpu[0].y) * RayBoundsOptions{}.relativePad / 16.0f;
                    for (int j = 0; j < pieces + 2; ++j) {
                        const glm::vec3 gpuLo(gpu[1 + 2 * j]), gpuHi(gpu[2 + 2 * j]);
                        const glm::vec3 cpuLo(cpu[1 + 2 * j]), cpuHi(cpu[2 + 2 * j]);
                        for (int i = 0; i < 3; ++i) {
                            EXPECT_LE(cpuLo[i], gpuLo[i] + tolerance) << "cell " << c << " point " << j << " axis " << i;
                            EXPECT_GE(cpuHi[i], gpuHi[i] - tolerance) << "cell " << c << " point " << j << " axis " << i;
                        }
                    }
                    const int interval = 1 + 2 * (pieces + 2);
                    for (int i = 0; i < 3; ++i) {
                        EXPECT_LE(cpu[interval][i], gpu[interval][i]) << "cell " << c << " direction axis " << i;
                        EXPECT_GE(cpu[interval + 1][i], gpu[interval + 1][i]) << "cell " << c << " direction axis " << i;
                    }
                    EXPECT_LE(cpu[interval].w, gpu[interval].w) << "cell " << c << " segment start";
                    EXPECT_GE(cpu[interval + 1].w, gpu[interval + 1].w) << "cell " << c << " segment end";
                }
            }
        }
    }
    EXPECT_GT(bounded, 500u);
}

// The bounds of AO rays from their G-buffer's surface frames (hemisphere_ray_bounds.h) hold the renderer's own AO
// rays (the ray generation shader's arithmetic, whatever the driver does with it): every point of every active ray's
// segment inside the scene's box is within reach of its pixel's cell, with a padding far below the grid's, for near and
// far views, several samples, rotation ranges and cell sizes; the frames reduced once from the first set's rays. The
// negative control bounds the same rays as if no pixel rotated its sample and must find points out of reach.
class RequestProbe final : public Tracer {
public:
    std::string name() const override { return "probe"; }
    void trace(const TraceRequest& request, const RayTextures&, HitTargets&, int, int, TraceStats&) override {
        last = request;
    }
    TraceRequest last;
};

using HemisphereRayBoundsGl = test::RenderTest;

TEST_F(HemisphereRayBoundsGl, CellsHoldEveryAoSegmentOfTheRenderersRaySets) {
    RenderSettings settings;
    settings.width = 75;
    settings.height = 53;
    Renderer& renderer = makeProceduralRenderer("city:20k", settings);
    const glm::vec3 boxMin(bvh_.nodes[0].boundsMin), boxMax(bvh_.nodes[0].boundsMax);
    RequestProbe probe;
    size_t checked = 0, outsideUnrotated = 0;
    for (const float rotationDegrees : {36.0f, 360.0f}) {
        settings.rotationDegrees = rotationDegrees;
        renderer.setSettings(settings);
        for (const CameraPath& path : {proceduralNearPath(spec_), proceduralFarPath(spec_)}) {
            const Camera camera = path.cameraAtFrame(3);
            FrameStats stats;
            renderer.renderGBuffer(camera, stats);
            for (auto [cellSize, pieces] : {std::pair{16, 4}, std::pair{8, 3}, std::pair{4, 8}}) {
                SCOPED_TRACE(path.name + " rotation " + std::to_string(rotationDegrees) + " cell " +
                             std::to_string(cellSize));
                RayBoundsOptions options{cellSize, pieces, 2};
                options.relativePad = 1e-6f;
                RayBoundsGrid grid(options), unrotated(options);
                SurfaceFrames frames;
                for (int sample = 0; sample < 4; ++sample) {
                    renderer.generateRayPass(camera, RayType::Ao, sample, stats);
                    renderer.useTracer(&probe);
                    renderer.traceRayPass(camera, RayType::Ao, sample, stats);
                    renderer.useTracer(nullptr);
                    ASSERT_TRUE(probe.last.hemisphereRays.has_value());
                    const TraceRequest::HemisphereRays set = *probe.last.hemisphereRays;
                    EXPECT_EQ(set.maxRotation, glm::radians(rotationDegrees));
                    const RayTextures& rays = renderer.targets().rays[0];
                    if (sample == 0) { // the frames are every set's, and both grids': reduced once, from the first
                        frames = grid.reduceSurfaceFrames(rays.origin.id(), rays.direction.id(), set.shadingNormals,
                                                          settings.width, settings.height);
                    }
                    grid.setHemisphereCells(frames, {set.sample, set.maxRotation, set.length}, boxMin, boxMax);
                    unrotated.setHemisphereCells(frames, {set.sample, 0.0f, set.length}, boxMin, boxMax);
                    std::vector<glm::vec4> origins(size_t(settings.width) * settings.height);
                    std::vector<glm::vec4> directions(origins.size());
                    glGetTextureImage(rays.origin.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(origins.size() * 16),
                                      origins.data());
                    glGetTextureImage(rays.direction.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(directions.size() * 16),
                                      directions.data());
                    for (int y = 0; y < settings.height; ++y) {
                        for (int x = 0; x < settings.width; ++x) {
                            const size_t i = size_t(y) * settings.width + x;
                            if (!(directions[i].w > origins[i].w)) continue;
                            ASSERT_EQ(directions[i].w, set.length);
                            const glm::vec3 o(origins[i]), d(directions[i]);
                            for (int step = 0; step <= 16; ++step) {
                                const glm::vec3 p = o + d * (set.length * float(step) / 16.0f);
                                if (!insideScene(p, boxMin, boxMax)) continue;
                                ASSERT_TRUE(grid.mayReach(Tile{x, y, 1, 1}, &p, &p, 1))
                                    << "pixel " << x << ", " << y << " sample " << sample << " step " << step;
                                outsideUnrotated += !unrotated.mayReach(Tile{x, y, 1, 1}, &p, &p, 1);
                                ++checked;
                            }
                        }
                    }
                }
            }
        }
    }
    EXPECT_GT(checked, 50000u);
    EXPECT_GT(outsideUnrotated, checked / 100);
}

} // namespace
} // namespace chcrt
