// CHC+RT's cost debug image (ChcrtDebugImage::Cost: BVH traversal steps per pixel summed over all subtree passes,
// bit 31 = capped) against what is exactly derivable from pure BVH tracing, its oracle. With the whole BVH as one
// termination subtree and loose query bounds (the query tests the root box itself), every active ray whose tile
// is visible traverses that one subtree exactly once (terminal tiles are disjoint; lazy re-queries intersect
// nothing), and a tile is invisible only when none of its rays passes the root box test that traversal counts
// nothing before; so the per-pixel steps equal the pure tracer's cost target (inner nodes + leaves + triangles),
// over warm frames too. With many subtrees the counts are not comparable (subtree roots are re-tested, upper
// levels skipped), but hits stay exact and every hit pixel did at least one leaf and one triangle test.
#include "tests/render/render_fixture.h"

#include "culling/chcrt_tracer.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <bit>
#include <cstring>

namespace chcrt::test {
namespace {

// The pure tracer's cost target of hit set 0 (inner nodes, leaves, triangles, capped), GL rows bottom to top.
std::vector<glm::uvec4> readCostTarget(const Renderer& renderer) {
    return readUvec4Image(renderer.targets().hits[0].cost.id(), renderer.settings().width, renderer.settings().height);
}

bool isActive(const Ray& ray) { return ray.tmax > ray.tmin; } // as the shaders test it

class ChcrtCostImageTest : public RenderTest {};

TEST_F(ChcrtCostImageTest, SingleSubtreeCostEqualsPureBvhCostPerPixel) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 64; // the whole BVH is one termination subtree
    options.pairs.minTileSize = 16;
    options.tighterBounds = false; // queries test the subtree root's box, exactly traversal's first test
    options.adaptive = true;       // a selected debug image must turn the fallback off (checked below)
    ChcrtTracer chcrt(bvh_, options);
    ASSERT_EQ(chcrt.hierarchy().subtrees.size(), 1u);
    chcrt.setDebugImage(ChcrtDebugImage::Cost);
    const CameraPath path = proceduralNearPath(spec_);

    uint64_t hitPixels = 0, costlyPixels = 0;
    for (int frame = 0; frame < 3; ++frame) { // frames 1 and 2 start from the previous fronts (Phase 1)
        const Camera camera = path.cameraAtFrame(frame * 2);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow}) {
            renderer.generateRayPass(camera, type, 0, stats);
            const std::vector<Ray> rays = renderer.readRays(0);
            renderer.useTracer(nullptr);
            renderer.traceRayPass(camera, type, 0, stats);
            const std::vector<Hit> reference = renderer.readHits(0);
            const std::vector<glm::uvec4> pureCost = readCostTarget(renderer);
            renderer.useTracer(&chcrt);
            chcrt.clearDebugImage();
            renderer.traceRayPass(camera, type, 0, stats);
            renderer.useTracer(nullptr);
            EXPECT_EQ(chcrt.lastStats().fallbackTraces, 0u);
            const std::vector<Hit> culled = renderer.readHits(0);
            const std::vector<uint32_t> cost = chcrt.readDebugImage();
            ASSERT_EQ(cost.size(), reference.size());
            ASSERT_EQ(pureCost.size(), reference.size());
            size_t differingHits = 0, differingCost = 0;
            for (size_t i = 0; i < cost.size(); ++i) {
                if (!sameHit(reference[i], culled[i], isAnyHit(type))) ++differingHits;
                const glm::uvec4& p = pureCost[i];
                ASSERT_EQ(p.w, 0u); // no capped rays: both counts are complete
                EXPECT_EQ(cost[i] & CHCRT_TRACE_STEPS_CAPPED, 0u) << i;
                if (cost[i] != p.x + p.y + p.z && ++differingCost <= 5) {
                    ADD_FAILURE() << toString(type) << " frame " << frame * 2 << " pixel " << i << ": chcrt "
                                  << cost[i] << " steps, pure BVH " << p.x << " + " << p.y << " + " << p.z;
                }
                if (!isActive(rays[i])) {
                    EXPECT_EQ(cost[i], 0u) << "inactive ray, pixel " << i;
                }
                if (culled[i].triangleId != CHCRT_NO_HIT_ID) {
                    EXPECT_GE(cost[i], 2u) << "a hit needs a leaf and a triangle test, pixel " << i;
                    ++hitPixels;
                }
                costlyPixels += cost[i] > 0;
            }
            EXPECT_EQ(differingHits, 0u) << toString(type) << " frame " << frame * 2;
            EXPECT_EQ(differingCost, 0u) << toString(type) << " frame " << frame * 2;
        }
        EXPECT_EQ(stats.cappedRays, 0u);
    }
    EXPECT_GT(hitPixels, 0u);
    EXPECT_GT(costlyPixels, hitPixels); // misses that entered the scene box cost something too
    // Culling happened (some tiles invisible), so the equality is not that of one full-screen pass.
    EXPECT_GT(chcrt.totalStats().queries, 1u);
    EXPECT_GT(chcrt.totalStats().subtreesScheduled, 1u);
}

