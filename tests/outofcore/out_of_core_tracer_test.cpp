// Out-of-core CHC+RT tracing is exact (issue #5 part 2, task 2): a prepared city 10-20x larger than the GPU
// cache budget traced through OutOfCoreTracer (file hierarchy + GpuSubtreeCache + SubtreeStore) gives bit for
// bit the hits of in-core pure BVH tracing of the same file, for primary, shadow and AO rays over consecutive
// frames of the near path, while the cache evicts. A budget below one subtree is an InputError.
#include "culling/outofcore/out_of_core_tracer.h"
#include "culling/outofcore/primary_resolve.h"
#include "renderer/core/error.h"
#include "renderer/render/camera_math.h"
#include "renderer/render/hit_comparison.h"
#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/render_layout.h"
#include "tests/outofcore/outofcore_test_util.h"
#include "tests/render/render_fixture.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

using OutOfCoreTracerTest = test::RenderTest;

// GPU bytes of all subtrees of the file (nodes + triangles, what the cache would hold to keep everything).
uint64_t sceneGpuBytes(const outofcore::ChsFile& file) {
    uint64_t bytes = 0;
    for (const outofcore::ChsSubtreeRecord& r : file.subtrees()) {
        bytes += uint64_t(r.nodeCount) * sizeof(BvhNodeGpu) + uint64_t(r.triangleCount) * sizeof(TriangleGpu);
    }
    return bytes;
}

// `budgetDivisor`: the GPU cache holds 1/budgetDivisor of the scene (1: all of it, no evictions). `hints`: hit hints
// and the hint pass (batched rounds intersected by cells only).
void runExactness(outofcore::CachePolicy policy, ChcrtQueries queries = ChcrtQueries::Gl, bool compact = true,
                  bool cellIntersect = false, bool hints = false, uint64_t budgetDivisor = 15) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:60k", file, 1000, 256ull << 20, compact);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    RenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    Renderer renderer(loaded.scene, loaded.bvh, loaded.light, settings);

    outofcore::OutOfCoreOptions options;
    options.policy = policy;
    options.hostCacheBytes = 1ull << 20; // smaller than the file too: subtrees are re-read
    {
        const outofcore::ChsFile chs(file);
        options.gpuCacheBytes = sceneGpuBytes(chs) / budgetDivisor; // the scene is ~budgetDivisor x the budget
    }
    ChcrtOptions chcrt;
    chcrt.pairs.minTileSize = 16;
    chcrt.queries = queries;
    chcrt.cellIntersect = cellIntersect;
    chcrt.hitHints = chcrt.hintPass = hints;
    outofcore::OutOfCoreTracer tracer(file, options, chcrt);
    ASSERT_LE(tracer.cache().stats().allocatedBytes, options.gpuCacheBytes);
    ASSERT_GE(tracer.cache().slotCount(), 1u);

    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec(loaded.source, spec));
    const CameraPath path = proceduralNearPath(spec);
    uint64_t hits = 0, compared = 0;
    const int frames = hints ? 6 : 4;
    for (int frame = 0; frame < frames; ++frame) { // consecutive frames: the fronts, the cache and hints carry over
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao}) {
            renderer.generateRayPass(camera, type, 0, stats);
            renderer.useTracer(&tracer);
            renderer.traceRayPass(camera, type, 0, stats);
            const std::vector<Hit> outOfCore = renderer.readHits(0);
            renderer.useTracer(nullptr);
            renderer.traceRayPass(camera, type, 0, stats);
            const std::vector<Hit> pure = renderer.readHits(0);
            ASSERT_EQ(outOfCore.size(), pure.size());
            // The rule of `chcrt verify`: same id and t bits; any-hit rays (shadow, AO) only hit/miss.
            const HitComparison result = compareHitsExactly(renderer.readRays(0), outOfCore, pure, isAnyHit(type));
            EXPECT_EQ(result.differing, 0u) << toString(type) << " frame " << frame;
            EXPECT_GT(result.activeRays, 0u);
            for (size_t i = 0; i < pure.size(); ++i) hits += pure[i].hit();
            compared += pure.size();
        }
        EXPECT_EQ(stats.cappedRays, 0u);
    }
    EXPECT_GT(hits, compared / 4);
    const outofcore::GpuCacheStats& c = tracer.cache().stats();
    if (budgetDivisor > 1) {
        EXPECT_GT(c.evictions, 0u);
        EXPECT_GT(c.misses, c.slots);
    } else {
        EXPECT_EQ(c.evictions, 0u);
    }
    EXPECT_EQ(tracer.cache().contentEpoch(), c.evictions); // every replaced slot moves the hints' epoch on
    // Hints are visited only where no slot changed since they were recorded (ChcrtTracer::hintImageFor): with every
    // subtree resident the hint pass runs from the second frame on.
    if (hints && budgetDivisor == 1) {
        EXPECT_GT(tracer.chcrt().totalStats().hintPasses, 0u);
    }
    if (!hints) {
        EXPECT_EQ(tracer.chcrt().totalStats().hintPasses, 0u);
    }
    EXPECT_LE(c.residentBytes, c.allocatedBytes);
    EXPECT_LE(c.allocatedBytes, options.gpuCacheBytes);
    const outofcore::OutOfCoreStats s = tracer.snapshot();
    if (queries == ChcrtQueries::Gl) EXPECT_GT(s.queries, 0u);
    else EXPECT_GT(tracer.chcrt().totalStats().pairsTestedBatched, 0u);
    // Intersected by cell passes, or by per-tile subtree passes: never both.
    EXPECT_EQ(tracer.chcrt().totalStats().cellsDrawn > 0, cellIntersect);
    EXPECT_EQ(s.uploadedBvhBytes + s.uploadedGeometryBytes, c.uploadedNodeBytes + c.uploadedTriangleBytes);
    // The file holds LOD proxies (prepare's default); an exact tracer never serves one (issue #19).
    ASSERT_GT(tracer.file().lodLevels(), 0u);
    EXPECT_FALSE(tracer.lodEnabled());
    EXPECT_EQ(c.proxyUploads, 0u);
    EXPECT_EQ(c.proxySlots, 0u);
    for (uint32_t level = 1; level < outofcore::kLodStatLevels; ++level) EXPECT_EQ(c.requestsPerLevel[level], 0u);
}

