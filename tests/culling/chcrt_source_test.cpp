// CHC+RT through the §5.4 interface: a SubtreeSource that cannot hold every scheduled subtree at once (as an
// out-of-core cache) must still give exactly the hits of pure BVH tracing, in several residency rounds; one
// that cannot hold even one subtree is an error. Also the debug images (Figures 4 and 5) against the hits.
#include "tests/render/render_fixture.h"

#include "culling/bvh_subtree_source.h"
#include "culling/chcrt_tracer.h"
#include "renderer/core/error.h"


namespace chcrt::test {
namespace {

// Makes at most `capacity` of the requested subtrees resident per call (the first ones), like a full cache.
class LimitedSource final : public SubtreeSource {
public:
    LimitedSource(const CullingHierarchy& h, size_t capacity) : inCore_(h), capacity_(capacity) {}
    void acquire(std::span<const uint32_t> subtrees, std::span<uint32_t> gpuRoots) override {
        ++calls;
        const size_t n = std::min(capacity_, subtrees.size());
        inCore_.acquire(subtrees.first(n), gpuRoots.first(n));
        for (size_t i = n; i < subtrees.size(); ++i) gpuRoots[i] = kNotResident;
    }
    uint64_t calls = 0;

private:
    BvhSubtreeSource inCore_;
    size_t capacity_;
};

class ChcrtSourceTest : public RenderTest {
protected:
    ChcrtOptions smallOptions() const {
        ChcrtOptions options;
        options.partition.maxSubtreeHeight = 6;
        options.pairs.minTileSize = 16;
        options.adaptive = false;
        return options;
    }
    // Traces `type` with pure BVH and with `tracer` over 4 frames; returns the differing pixels.
    size_t compare(Renderer& renderer, Tracer& tracer, RayType type) {
        const CameraPath path = proceduralNearPath(spec_);
        size_t differing = 0;
        for (int frame = 0; frame < 4; ++frame) {
            const Camera camera = path.cameraAtFrame(frame * 3);
            FrameStats stats;
            renderer.renderGBuffer(camera, stats);
            renderer.generateRayPass(camera, type, 0, stats);
            differing += traceAgainstPureBvh(renderer, tracer, camera, type, 0, stats).differing;
        }
        renderer.useTracer(nullptr);
        return differing;
    }
};

TEST_F(ChcrtSourceTest, SubtreesThatDoNotFitAreIntersectedInLaterRoundsWithExactHits) {
    RenderSettings settings;
    settings.width = 80;
    settings.height = 64;
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    // Every query mode an out-of-core source can run (bounds-gpu needs the BVH in core).
    for (ChcrtQueries queries : {ChcrtQueries::Gl, ChcrtQueries::Batched, ChcrtQueries::BoundsOnly}) {
        SCOPED_TRACE(toString(queries));
        ChcrtOptions options = smallOptions();
        options.queries = queries;
        CullingHierarchy hierarchy = buildCullingHierarchy(bvh_, options.partition);
        ASSERT_GT(hierarchy.subtrees.size(), 8u);
        LimitedSource source(hierarchy, 3);
        ChcrtTracer tracer(std::move(hierarchy), source, nullptr, options);
        for (RayType type : {RayType::Primary, RayType::Shadow}) {
            EXPECT_EQ(compare(renderer, tracer, type), 0u) << toString(type);
        }
        const ChcrtStats& total = tracer.totalStats();
        EXPECT_EQ(total.residencyRounds, source.calls);
        // More rounds than intersect() calls per trace: subtrees were left out and handled in later rounds.
        EXPECT_GT(total.residencyRounds, 2 * total.traces);
        EXPECT_EQ(total.fallbackTraces, 0u); // no full tracer given: never falls back
    }
}

TEST_F(ChcrtSourceTest, ASourceThatCannotHoldOneSubtreeIsAnError) {
    RenderSettings settings;
    settings.width = 32;
    settings.height = 32;
    Renderer& renderer = makeProceduralRenderer("interior:20k", settings);
    const ChcrtOptions options = smallOptions();
    LimitedSource source(buildCullingHierarchy(bvh_, options.partition), 0);
    ChcrtTracer tracer(buildCullingHierarchy(bvh_, options.partition), source, nullptr, options);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    FrameStats stats;
    renderer.generateRayPass(camera, RayType::Primary, 0, stats);
    renderer.useTracer(&tracer);
    EXPECT_THROW(renderer.traceRayPass(camera, RayType::Primary, 0, stats), InputError);
    renderer.useTracer(nullptr);
}

TEST_F(ChcrtSourceTest, DebugImagesAgreeWithTheHits) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer& renderer = makeProceduralRenderer("city:30k", settings);
    ChcrtOptions options = smallOptions();
    ChcrtTracer tracer(bvh_, options);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    for (ChcrtDebugImage kind : {ChcrtDebugImage::Overdraw, ChcrtDebugImage::Subtrees, ChcrtDebugImage::Batches}) {
        tracer.resetVisibility();
        tracer.setDebugImage(kind);
        FrameStats stats;
        renderer.generateRayPass(camera, RayType::Primary, 0, stats);
        renderer.useTracer(&tracer);
        tracer.clearDebugImage();
        renderer.traceRayPass(camera, RayType::Primary, 0, stats);
        renderer.useTracer(nullptr);
        const std::vector<Hit> hits = renderer.readHits(0);
        const std::vector<uint32_t> debug = tracer.readDebugImage();
        ASSERT_EQ(debug.size(), hits.size());
        ASSERT_EQ(tracer.debugWidth(), settings.width);
        uint64_t sum = 0, hitPixels = 0;
        for (size_t i = 0; i < hits.size(); ++i) {
            const bool hit = hits[i].triangleId != CHCRT_NO_HIT_ID;
            hitPixels += hit;
            sum += debug[i];
            if (kind == ChcrtDebugImage::Subtrees) {
                // Every hit was found by some subtree pass of this trace (the init pass resets hits); misses never
                // changed. Ids are subtree indices + 1.
                EXPECT_EQ(debug[i] != 0, hit) << i;
                EXPECT_LE(debug[i], tracer.hierarchy().subtrees.size());
            } else if (hit) {
                EXPECT_GE(debug[i], 1u) << i; // a hit pixel was queried and traversed at least once
            }
        }
        ASSERT_GT(hitPixels, 0u);
        if (kind == ChcrtDebugImage::Overdraw) {
            // The first trace starts at the root pair: the whole screen is queried at least once.
            for (uint32_t v : debug) EXPECT_GE(v, 1u);
            EXPECT_GT(sum, debug.size()); // and several query levels overlap
        }
        const std::vector<float> rgb = colorizeChcrtDebugImage(kind, debug, settings.width, settings.height);
        EXPECT_EQ(rgb.size(), debug.size() * 3);
    }
    EXPECT_THROW(parseChcrtDebugImage("depth"), InputError);
}

} // namespace
} // namespace chcrt::test