// A debug trace's time includes the instrumentation (and `bench --steps` adds such traces next to timed ones), so it
// must not become a sample of culling's cost. The rule traces culled until culling's time is known, then measures a
// pure pass: after three warm debug traces the first plain trace must still cull.
TEST_F(ChcrtCostImageTest, DebugTracesDoNotFeedTheAdaptiveChoice) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    ChcrtOptions options;
    options.adaptive = true;
    ChcrtTracer chcrt(bvh_, options);
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Primary, stats);
    renderer.useTracer(&chcrt);
    chcrt.setDebugImage(ChcrtDebugImage::Cost);
    for (int i = 0; i < 4; ++i) { // one cold trace, three warm ones
        renderer.traceRayPass(camera, RayType::Primary, 0, stats);
        EXPECT_EQ(chcrt.lastStats().fallbackTraces, 0u);
    }
    chcrt.setDebugImage(ChcrtDebugImage::None);
    // The choice starts as if nothing had run: the pure pass four times (the first two are not counted), then
    // culling, whose time is still unknown. Had the (slow, instrumented) debug traces been counted as culling's time,
    // the fifth trace would be a pure pass again.
    for (uint64_t expected : {1u, 1u, 1u, 1u, 0u}) {
        renderer.traceRayPass(camera, RayType::Primary, 0, stats);
        EXPECT_EQ(chcrt.lastStats().fallbackTraces, expected) << "debug traces were counted as culling's time";
    }
    renderer.useTracer(nullptr);
}

TEST_F(ChcrtCostImageTest, ManySubtreesKeepHitsExactAndCountEveryPass) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer& renderer = makeProceduralRenderer("interior:30k", settings);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 6;
    options.pairs.minTileSize = 16;
    options.adaptive = false;
    ChcrtTracer chcrt(bvh_, options);
    ASSERT_GT(chcrt.hierarchy().subtrees.size(), 8u);
    const CameraPath path = proceduralNearPath(spec_);
    const Camera camera = path.cameraAtFrame(0);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    for (RayType type : {RayType::Primary, RayType::Ao}) {
        renderer.generateRayPass(camera, type, 0, stats);
        const std::vector<Ray> rays = renderer.readRays(0);
        renderer.useTracer(nullptr);
        renderer.traceRayPass(camera, type, 0, stats);
        const std::vector<Hit> reference = renderer.readHits(0);
        // The same cold trace twice: first with the Batches image, which tells the pixels some subtree pass
        // covered, then with the Cost image. A pixel no pass covered has no steps.
        renderer.useTracer(&chcrt);
        chcrt.resetVisibility();
        chcrt.setDebugImage(ChcrtDebugImage::Batches);
        chcrt.clearDebugImage();
        renderer.traceRayPass(camera, type, 0, stats);
        const std::vector<uint32_t> batches = chcrt.readDebugImage();
        chcrt.resetVisibility(); // the same passes again (the same cold start)
        chcrt.setDebugImage(ChcrtDebugImage::Cost);
        chcrt.clearDebugImage();
        renderer.traceRayPass(camera, type, 0, stats);
        renderer.useTracer(nullptr);
        const std::vector<Hit> culled = renderer.readHits(0);
        const std::vector<uint32_t> cost = chcrt.readDebugImage();
        ASSERT_EQ(cost.size(), reference.size());
        size_t differingHits = 0;
        uint64_t hitPixels = 0;
        for (size_t i = 0; i < cost.size(); ++i) {
            if (!sameHit(reference[i], culled[i], isAnyHit(type))) ++differingHits;
            EXPECT_EQ(cost[i] & CHCRT_TRACE_STEPS_CAPPED, 0u) << i;
            if (!isActive(rays[i])) {
                EXPECT_EQ(cost[i], 0u) << "inactive ray, pixel " << i;
            }
            if (batches[i] == 0) {
                EXPECT_EQ(cost[i], 0u) << "no subtree pass covered pixel " << i;
            }
            if (culled[i].triangleId != CHCRT_NO_HIT_ID) {
                ++hitPixels;
                EXPECT_GE(cost[i], 2u) << "a hit needs a leaf and a triangle test, pixel " << i;
            }
        }
        EXPECT_EQ(differingHits, 0u) << toString(type);
        EXPECT_GT(hitPixels, cost.size() / 20) << toString(type);
    }
    EXPECT_EQ(stats.cappedRays, 0u);
}