TEST_F(OutOfCoreTracerTest, HitsEqualInCorePureBvhWithLruEvictions) { runExactness(outofcore::CachePolicy::Lru); }

// In the full subtree layout (prepare --layout full; the others run on the default, compact).
TEST_F(OutOfCoreTracerTest, HitsEqualInCorePureBvhWithRoundRobinEvictions) {
    runExactness(outofcore::CachePolicy::RoundRobin, ChcrtQueries::Gl, false);
}

// The compact layout (quantized boxes, indexed triangles) gives the full layout's hits bit for bit, out of core and
// in core (loadPreparedScene keeps the decoded boxes): the hit rule does not depend on the boxes (shared/intersect.h,
// hitRule). Any-hit rays compare hit or miss (either layout may stop at another occluder).
TEST_F(OutOfCoreTracerTest, CompactLayoutGivesTheFullLayoutsHitsBitForBit) {
    test::ScratchDir dir;
    const auto compactFile = dir.file("compact.chs"), fullFile = dir.file("full.chs");
    test::prepareSmall("city:60k", compactFile, 1000, 256ull << 20, true);
    test::prepareSmall("city:60k", fullFile, 1000, 256ull << 20, false);
    const outofcore::LoadedPreparedScene full = outofcore::loadPreparedScene(fullFile);
    const outofcore::LoadedPreparedScene compact = outofcore::loadPreparedScene(compactFile);
    ASSERT_EQ(full.bvh.nodes.size(), compact.bvh.nodes.size());
    size_t widerBoxes = 0;
    for (size_t k = 0; k < full.bvh.nodes.size(); ++k) {
        widerBoxes += full.bvh.nodes[k].boundsMin != compact.bvh.nodes[k].boundsMin ||
                      full.bvh.nodes[k].boundsMax != compact.bvh.nodes[k].boundsMax;
    }
    EXPECT_GT(widerBoxes, full.bvh.nodes.size() / 2); // quantized: most boxes differ, the hits may not
    RenderSettings settings;
    settings.width = 96;
    settings.height = 64;
    Renderer fullRenderer(full.scene, full.bvh, full.light, settings);
    Renderer compactRenderer(compact.scene, compact.bvh, compact.light, settings);
    outofcore::OutOfCoreOptions options;
    options.hostCacheBytes = 1ull << 20;
    {
        const outofcore::ChsFile chs(fullFile);
        options.gpuCacheBytes = sceneGpuBytes(chs) / 8;
    }
    ChcrtOptions chcrt;
    chcrt.pairs.minTileSize = 16;
    outofcore::OutOfCoreTracer compactTracer(compactFile, options, chcrt);
    outofcore::OutOfCoreTracer fullTracer(fullFile, options, chcrt);
    ASSERT_TRUE(compactTracer.cache().compact());
    ASSERT_FALSE(fullTracer.cache().compact());
    EXPECT_GE(compactTracer.cache().slotCount(), fullTracer.cache().slotCount() * 3 / 2); // the same budget holds more

    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec(full.source, spec));
    const CameraPath path = proceduralNearPath(spec);
    uint64_t hits = 0;
    for (int frame = 0; frame < 3; ++frame) {
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        fullRenderer.renderGBuffer(camera, stats);
        compactRenderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao}) {
            fullRenderer.generateRayPass(camera, type, 0, stats);
            compactRenderer.generateRayPass(camera, type, 0, stats);
            fullRenderer.traceRayPass(camera, type, 0, stats);
            compactRenderer.traceRayPass(camera, type, 0, stats);
            const std::vector<Hit> inCoreFull = fullRenderer.readHits(0), inCoreCompact = compactRenderer.readHits(0);
            fullRenderer.useTracer(&fullTracer);
            fullRenderer.traceRayPass(camera, type, 0, stats);
            const std::vector<Hit> outOfCoreFull = fullRenderer.readHits(0);
            fullRenderer.useTracer(&compactTracer);
            fullRenderer.traceRayPass(camera, type, 0, stats);
            const std::vector<Hit> outOfCoreCompact = fullRenderer.readHits(0);
            fullRenderer.useTracer(nullptr);
            const std::vector<Ray> rays = fullRenderer.readRays(0);
            const bool anyHit = isAnyHit(type);
            EXPECT_EQ(compareHitsExactly(rays, inCoreCompact, inCoreFull, anyHit).differing, 0u) << toString(type);
            EXPECT_EQ(compareHitsExactly(rays, outOfCoreCompact, outOfCoreFull, anyHit).differing, 0u) << toString(type);
            EXPECT_EQ(compareHitsExactly(rays, outOfCoreCompact, inCoreFull, anyHit).differing, 0u) << toString(type);
            for (const Hit& h : inCoreFull) hits += h.hit();
        }
        EXPECT_EQ(stats.cappedRays, 0u);
    }
    EXPECT_GT(hits, 10000u);
}

// Batched queries, with per-tile subtree passes and with each round in one cell pass (the out-of-core default of the
// chcrt methods, app/methods.cpp).
TEST_F(OutOfCoreTracerTest, HitsEqualInCorePureBvhWithBatchedQueries) {
    runExactness(outofcore::CachePolicy::Lru, ChcrtQueries::Batched);
}

TEST_F(OutOfCoreTracerTest, HitsEqualInCorePureBvhWithBatchedQueriesIntersectedByCells) {
    runExactness(outofcore::CachePolicy::Lru, ChcrtQueries::Batched, true, true);
    runExactness(outofcore::CachePolicy::RoundRobin, ChcrtQueries::Batched, false, true);
}

// Hit hints out of core (culling/README.md "Hit hints out of core"): hints name nodes of cache slots, visited by the
// hint pass, dropped whenever a slot changed. Exact with every subtree resident (the hint pass runs; compact and full
// layouts: the compact visit decodes the leaf in its subtree's frame), with a fifth of the scene (some traces replace
// slots, some do not), and with a fifteenth (nearly every trace replaces slots).
TEST_F(OutOfCoreTracerTest, HitsEqualInCorePureBvhWithHitHints) {
    runExactness(outofcore::CachePolicy::Lru, ChcrtQueries::Batched, true, true, true, 1);
    runExactness(outofcore::CachePolicy::Lru, ChcrtQueries::Batched, false, true, true, 1);
    runExactness(outofcore::CachePolicy::Lru, ChcrtQueries::Batched, true, true, true, 5);
    runExactness(outofcore::CachePolicy::RoundRobin, ChcrtQueries::Batched, true, true, true, 15);
}