TEST_F(ChcrtCostImageTest, CountSaturatesBelowTheCappedBit) {
    // A count near 2^31 (a pre-filled image stands in for very many passes) must stop at 2^31 - 1 instead of
    // carrying into bit 31, which would read as capped. One subtree: the added steps are pure BVH's.
    RenderSettings settings;
    settings.width = 48;
    settings.height = 32;
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 64;
    options.pairs.minTileSize = 16;
    options.tighterBounds = false;
    options.adaptive = false;
    ChcrtTracer chcrt(bvh_, options);
    ASSERT_EQ(chcrt.hierarchy().subtrees.size(), 1u);
    chcrt.setDebugImage(ChcrtDebugImage::Cost);
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Primary, stats);
    renderer.traceRayPass(camera, RayType::Primary, 0, stats);
    const std::vector<glm::uvec4> pureCost = readCostTarget(renderer);
    renderer.useTracer(&chcrt);
    renderer.traceRayPass(camera, RayType::Primary, 0, stats); // creates the debug texture
    constexpr uint32_t kStart = CHCRT_TRACE_STEPS_COUNT - 40u;
    glClearTexImage(chcrt.debugTexture(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &kStart);
    renderer.traceRayPass(camera, RayType::Primary, 0, stats);
    renderer.useTracer(nullptr);
    const std::vector<uint32_t> cost = chcrt.readDebugImage();
    ASSERT_EQ(cost.size(), pureCost.size());
    uint64_t saturated = 0, below = 0;
    for (size_t i = 0; i < cost.size(); ++i) {
        const uint64_t steps = uint64_t(pureCost[i].x) + pureCost[i].y + pureCost[i].z;
        const uint64_t expected = std::min<uint64_t>(kStart + steps, CHCRT_TRACE_STEPS_COUNT);
        EXPECT_EQ(cost[i], expected) << "pixel " << i << ", " << steps << " steps";
        saturated += expected == CHCRT_TRACE_STEPS_COUNT;
        below += expected < CHCRT_TRACE_STEPS_COUNT && steps > 0;
    }
    EXPECT_GT(saturated, 0u); // both cases occurred
    EXPECT_GT(below, 0u);
}