// The hint pass's stop rule out of core (ChcrtTracer::finishHintPass): a pass that dropped the hints of cache slots
// replaced since they were recorded is no sample of what hints leave, so it never counts towards stopping the pass.
// With every pass counted as leaving too many rays (hintPassMaxLeft 0), a cache that holds the whole scene stops
// the pass after two counted passes (the control: the rule can stop it here), while a cache that replaces slots
// between every two traces of the shadow ray set keeps it running on every trace.
std::vector<uint64_t> shadowHintPasses(uint64_t budgetDivisor) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:60k", file, 1000, 256ull << 20, true);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    RenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    Renderer renderer(loaded.scene, loaded.bvh, loaded.light, settings);
    outofcore::OutOfCoreOptions options;
    {
        const outofcore::ChsFile chs(file);
        options.gpuCacheBytes = sceneGpuBytes(chs) / budgetDivisor;
    }
    ChcrtOptions chcrt;
    chcrt.pairs.minTileSize = 16;
    chcrt.queries = ChcrtQueries::Batched;
    chcrt.cellIntersect = true;
    chcrt.hitHints = chcrt.hintPass = true;
    chcrt.hintPassMaxLeft = 0.0f;
    chcrt.hintPassRetryInterval = 100;
    outofcore::OutOfCoreTracer tracer(file, options, chcrt);
    ProceduralSpec spec;
    EXPECT_TRUE(parseProceduralSpec(loaded.source, spec));
    const Camera camera = proceduralNearPath(spec).cameraAtFrame(0);
    renderer.useTracer(&tracer);
    std::vector<uint64_t> passes;
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    for (int frame = 0; frame < 6; ++frame) {
        for (RayType type : {RayType::Shadow, RayType::Ao, RayType::Primary}) {
            renderer.generateRayPass(camera, type, 0, stats);
            renderer.traceRayPass(camera, type, 0, stats);
            if (type == RayType::Shadow) passes.push_back(tracer.chcrt().lastStats().hintPasses);
        }
    }
    return passes;
}

TEST_F(OutOfCoreTracerTest, HintPassesThatDroppedStaleHintsDoNotStopThePass) {
    // No hints in the first trace; the first pass does not count; two counted passes stop it.
    EXPECT_EQ(shadowHintPasses(1), (std::vector<uint64_t>{0, 1, 1, 1, 0, 0}));
    // Every pass dropped hints of replaced slots: none counts, the pass runs on every trace.
    EXPECT_EQ(shadowHintPasses(15), (std::vector<uint64_t>{0, 1, 1, 1, 1, 1}));
}

// The viewer's streaming (--uploads-per-trace): a trace that may upload only 2 subtrees leaves the rest for later
// traces (postponed, hits missing), and repeating the trace from the same camera converges: once a trace
// postpones nothing, its hits are exactly the in-core pure BVH hits. `cacheDivisor`: the GPU cache holds
// 1/cacheDivisor of the scene; when the trace's subtrees fill it, the limit is lifted so that the trace completes.
void runStreaming(uint64_t cacheDivisor, bool limitHoldsEveryTrace) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:60k", file, 1000);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    RenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    Renderer renderer(loaded.scene, loaded.bvh, loaded.light, settings);
    outofcore::OutOfCoreOptions options;
    {
        const outofcore::ChsFile chs(file);
        options.gpuCacheBytes = sceneGpuBytes(chs) / cacheDivisor + (1u << 20);
    }
    options.maxUploadsPerTrace = 2;
    ChcrtOptions chcrt;
    chcrt.pairs.minTileSize = 16;
    outofcore::OutOfCoreTracer tracer(file, options, chcrt);
    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec(loaded.source, spec));
    const Camera camera = proceduralNearPath(spec).cameraAtFrame(0);
    FrameStats stats;
    renderer.generateRayPass(camera, RayType::Primary, 0, stats);
    renderer.useTracer(nullptr);
    renderer.traceRayPass(camera, RayType::Primary, 0, stats);
    const std::vector<Hit> pure = renderer.readHits(0);
    renderer.useTracer(&tracer);
    int traces = 0;
    uint64_t firstPostponed = 0, firstDiffering = 0;
    for (; traces < 200; ++traces) {
        const uint64_t uploadsBefore = tracer.cache().stats().misses;
        renderer.traceRayPass(camera, RayType::Primary, 0, stats);
        const ChcrtStats& last = tracer.chcrt().lastStats();
        const uint64_t uploads = tracer.cache().stats().misses - uploadsBefore;
        if (limitHoldsEveryTrace || last.subtreesPostponed > 0) {
            EXPECT_LE(uploads, 2u) << "trace " << traces;
        }
        const HitComparison result = compareHitsExactly(renderer.readRays(0), renderer.readHits(0), pure, false);
        if (traces == 0) {
            firstPostponed = last.subtreesPostponed;
            firstDiffering = result.differing;
        }
        if (last.subtreesPostponed == 0) {
            EXPECT_EQ(result.differing, 0u) << "a complete trace is exact (trace " << traces << ")";
            break;
        }
    }
    EXPECT_GT(firstPostponed, 0u);
    EXPECT_GT(firstDiffering, 0u) << "the first, incomplete trace misses hits";
    EXPECT_GT(traces, 1);
    EXPECT_LT(traces, 200) << "repeated traces must converge";
    EXPECT_GT(tracer.snapshot().cachePostponed, 0u);
}

TEST_F(OutOfCoreTracerTest, UploadLimitStreamsTheWorkingSetAndRepeatedTracesConvergeToExactHits) {
    runStreaming(1, true); // the working set fits: every trace keeps the limit
}

TEST_F(OutOfCoreTracerTest, UploadLimitIsLiftedWhenTheWorkingSetExceedsTheCache) {
    runStreaming(4, false);
}

TEST_F(OutOfCoreTracerTest, BudgetBelowOneSubtreeIsAnInputError) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:20k", file, 1000);
    outofcore::OutOfCoreOptions options;
    options.gpuCacheBytes = 1024;
    EXPECT_THROW(outofcore::OutOfCoreTracer(file, options, ChcrtOptions{}), InputError);
}

std::vector<glm::vec4> readRgba32f(GLuint texture, int width, int height) {
    std::vector<glm::vec4> texels(size_t(width) * height);
    glGetTextureImage(texture, 0, GL_RGBA, GL_FLOAT, GLsizei(texels.size() * sizeof(glm::vec4)), texels.data());
    return texels;
}
std::vector<uint32_t> readR32ui(GLuint texture, int width, int height) {
    std::vector<uint32_t> texels(size_t(width) * height);
    glGetTextureImage(texture, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(texels.size() * 4), texels.data());
    return texels;
}

// Primary visibility without per-triangle buffers (PrimaryResolve): the G-buffer resolved from out-of-core
// primary hits through the recorded subtrees equals the in-core traced G-buffer (same triangles and positions,
// normals and albedo up to float rounding), with a cache far smaller than the scene.
constexpr uint64_t kWholeScene = 256ull << 20;