TEST_F(ChcrtCostImageTest, CappedPassesSetTheFlagAndTheCountStaysBelowIt) {
    // A low loop cap (the host may override CHCRT_TRACE_ITERATION_CAP through the subtree defines) caps many rays:
    // exactly the pixels the shader's capped-ray counter counted carry bit 31, with their steps below it.
    RenderSettings settings;
    settings.width = 48;
    settings.height = 32;
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 64; // one subtree: each pixel is traversed at most once
    options.pairs.minTileSize = 16;
    options.adaptive = false;
    constexpr uint32_t kCap = 24;
    options.subtreeDefines = [](bool) {
        return std::vector<ShaderDefine>{{"CHCRT_TRACE_ITERATION_CAP", std::to_string(kCap) + "u"}};
    };
    ChcrtTracer chcrt(bvh_, options);
    ASSERT_EQ(chcrt.hierarchy().subtrees.size(), 1u);
    chcrt.setDebugImage(ChcrtDebugImage::Cost);
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Primary, stats);
    renderer.useTracer(&chcrt);
    chcrt.clearDebugImage();
    FrameStats traceStats;
    renderer.traceRayPass(camera, RayType::Primary, 0, traceStats);
    renderer.useTracer(nullptr);
    const std::vector<uint32_t> cost = chcrt.readDebugImage();
    uint64_t capped = 0;
    for (uint32_t v : cost) {
        if ((v & CHCRT_TRACE_STEPS_CAPPED) == 0) continue;
        ++capped;
        EXPECT_GE(v & CHCRT_TRACE_STEPS_COUNT, 1u);
        EXPECT_LE(v & CHCRT_TRACE_STEPS_COUNT, kCap);
    }
    EXPECT_GT(capped, 0u);
    EXPECT_EQ(capped, traceStats.cappedRays);
    // Capped pixels are magenta in the colourised image.
    const std::vector<float> rgb =
        colorizeChcrtDebugImage(ChcrtDebugImage::Cost, cost, settings.width, settings.height);
    for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
            const uint32_t v = cost[size_t(settings.height - 1 - y) * settings.width + size_t(x)];
            const float* c = &rgb[(size_t(y) * settings.width + size_t(x)) * 3];
            if (v & CHCRT_TRACE_STEPS_CAPPED) {
                EXPECT_EQ(glm::vec3(c[0], c[1], c[2]), glm::vec3(1.0f, 0.0f, 1.0f)) << x << "," << y;
            }
        }
    }
}

// The bounds image (ChcrtDebugImage::Bounds): one value per grid cell, 0 exactly where no ray is active, the largest
// segment end of the cell's rays otherwise, and the same whether the CPU (bounds-only) or the GPU (bounds-gpu) decides
// the lists: both read the same reduction.
TEST_F(ChcrtCostImageTest, TheBoundsImageHoldsEachCellsExtentInEitherBoundsMode) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Shadow, stats);
    const std::vector<Ray> rays = renderer.readRays(0);
    std::vector<std::vector<uint32_t>> images;
    for (ChcrtQueries queries : {ChcrtQueries::BoundsOnly, ChcrtQueries::BoundsGpu}) {
        ChcrtOptions options;
        options.partition.maxSubtreeHeight = 8;
        options.adaptive = false;
        options.queries = queries;
        ChcrtTracer chcrt(bvh_, options);
        chcrt.setDebugImage(ChcrtDebugImage::Bounds);
        renderer.useTracer(&chcrt);
        renderer.traceRayPass(camera, RayType::Shadow, 0, stats);
        renderer.useTracer(nullptr);
        images.push_back(chcrt.readDebugImage());
    }
    ASSERT_EQ(images[0].size(), rays.size());
    EXPECT_EQ(images[0], images[1]);
    const int cell = RayBoundsOptions{}.cellSize;
    size_t bounded = 0;
    for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
            const uint32_t v = images[0][size_t(y) * size_t(settings.width) + size_t(x)];
            EXPECT_EQ(v, images[0][size_t(y / cell * cell) * size_t(settings.width) + size_t(x / cell * cell)]);
            bool anyActive = false; // in this pixel's cell
            float longest = 0.0f;   // the largest tmax of the cell's active rays
            for (int cy = y / cell * cell; cy < std::min(settings.height, (y / cell + 1) * cell); ++cy) {
                for (int cx = x / cell * cell; cx < std::min(settings.width, (x / cell + 1) * cell); ++cx) {
                    const Ray& ray = rays[size_t(cy) * size_t(settings.width) + size_t(cx)];
                    anyActive = anyActive || isActive(ray);
                    if (isActive(ray)) longest = std::max(longest, ray.tmax);
                }
            }
            if (!anyActive) {
                EXPECT_EQ(v, 0u) << x << ", " << y;
                continue;
            }
            ASSERT_NE(v, 0u) << x << ", " << y;
            if (v == 0xFFFFFFFFu) continue;
            ++bounded;
            // A shadow segment ends at the light or where it leaves the scene: never beyond its tmax (the value is
            // rounded up by 2^-10).
            EXPECT_LE(std::bit_cast<float>(v), longest * 1.01f) << x << ", " << y;
        }
    }
    EXPECT_GT(bounded, rays.size() / 4);
}

} // namespace
} // namespace chcrt::test