// hostCacheBytes: a store that holds every subtree (the resolve looks triangles up in the subtrees it holds) or one
// of 1 MB (~10 of the file's 60 subtrees: the resolve reads the hit triangles one by one, through the hit triangle
// image).
void runPrimaryResolve(uint64_t denseSpanFactor, uint64_t hostCacheBytes, const ChcrtOptions& chcrt = ChcrtOptions{}) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:60k", file, 1000);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    RenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    settings.primaryVisibility = PrimaryVisibility::Traced;
    Renderer renderer(loaded.scene, loaded.bvh, loaded.light, settings);
    outofcore::OutOfCoreOptions options;
    options.hostCacheBytes = hostCacheBytes;
    {
        const outofcore::ChsFile chs(file);
        options.gpuCacheBytes = sceneGpuBytes(chs) / 15;
    }
    outofcore::OutOfCoreTracer tracer(file, options, chcrt);
    outofcore::PrimaryResolve resolve(tracer, denseSpanFactor);
    uint64_t subtreesByTriangles = 0, laterSubtreesRead = 0;
    const float nearPlane = nearPlaneFor(loaded.scene.bounds());
    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec(loaded.source, spec));
    const CameraPath path = proceduralNearPath(spec);
    const FrameTargets& t = renderer.targets();
    const int w = settings.width, h = settings.height;
    uint64_t hitPixels = 0;
    for (int frame = 0; frame < 3; ++frame) {
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        renderer.useTracer(nullptr);
        renderer.renderGBuffer(camera, stats); // in core: pure BVH primary hits, id-indexed resolve
        const auto position = readRgba32f(t.gbufferPosition.id(), w, h);
        const auto normal = readRgba32f(t.gbufferNormal.id(), w, h);
        const auto albedo = readRgba32f(t.gbufferAlbedo.id(), w, h);
        const auto triangle = readR32ui(t.gbufferTriangle.id(), w, h);

        renderer.generateRayPass(camera, RayType::Primary, 0, stats);
        renderer.useTracer(&tracer);
        renderer.traceRayPass(camera, RayType::Primary, 0, stats);
        renderer.useTracer(nullptr);
        resolve.resolve(camera, t, nearPlane);
        EXPECT_EQ(resolve.lastStats().unresolvedPixels, 0u);
        subtreesByTriangles += resolve.lastStats().subtreesByTriangles;
        if (frame > 0) laterSubtreesRead += resolve.lastStats().subtreesRead;
        const auto position2 = readRgba32f(t.gbufferPosition.id(), w, h);
        const auto normal2 = readRgba32f(t.gbufferNormal.id(), w, h);
        const auto albedo2 = readRgba32f(t.gbufferAlbedo.id(), w, h);
        const auto triangle2 = readR32ui(t.gbufferTriangle.id(), w, h);
        for (size_t p = 0; p < triangle.size(); ++p) {
            ASSERT_EQ(triangle2[p], triangle[p]) << "frame " << frame << " pixel " << p;
            ASSERT_EQ(position2[p], position[p]) << "frame " << frame << " pixel " << p;
            ASSERT_NEAR(normal2[p].w, normal[p].w, 1e-4f * std::abs(normal[p].w) + 1e-6f);
            ASSERT_LT(glm::length(glm::vec3(normal2[p]) - glm::vec3(normal[p])), 1e-3f) << "frame " << frame << " pixel " << p;
            ASSERT_LT(glm::length(albedo2[p] - albedo[p]), 1.5f / 255.0f) << "frame " << frame << " pixel " << p;
            hitPixels += triangle[p] != CHCRT_NO_HIT_ID;
        }
    }
    EXPECT_GT(hitPixels, uint64_t(w) * h);
    EXPECT_GT(tracer.cache().stats().evictions, 0u);
    EXPECT_EQ(tracer.chcrt().totalStats().cellsDrawn > 0, chcrt.cellIntersect && chcrt.queries == ChcrtQueries::Batched);
    // The lookup the test covered: dense id tables (the default for compact ids), scans of the subtrees, or the hit
    // triangles read one by one (subtrees the store does not hold; not in frame 0, whose reads verify the blobs).
    const outofcore::PrimaryResolveStats& last = resolve.lastStats();
    EXPECT_EQ(last.subtreesIndexed + last.subtreesScanned + last.subtreesByTriangles, last.subtreesRead);
    if (hostCacheBytes == kWholeScene) {
        EXPECT_EQ(subtreesByTriangles, 0u);
        if (denseSpanFactor == 0) {
            EXPECT_EQ(last.subtreesIndexed, 0u);
        } else {
            EXPECT_GT(last.subtreesIndexed, 0u);
        }
    } else {
        EXPECT_GT(last.subtreesByTriangles, 0u);
        EXPECT_GT(last.trianglesRead, 0u);
        // After frame 0 most subtrees come from their hit triangles: the hit triangle image names them (a stale or
        // missing image sends a subtree back to the whole read when the triangle's id is not the pixel's).
        EXPECT_GT(2 * subtreesByTriangles, laterSubtreesRead);
    }
}

TEST_F(OutOfCoreTracerTest, PrimaryResolveMatchesTheInCoreTracedGBuffer) {
    runPrimaryResolve(outofcore::PrimaryResolve::kDefaultDenseSpanFactor, kWholeScene);
}

TEST_F(OutOfCoreTracerTest, PrimaryResolveByScanningSubtreesMatchesTheInCoreTracedGBuffer) {
    runPrimaryResolve(0, kWholeScene);
}

TEST_F(OutOfCoreTracerTest, PrimaryResolveReadingHitTrianglesMatchesTheInCoreTracedGBuffer) {
    runPrimaryResolve(outofcore::PrimaryResolve::kDefaultDenseSpanFactor, 1ull << 20);
}

// The same through cell passes, which write the subtree and hit triangle images too (culling/cell_pixel.glsl).
TEST_F(OutOfCoreTracerTest, PrimaryResolveFromCellPassesMatchesTheInCoreTracedGBuffer) {
    ChcrtOptions chcrt;
    chcrt.queries = ChcrtQueries::Batched;
    chcrt.cellIntersect = true;
    runPrimaryResolve(outofcore::PrimaryResolve::kDefaultDenseSpanFactor, 1ull << 20, chcrt);
    runPrimaryResolve(outofcore::PrimaryResolve::kDefaultDenseSpanFactor, kWholeScene, chcrt);
}

// A renderer WITHOUT the scene (geometry-free proxy) and out-of-core primary visibility
// (Renderer::setOutOfCorePrimary): its shadow rays are bit for bit those of the in-core traced G-buffer (same
// positions and geometric normals), so their hits equal in-core pure BVH tracing exactly; AO rays depend on
// the interpolated normals (equal up to float rounding), so almost all AO answers agree.
TEST_F(OutOfCoreTracerTest, ProxyRendererWithOutOfCorePrimaryTracesTheInCoreSecondaryRays) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    test::prepareSmall("city:60k", file, 1000);
    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    const outofcore::LoadedPreparedScene proxy = outofcore::loadPreparedSceneProxy(file);
    ASSERT_EQ(proxy.scene.triangles.size(), 1u);
    ASSERT_EQ(proxy.scene.bounds().lower, loaded.scene.bounds().lower);
    ASSERT_EQ(proxy.scene.bounds().upper, loaded.scene.bounds().upper);
    RenderSettings settings;
    settings.width = 80;
    settings.height = 60;
    settings.primaryVisibility = PrimaryVisibility::Traced;
    Renderer inCore(loaded.scene, loaded.bvh, loaded.light, settings);
    Renderer outOfCore(proxy.scene, proxy.bvh, proxy.light, settings);
    outofcore::OutOfCoreOptions options;
    {
        const outofcore::ChsFile chs(file);
        options.gpuCacheBytes = sceneGpuBytes(chs) / 15;
    }
    outofcore::OutOfCoreTracer tracer(file, options, ChcrtOptions{});
    outofcore::PrimaryResolve* resolve = &tracer.primaryResolve();
    outOfCore.setOutOfCorePrimary([resolve](const Camera& camera, const FrameTargets& targets, float nearPlane) {
        resolve->resolve(camera, targets, nearPlane);
        return resolve->geometricNormalTexture();
    });
    outOfCore.useTracer(&tracer);
    ProceduralSpec spec;
    ASSERT_TRUE(parseProceduralSpec(loaded.source, spec));
    const CameraPath path = proceduralNearPath(spec);
    uint64_t aoRays = 0, aoDiffering = 0, shadowRays = 0;
    for (int frame = 0; frame < 3; ++frame) {
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        inCore.renderGBuffer(camera, stats);
        outOfCore.renderGBuffer(camera, stats);
        EXPECT_EQ(resolve->lastStats().unresolvedPixels, 0u);
        for (RayType type : {RayType::Shadow, RayType::Ao}) {
            inCore.generateRayPass(camera, type, 0, stats);
            inCore.traceRayPass(camera, type, 0, stats);
            const std::vector<Ray> raysIn = inCore.readRays(0);
            const std::vector<Hit> hitsIn = inCore.readHits(0);
            outOfCore.generateRayPass(camera, type, 0, stats);
            outOfCore.traceRayPass(camera, type, 0, stats);
            const std::vector<Ray> raysOut = outOfCore.readRays(0);
            const HitComparison result = compareHitsExactly(raysIn, outOfCore.readHits(0), hitsIn, true);
            if (type == RayType::Shadow) {
                for (size_t p = 0; p < raysIn.size(); ++p) {
                    ASSERT_EQ(raysOut[p].origin, raysIn[p].origin) << "pixel " << p;
                    ASSERT_EQ(raysOut[p].direction, raysIn[p].direction) << "pixel " << p;
                }
                EXPECT_EQ(result.differing, 0u) << "frame " << frame;
                shadowRays += result.activeRays;
            } else {
                aoRays += result.activeRays;
                aoDiffering += result.differing;
            }
        }
        EXPECT_EQ(stats.cappedRays, 0u);
    }
    EXPECT_GT(shadowRays, 1000u);
    EXPECT_GT(aoRays, 1000u);
    EXPECT_LE(aoDiffering, aoRays / 100);
    EXPECT_GT(tracer.cache().stats().evictions, 0u);
}

} // namespace
} // namespace chcrt
