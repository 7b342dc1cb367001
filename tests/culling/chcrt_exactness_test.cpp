// CHC+RT conservative culling against pure BVH tracing, its oracle (CHC+RT §4.5: the culling never changes the
// result): over consecutive frames of a near walkthrough with temporal coherence on, every pixel's hit must
// equal pure BVH tracing's (bits of t and triangle id for closest-hit rays, hit/miss for any-hit rays).
#include "tests/render/render_fixture.h"

#include "culling/chcrt_tracer.h"
#include "culling/gpu_cell_lists.h"
#include "renderer/gl/gl_object_count.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace chcrt::test {
namespace {

struct ExactnessCase {
    const char* scene;
    uint32_t maxSubtreeHeight;
    int minTileSize;
    bool tighterBounds = true; // §5.1
    int multiQueryPairs = 4;   // §5.1 (1 = off)
    bool adaptive = false;     // the adaptive fallback switches between culling and pure passes per ray set
    bool leafCache = false;    // §5.2 2-entry leaf cache (off by default: slower on llvmpipe)
    bool rayExtent = true;     // pairs out of their rays' reach skipped (culling/ray_bounds_grid.h)
    bool mergedBatch = true;   // a batch's subtrees as one traversal (false: one after another)
    ChcrtQueries queries = ChcrtQueries::Gl; // how pairs are decided
    int boundsCell = 8;        // ray bounds grid cell edge in pixels
    int boundsPieces = 4;      // boxes per cell
    bool boundsPreviousFront = false; // BoundsOnly: Phase 1 over the previous visible front, two rounds
    std::vector<uint32_t> adaptiveHeights = {}; // more culling arms of the adaptive choice
    uint32_t cellListLimit = 0; // BoundsOnly: longer cell lists traverse the whole BVH
    bool hitHints = false;      // BoundsOnly: any-hit rays visit the leaf of their previous hit first
    bool computeCellPass = false; // cell lists traced in compute dispatches instead of fragment passes
    bool hintPass = false;      // hints visited in a pass of their own, the rays left traced compacted
    bool closestHitHints = false; // closest-hit ray sets (primary, diffuse) keep hints too
    bool shareShadowLists = false; // BoundsOnly: a frame's shadow ray sets share one swept grid and its lists
    bool hemisphereBounds = false; // BoundsOnly: AO ray sets bounded from their G-buffer's surface frames
};

class ChcrtExactnessTest : public RenderTest, public ::testing::WithParamInterface<ExactnessCase> {};

// Fixed times for the adaptive choice instead of the wall clock, so that its choices are the same on every machine:
// a pure pass takes 5 ms, the configured culling 6 ms before frame 3 (the pure pass wins: a stretch of fallbacks,
// culling re-probed) and 1 ms from then on (culling wins again and resumes from fronts several frames old), the
// further heights 7 ms.
std::function<double(uint32_t, double)> fixedAdaptiveTiming(const int& frame) {
    return [&frame](uint32_t arm, double) { return arm == 0 ? 5.0 : arm == 1 ? (frame < 2 ? 6.0 : 1.0) : 7.0; };
}

// The tracer options of a case. Adaptive cases run on fixed times (of `frame`, read at each trace) with probes due
// within the 12 traces per ray kind, so every arm and the switch back are reached whatever the machine.
ChcrtOptions optionsOf(const ExactnessCase& c, const int& frame) {
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = c.maxSubtreeHeight;
    options.pairs.minTileSize = c.minTileSize;
    options.tighterBounds = c.tighterBounds;
    options.multiQueryPairs = c.multiQueryPairs;
    options.adaptive = c.adaptive;
    options.leafCache = c.leafCache;
    options.rayExtentCulling = c.rayExtent;
    options.mergedBatch = c.mergedBatch;
    options.queries = c.queries;
    options.bounds.cellSize = c.boundsCell;
    options.bounds.pieces = c.boundsPieces;
    options.boundsPreviousFront = c.boundsPreviousFront;
    options.adaptiveHeights = c.adaptiveHeights;
    options.cellListLimit = c.cellListLimit;
    options.hitHints = c.hitHints;
    options.passTimerInterval = 1; // every trace's pass times, which the hint-pass case below compares
    options.computeCellPass = c.computeCellPass;
    options.hintPass = c.hintPass;
    options.closestHitHints = c.closestHitHints;
    options.shareShadowLists = c.shareShadowLists;
    options.hemisphereBounds = c.hemisphereBounds;
    if (c.adaptive) {
        options.adaptiveTiming = fixedAdaptiveTiming(frame);
        options.adaptiveProbeInterval = 1;
        options.adaptiveProbeBudget = 1.0;
    }
    return options;
}

// What a trace was: "F" for a pure pass of the adaptive fallback, else the termination height it culled with.
std::string traceKind(const ChcrtStats& last) {
    return last.fallbackTraces ? "F" : std::to_string(last.heightSum);
}

// The texels of a hint texture (R32UI).
std::vector<uint32_t> readHints(GLuint texture, int width, int height) {
    std::vector<uint32_t> values(size_t(width) * size_t(height), 0u);
    if (texture == 0) return {};
    glGetTextureImage(texture, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(values.size() * 4), values.data());
    return values;
}

TEST_P(ChcrtExactnessTest, HitsEqualPureBvhOverConsecutiveFrames) {
    const ExactnessCase c = GetParam();
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    int frame = 0;
    const ChcrtOptions options = optionsOf(c, frame);
    ChcrtTracer chcrt(bvh_, options);
    const CameraPath path = proceduralNearPath(spec_);

    uint64_t compared = 0, hits = 0;
    std::map<std::string, std::vector<std::string>> kinds; // per ray type, the traceKind of each trace
    for (frame = 0; frame < 6; ++frame) {
        const Camera camera = path.cameraAtFrame(frame * 2);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
            for (int sample = 0; sample < 2; ++sample) {
                renderer.generateRayPass(camera, type, sample, stats);
                const OracleComparison traced = traceAgainstPureBvh(renderer, chcrt, camera, type, sample, stats);
                kinds[toString(type)].push_back(traceKind(chcrt.lastStats()));
                for (const Hit& hit : traced.reference) hits += hit.triangleId != CHCRT_NO_HIT_ID;
                compared += traced.reference.size();
                EXPECT_EQ(traced.differing, 0u) << c.scene << " frame " << frame * 2 << " " << toString(type) << " sample "
                                         << sample;
            }
        }
        EXPECT_EQ(stats.cappedRays, 0u);
    }
    EXPECT_GT(hits, compared / 4);
    // Hit hints: any-hit ray sets recorded the leaves of their hits (the exactness above covers the frames that
    // started from them), closest-hit ray sets the leaves of their nearest hits with closestHitHints, else none.
    TraceRequest shadow;
    shadow.rayType = RayType::Shadow;
    shadow.anyHit = true;
    TraceRequest primary;
    if (c.hitHints && decidesByBounds(c.queries)) {
        if (!c.closestHitHints) {
            EXPECT_EQ(chcrt.hintTexture(primary), 0u);
        }
        for (const TraceRequest* request : {&shadow, &primary}) {
            if (request == &primary && !c.closestHitHints) continue;
            const std::vector<uint32_t> leaves = readHints(chcrt.hintTexture(*request), settings.width,
                                                           settings.height);
            size_t recorded = 0;
            for (uint32_t leaf : leaves) {
                if (leaf == CHCRT_NO_HIT_ID) continue;
                ++recorded;
                ASSERT_LT(leaf, bvh_.nodes.size());
                EXPECT_TRUE(bvh_.isLeaf(leaf)) << "hint " << leaf << " is not a leaf";
            }
            EXPECT_GT(recorded, leaves.size() / 20) << toString(request->rayType);
        }
        if (c.hintPass) {
            // The hint pass ran on every culled any-hit trace and left some rays (not all) to the cell lists.
            EXPECT_GT(chcrt.totalStats().hintPasses, 0u);
            EXPECT_GT(chcrt.totalStats().hintRaysLeft, 0u);
            // Their GPU time is counted apart, as a part of the subtree passes'.
            EXPECT_GT(chcrt.totalStats().hintPassMs, 0.0);
            EXPECT_LT(chcrt.totalStats().hintPassMs, chcrt.totalStats().subtreePassMs);
        } else {
            EXPECT_EQ(chcrt.totalStats().hintPasses, 0u);
            EXPECT_EQ(chcrt.totalStats().hintPassMs, 0.0);
        }
    } else {
        EXPECT_EQ(chcrt.hintTexture(shadow), 0u);
    }
    // The comparison is only meaningful if culling happened: pairs were found invisible, and temporal
    // coherence reused the visible front (Phase 1 work after the first frame).
    const ChcrtStats& total = chcrt.totalStats();
    EXPECT_EQ(total.queries, total.queriesSingle + total.queriesMulti);
    if (c.multiQueryPairs <= 1) {
        EXPECT_EQ(total.queriesMulti, 0u);
    }
    EXPECT_EQ(total.traces, 6u * 4u * 2u);
    const bool bounded = decidesByBounds(c.queries);
    const bool gpuLists = c.queries == ChcrtQueries::BoundsGpu;
    if (!c.adaptive) {
        EXPECT_EQ(total.fallbackTraces, 0u);
        if (!gpuLists) {
            EXPECT_GT(total.pairsInvisible, 0u); // the GPU keeps no pairs
        }
        // Phase 1 reuses the previous visible front (GL queries, or the bounds with boundsPreviousFront); without
        // it every scheduled subtree is a newly visible terminal pair.
        if (!bounded || c.boundsPreviousFront) EXPECT_GT(total.subtreesScheduled, total.pairsNewlyVisible);
        else if (!gpuLists) {
            EXPECT_EQ(total.subtreesScheduled, total.pairsNewlyVisible);
        }
        if (bounded) {
            // Every pair decided by the grid, intersected from cell lists: the exactness above covers both.
            EXPECT_EQ(total.queries, 0u);
            EXPECT_GT(total.pairsDecidedBounds, total.traces);
            EXPECT_GT(total.cellEntries, 0u);
            EXPECT_GT(total.cellsDrawn, 0u);
            if (gpuLists) {
                // The compute pass counts what decided each box test: one or two boxes per node it tested, some
                // culled by the pieces (shadow and AO segments end at the light or the AO radius), some reached.
                const uint64_t decided = total.boundsCulledPieces + total.boundsCulledFrustum + total.boundsReached;
                EXPECT_GE(decided, total.pairsDecidedBounds);
                EXPECT_LE(decided, 2 * total.pairsDecidedBounds);
                EXPECT_GT(total.boundsCulledPieces, 0u);
                EXPECT_GT(total.boundsReached, 0u);
            }
            // A list limit sends some cells through the whole BVH, and not every cell (the GPU's lists hold at most
            // CHCRT_CULLING_GPU_LIST_MAX entries whatever the limit).
            if (c.cellListLimit > 0) {
                EXPECT_GT(total.cellsWholeTree, 0u);
                EXPECT_LT(total.cellsWholeTree, total.cellsDrawn);
            } else if (gpuLists) {
                EXPECT_LT(total.cellsWholeTree, total.cellsDrawn);
            } else {
                EXPECT_EQ(total.cellsWholeTree, 0u);
            }
            // Shared shadow lists: the first frame's second shadow set made them (its first set had no earlier
            // frame of several sets), every later frame's first set made them and its second traced them. (The
            // adaptive choice may give either to the pure pass or another height.)
            if (c.shareShadowLists) {
                EXPECT_GT(total.sharedListsMade, 0u);
                EXPECT_GT(total.sharedListsReused, 0u);
                if (!c.adaptive) {
                    EXPECT_EQ(total.sharedListsMade, 6u);
                    EXPECT_EQ(total.sharedListsReused, 5u);
                }
            } else {
                EXPECT_EQ(total.sharedListsMade + total.sharedListsReused, 0u);
            }
            // AO cells from the surface frames: every AO trace that culled without a hint pass (the first of each
            // sample index has no hints, so it has none).
            if (c.hemisphereBounds && c.queries == ChcrtQueries::BoundsOnly) {
                EXPECT_GT(total.boundsFromHemisphere, 0u);
                if (!c.hintPass) {
                    EXPECT_EQ(total.boundsFromHemisphere, 12u);
                }
            } else {
                EXPECT_EQ(total.boundsFromHemisphere, 0u);
            }
        } else if (c.queries == ChcrtQueries::Batched) {
            // Every ray-exact test ran in the batched dispatches: no GL query, several rounds per trace.
            EXPECT_EQ(total.queries, 0u);
            EXPECT_GT(total.pairsTestedBatched, total.traces);
            EXPECT_GT(total.batchedRounds, total.traces);
        } else {
            EXPECT_GT(total.queries, 0u);
            EXPECT_EQ(total.pairsTestedBatched, 0u);
        }
        // Bounded rays (shadow, AO) leave pairs out of their reach: the exactness above covers the skipping.
        if (c.rayExtent && !bounded) {
            EXPECT_GT(total.queriesSkippedExtent, 0u);
        }
    }
    if (!c.rayExtent && !bounded) {
        EXPECT_EQ(total.queriesSkippedExtent, 0u);
        EXPECT_EQ(total.leavesSkippedExtent, 0u);
    }
    // The configured culling runs first (its height: the hierarchy's, at most maxSubtreeHeight).
    const std::string configured = kinds["primary"].front();
    const auto has = [](const std::vector<std::string>& sequence, const std::string& kind) {
        return std::find(sequence.begin(), sequence.end(), kind) != sequence.end();
    };
    if (c.adaptive) {
        // The adaptive choice measures the pure pass first (on each sample index before culling is measured there),
        // then the configured culling, so both branches are compared above. With the fixed times the pure pass wins
        // until frame 2; from then on culling wins, is confirmed, and the further heights are explored once culling
        // comes close to the pure pass (e.g. ao F F F 12 F 12 6 10 F 12 12 12); culling resumes from fronts several
        // frames old.
        EXPECT_GE(total.fallbackTraces, 2u * 4u);
        EXPECT_GE(total.traces - total.fallbackTraces, (1u + c.adaptiveHeights.size()) * 4u);
        for (const auto& [type, sequence] : kinds) {
            std::string text;
            for (const std::string& kind : sequence) text += kind + " ";
            std::printf("[ adaptive ] %s: %s\n", type.c_str(), text.c_str());
            EXPECT_TRUE(has(sequence, "F")) << type << ": " << text;
            std::set<std::string> heights(sequence.begin(), sequence.end());
            heights.erase("F");
            // Every arm ran; shadow rays that share a sweep's lists have the configured height only (a one-set probe
            // of another height cannot weigh lists made once per sweep: ChcrtOptions::adaptiveHeights).
            const bool oneHeight = type == "shadow" && c.shareShadowLists;
            EXPECT_EQ(heights.size(), 1u + (oneHeight ? 0u : c.adaptiveHeights.size())) << type << ": " << text;
            if (c.adaptiveHeights.empty()) {
                // Once culling measures cheaper (frame 2 on), it runs again after the pure stretch.
                const auto firstPure = std::find(sequence.begin(), sequence.end(), "F");
                EXPECT_GE(std::count(firstPure, sequence.end(), configured), 3) << type << ": " << text;
            }
        }
    } else {
        for (const auto& [type, sequence] : kinds) {
            EXPECT_EQ(std::count(sequence.begin(), sequence.end(), configured), 12) << type; // no fallback, one height
        }
        // per sample index for AO and diffuse, one state each for primary and shadow (§5.3); the GPU's lists keep
        // none
        EXPECT_EQ(chcrt.rayStateCount(), gpuLists ? 0u : 2u + 2u + 2u);
    }
    std::printf("[ stats    ] %s: %llu traces, %llu queries (%llu invisible, %llu lazy, %llu traversal), "
                "%llu subtrees in %llu calls, fronts %llu visible / %llu invisible, phases %.1f/%.1f/%.1f ms\n",
                c.scene, (unsigned long long)total.traces, (unsigned long long)total.queries,
                (unsigned long long)total.queriesInvisible, (unsigned long long)total.queriesLazy,
                (unsigned long long)total.queriesTraversal, (unsigned long long)total.subtreesScheduled,
                (unsigned long long)total.shaderCalls, (unsigned long long)total.pairsVisible,
                (unsigned long long)total.pairsInvisible, total.phase1Ms, total.phase2Ms, total.phase3Ms);
}

TEST_P(ChcrtExactnessTest, ShadedFrameEqualsPureBvhFrame) {
    // The whole frame (incl. the bounce shadow rays of the diffuse effect, their own ray set) must be the same
    // image bit for bit: every traced answer is the same.
    const ExactnessCase c = GetParam();
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.samplesPerPixel = 2;
    Renderer& renderer = makeProceduralRenderer(c.scene, settings);
    int frame = 0;
    const ChcrtOptions options = optionsOf(c, frame);
    ChcrtTracer chcrt(bvh_, options);
    const CameraPath path = proceduralNearPath(spec_);
    for (frame = 0; frame < 2; ++frame) {
        const Camera camera = path.cameraAtFrame(frame);
        renderer.useTracer(nullptr);
        renderer.renderFrame(camera);
        const ImageRgba32f reference = renderer.readHdrImage();
        renderer.useTracer(&chcrt);
        renderer.renderFrame(camera);
        const ImageRgba32f culled = renderer.readHdrImage();
        ASSERT_EQ(reference.pixels.size(), culled.pixels.size());
        EXPECT_EQ(std::memcmp(reference.pixels.data(), culled.pixels.data(),
                              reference.pixels.size() * sizeof(reference.pixels[0])),
                  0)
            << "frame " << frame;
    }
}

TEST_F(RenderTest, PassTimersRunOnOneTraceInTheirIntervalAndAreEstimatedForAll) {
    // ChcrtOptions::passTimerInterval: the statistics' pass times come from the first trace and every interval-th
    // after it, and are estimated for every culled trace from those; 0 times none.
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Primary, stats);
    for (const uint32_t interval : {3u, 0u}) {
        ChcrtOptions options = recommendedChcrtOptions(RendererTraits{.software = true});
        options.adaptive = false;
        options.passTimerInterval = interval;
        ChcrtTracer chcrt(bvh_, options);
        std::vector<double> timed;
        for (int trace = 0; trace < 7; ++trace) {
            EXPECT_EQ(traceAgainstPureBvh(renderer, chcrt, camera, RayType::Primary, 0, stats).differing, 0u);
            timed.push_back(chcrt.lastStats().subtreePassMs);
            EXPECT_EQ(chcrt.lastStats().passTimedTraces, interval != 0 && trace % 3 == 0 ? 1u : 0u) << trace;
        }
        for (int trace = 0; trace < 7; ++trace) {
            if (interval != 0 && trace % 3 == 0) {
                EXPECT_GT(timed[size_t(trace)], 0.0) << trace;
            } else {
                EXPECT_EQ(timed[size_t(trace)], 0.0) << trace;
            }
        }
        const ChcrtStats& total = chcrt.totalStats();
        EXPECT_EQ(total.passTimedTraces, interval == 0 ? 0u : 3u);
        const double timedSum = timed[0] + timed[3] + timed[6];
        EXPECT_DOUBLE_EQ(total.subtreePassMs, timedSum);
        EXPECT_DOUBLE_EQ(total.estimatedPassMs(total.subtreePassMs), interval == 0 ? 0.0 : timedSum * 7.0 / 3.0);
    }
}

TEST_F(RenderTest, AggressiveCullingLosesHitsThatTheComparisonDetects) {
    // §7 aggressive variant: pairs with few passing rays are culled, so some hits are lost. This also shows that
    // the exactness comparison above can fail.
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 8;
    options.pairs.minTileSize = 16;
    options.visibleThreshold = 40;
    options.adaptive = false;
    ChcrtTracer aggressive(bvh_, options, "chcrt-aggressive");
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Primary, stats);
    const OracleComparison traced = traceAgainstPureBvh(renderer, aggressive, camera, RayType::Primary, 0, stats);
    for (size_t i = 0; i < traced.reference.size(); ++i) {
        // Culling only removes candidates: a differing pixel is a miss or a farther hit, never a nearer one.
        const Hit& reference = traced.reference[i];
        const Hit& culled = traced.traced[i];
        if (reference.triangleId != CHCRT_NO_HIT_ID && culled.triangleId != CHCRT_NO_HIT_ID) {
            EXPECT_GE(culled.t, reference.t);
        }
    }
    EXPECT_GT(traced.differing, 0u);
    EXPECT_LT(traced.differing, traced.reference.size() / 2);
    EXPECT_EQ(aggressive.name(), "chcrt-aggressive");
}

TEST_F(RenderTest, RayBoundsShrunkBelowTheRoundingPadLoseHitsThatTheComparisonDetects) {
    // Negative control of the bounds-only exactness cases: boxes that are too small by a fraction of the
    // coordinates' magnitude (instead of padded by it) must change hits, so the comparison above can fail.
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 8;
    options.pairs.minTileSize = 16;
    options.adaptive = false;
    options.queries = ChcrtQueries::BoundsOnly;
    options.bounds.relativePad = -1.0f / 64.0f;
    ChcrtTracer shrunk(bvh_, options);
    const CameraPath path = proceduralNearPath(spec_);
    std::map<RayType, size_t> differing;
    FrameStats stats;
    for (int frame = 0; frame < 3; ++frame) {
        const Camera camera = path.cameraAtFrame(frame * 2);
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao}) {
            renderer.generateRayPass(camera, type, 0, stats);
            differing[type] += traceAgainstPureBvh(renderer, shrunk, camera, type, 0, stats).differing;
        }
    }
    EXPECT_GT(differing[RayType::Shadow] + differing[RayType::Ao], 0u);
    // Primary rays' cells come from the camera (camera_ray_bounds.h), padded the same way: shrunk, they lose hits too.
    EXPECT_EQ(shrunk.totalStats().boundsFromCamera, 3u);
    EXPECT_GT(differing[RayType::Primary], 0u);
}

// Forwards every trace to `inner` with the request as `rewrite` leaves it (the negative controls below: what the
// renderer tells a tracer about its rays made smaller than the rays are).
class RewrittenRequests final : public Tracer {
public:
    RewrittenRequests(Tracer& inner, std::function<void(TraceRequest&)> rewrite)
        : inner_(inner), rewrite_(std::move(rewrite)) {}
    std::string name() const override { return inner_.name(); }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override {
        TraceRequest rewritten = request;
        rewrite_(rewritten);
        inner_.trace(rewritten, rays, hits, width, height, stats);
    }

private:
    Tracer& inner_;
    std::function<void(TraceRequest&)> rewrite_;
};

// The pixels whose hits differ between pure BVH and `tracer` over `frames` G-buffers of the near path (every second
// frame) with `samples` ray sets of `type` each.
size_t differingOverNearPath(Renderer& renderer, Tracer& tracer, const CameraPath& path, RayType type, int frames,
                             int samples) {
    size_t differing = 0;
    FrameStats stats;
    for (int frame = 0; frame < frames; ++frame) {
        const Camera camera = path.cameraAtFrame(frame * 2);
        renderer.renderGBuffer(camera, stats);
        for (int sample = 0; sample < samples; ++sample) {
            renderer.generateRayPass(camera, type, sample, stats);
            differing += traceAgainstPureBvh(renderer, tracer, camera, type, sample, stats).differing;
        }
    }
    renderer.useTracer(nullptr);
    return differing;
}

TEST_F(RenderTest, SharedShadowListsSweptToTooSmallALightLoseHitsThatTheComparisonDetects) {
    // Negative control of the shared shadow lists' exactness cases: lists made for segments that end at one corner of
    // the light instead of anywhere on it must change hits of the sets that share them (the first set's too).
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    for (ChcrtQueries queries : {ChcrtQueries::BoundsOnly, ChcrtQueries::BoundsGpu}) {
        SCOPED_TRACE(toString(queries));
        ChcrtOptions options;
        options.partition.maxSubtreeHeight = 8;
        options.pairs.minTileSize = 16;
        options.adaptive = false;
        options.queries = queries;
        options.shareShadowLists = true;
        ChcrtTracer chcrt(bvh_, options);
        // The light sweep's box shrunk to its lower corner.
        RewrittenRequests shrunk(chcrt, [](TraceRequest& r) {
            if (r.lightSweep) r.lightSweep->lightMax = r.lightSweep->lightMin;
        });
        const size_t differing =
            differingOverNearPath(renderer, shrunk, proceduralNearPath(spec_), RayType::Shadow, 3, 4);
        EXPECT_EQ(chcrt.totalStats().sharedListsMade, 3u);
        EXPECT_EQ(chcrt.totalStats().sharedListsReused, 8u); // the first frame's first set had its own lists
        EXPECT_GT(differing, 0u);
    }
}

TEST_F(RenderTest, AoCellsBoundedForShorterRaysLoseHitsThatTheComparisonDetects) {
    // Negative control of the hemisphere cases: cells bounded from the surface frames for rays a quarter of the AO
    // rays' length must change hits (and with the option off the same wrapper changes nothing).
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    for (const bool hemisphereBounds : {true, false}) {
        SCOPED_TRACE(hemisphereBounds);
        ChcrtOptions options;
        options.partition.maxSubtreeHeight = 8;
        options.pairs.minTileSize = 16;
        options.adaptive = false;
        options.queries = ChcrtQueries::BoundsOnly;
        options.hemisphereBounds = hemisphereBounds;
        ChcrtTracer chcrt(bvh_, options);
        // The AO rays a quarter of their length.
        RewrittenRequests shortened(chcrt, [](TraceRequest& r) {
            if (r.hemisphereRays) r.hemisphereRays->length *= 0.25f;
        });
        const size_t differing =
            differingOverNearPath(renderer, shortened, proceduralNearPath(spec_), RayType::Ao, 2, 3);
        EXPECT_EQ(chcrt.totalStats().boundsFromHemisphere, hemisphereBounds ? 6u : 0u);
        EXPECT_EQ(chcrt.totalStats().boundsUpdates, hemisphereBounds ? 2u : 6u); // one reduction per G-buffer
        if (hemisphereBounds) {
            EXPECT_GT(differing, 0u);
        } else {
            EXPECT_EQ(differing, 0u);
        }
    }
}

TEST_F(RenderTest, OneShadowSetPerGBufferKeepsItsOwnLists) {
    // Shared lists pay only when a second set traces them: with one shadow set per G-buffer (the viewer at 1 spp)
    // every set decides its own lists, which the hint pass's marks keep small; from a G-buffer with two sets on, the
    // first set of each makes them.
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    ChcrtOptions options = recommendedChcrtOptions(RendererTraits{.software = true});
    options.adaptive = false;
    ChcrtTracer chcrt(bvh_, options);
    const CameraPath path = proceduralNearPath(spec_);
    FrameStats stats;
    const std::vector<int> setsPerFrame = {1, 1, 1, 2, 1, 3, 3};
    for (size_t frame = 0; frame < setsPerFrame.size(); ++frame) {
        const Camera camera = path.cameraAtFrame(int(frame));
        renderer.renderGBuffer(camera, stats);
        for (int sample = 0; sample < setsPerFrame[frame]; ++sample) {
            renderer.generateRayPass(camera, RayType::Shadow, sample, stats);
            EXPECT_EQ(traceAgainstPureBvh(renderer, chcrt, camera, RayType::Shadow, sample, stats).differing, 0u);
        }
    }
    renderer.useTracer(nullptr);
    // Made by frame 3's second set, frame 4's only set (after a frame of two), frame 5's second set (after a frame of
    // one) and frame 6's first; traced again by frame 5's third set and frame 6's second and third.
    EXPECT_EQ(chcrt.totalStats().sharedListsMade, 4u);
    EXPECT_EQ(chcrt.totalStats().sharedListsReused, 3u);
}

// Always culling with bounds-decided lists and hit hints, visited in the cell pass or (hintPass) in the hint pass: the
// configuration of the hint tests below.
ChcrtOptions hintedCullingOptions(bool hintPass) {
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 8;
    options.pairs.minTileSize = 16;
    options.adaptive = false;
    options.queries = ChcrtQueries::BoundsOnly;
    options.hitHints = true;
    options.hintPass = hintPass;
    return options;
}

TEST_F(RenderTest, ArbitraryHitHintsKeepHitsExact) {
    // A hint only says where to look first: whatever leaf or inner node it names, the hits stay pure BVH's. The hint
    // images of shadow, AO and (closest-hit hints) primary rays are overwritten with random nodes (leaves and inner
    // nodes alike) before each trace, with the hints visited in the cell pass and in the hint pass.
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    for (bool hintPass : {false, true}) {
        ChcrtOptions options = hintedCullingOptions(hintPass);
        options.closestHitHints = true;
        ChcrtTracer chcrt(bvh_, options);
        const CameraPath path = proceduralNearPath(spec_);
        std::mt19937 random(7);
        std::uniform_int_distribution<uint32_t> node(0, uint32_t(bvh_.nodes.size() - 1));
        std::vector<uint32_t> hints(size_t(settings.width) * size_t(settings.height));
        size_t differing = 0, traced = 0;
        FrameStats stats;
        for (int frame = 0; frame < 3; ++frame) {
            const Camera camera = path.cameraAtFrame(frame * 2);
            renderer.renderGBuffer(camera, stats);
            for (RayType type : {RayType::Shadow, RayType::Ao, RayType::Primary}) {
                TraceRequest request;
                request.rayType = type;
                request.anyHit = isAnyHit(type);
                renderer.generateRayPass(camera, type, 0, stats);
                renderer.useTracer(nullptr);
                renderer.traceRayPass(camera, type, 0, stats);
                const std::vector<Hit> reference = renderer.readHits(0);
                if (GLuint texture = chcrt.hintTexture(request)) {
                    for (uint32_t& h : hints) h = random() % 4 == 0 ? CHCRT_NO_HIT_ID : node(random);
                    glTextureSubImage2D(texture, 0, 0, 0, settings.width, settings.height, GL_RED_INTEGER,
                                        GL_UNSIGNED_INT, hints.data());
                    ++traced;
                }
                renderer.useTracer(&chcrt);
                renderer.traceRayPass(camera, type, 0, stats);
                const std::vector<Hit> culled = renderer.readHits(0);
                differing += countDifferingHits(reference, culled, isAnyHit(type));
            }
        }
        EXPECT_EQ(traced, 6u) << "hint pass " << hintPass; // the three ray sets, from their second trace on
        EXPECT_EQ(differing, 0u) << "hint pass " << hintPass;
        EXPECT_EQ(chcrt.totalStats().hintPasses > 0, hintPass);
    }
}

// A hint that names an inner node is not entered (shaders/culling/hint_leaf.glsl, enterHintLeaf): the cell pass takes
// a ray's hinted leaf as the first root of its list traversal, whose stack holds a termination subtree, not the BVH
// under an inner node near the root. With every shadow ray's hint the BVH root, each pixel's steps (the cost debug
// image, hint visits included) equal those with no hints at all, in the cell pass and in the hint pass; entering the
// root would traverse the whole BVH first.
TEST_F(RenderTest, HintsNamingInnerNodesAreNotEntered) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    ASSERT_GT(bvh_.nodes.size(), 1u); // node 0, the root, is an inner node
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Shadow, stats);
    renderer.useTracer(nullptr);
    renderer.traceRayPass(camera, RayType::Shadow, 0, stats);
    const std::vector<Hit> reference = renderer.readHits(0);
    TraceRequest request;
    request.rayType = RayType::Shadow;
    request.anyHit = true;
    for (bool hintPass : {false, true}) {
        ChcrtOptions options = hintedCullingOptions(hintPass);
        options.hintPassMaxLeft = 1.0; // the pass runs however many rays its hints leave
        ChcrtTracer chcrt(bvh_, options);
        chcrt.setDebugImage(ChcrtDebugImage::Cost);
        renderer.useTracer(&chcrt);
        renderer.traceRayPass(camera, RayType::Shadow, 0, stats); // makes the ray set's hint image
        const GLuint texture = chcrt.hintTexture(request);
        ASSERT_NE(texture, 0u);
        std::vector<std::vector<uint32_t>> costs;
        for (uint32_t hint : {uint32_t(CHCRT_NO_HIT_ID), 0u}) {
            const std::vector<uint32_t> hints(size_t(settings.width) * size_t(settings.height), hint);
            glTextureSubImage2D(texture, 0, 0, 0, settings.width, settings.height, GL_RED_INTEGER, GL_UNSIGNED_INT,
                                hints.data());
            chcrt.clearDebugImage();
            renderer.traceRayPass(camera, RayType::Shadow, 0, stats);
            const std::vector<Hit> culled = renderer.readHits(0);
            const size_t differing = countDifferingHits(reference, culled, true);
            EXPECT_EQ(differing, 0u) << "hint " << hint << ", hint pass " << hintPass;
            costs.push_back(chcrt.readDebugImage());
        }
        renderer.useTracer(nullptr);
        EXPECT_EQ(chcrt.totalStats().hintPasses > 0, hintPass);
        ASSERT_EQ(costs[0].size(), costs[1].size());
        size_t differingCost = 0;
        for (size_t i = 0; i < costs[0].size(); ++i) differingCost += costs[0][i] != costs[1][i];
        EXPECT_EQ(differingCost, 0u) << "hint pass " << hintPass;
    }
}

// The subtree debug image gives 0 to a hit found in the ray's hinted leaf (CHCRT_CELL_HINT_ENTRY: no listed subtree
// found it) and 1 + the subtree id to every other hit. The same shadow rays traced twice: the first trace has no hints,
// so every hit has a subtree; the second starts each occluded ray at the leaf of its first hit, where an any-hit ray
// ends — exactly the pixels with a hint show 0.
TEST_F(RenderTest, HitsFoundInTheHintedLeafShowNoSubtree) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Shadow, stats);
    ChcrtTracer chcrt(bvh_, hintedCullingOptions(false));
    chcrt.setDebugImage(ChcrtDebugImage::Subtrees);
    renderer.useTracer(&chcrt);
    TraceRequest request;
    request.rayType = RayType::Shadow;
    request.anyHit = true;
    const size_t pixels = size_t(settings.width) * size_t(settings.height);
    std::vector<uint32_t> hints(pixels, CHCRT_NO_HIT_ID);
    for (int trace = 0; trace < 2; ++trace) {
        chcrt.clearDebugImage();
        renderer.traceRayPass(camera, RayType::Shadow, 0, stats);
        const std::vector<Hit> hits = renderer.readHits(0);
        const std::vector<uint32_t> subtrees = chcrt.readDebugImage();
        ASSERT_EQ(subtrees.size(), pixels);
        size_t hitPixels = 0, hinted = 0;
        for (size_t i = 0; i < pixels; ++i) {
            const bool hit = hits[i].triangleId != CHCRT_NO_HIT_ID;
            const bool hasHint = hints[i] != CHCRT_NO_HIT_ID;
            hitPixels += hit;
            hinted += hasHint;
            EXPECT_TRUE(hit || !hasHint) << "trace " << trace << ", pixel " << i; // a hint's leaf still occludes
            EXPECT_EQ(subtrees[i] != 0, hit && !hasHint) << "trace " << trace << ", pixel " << i;
            EXPECT_LE(subtrees[i], chcrt.hierarchy().subtrees.size());
        }
        ASSERT_GT(hitPixels, 0u);
        EXPECT_EQ(hinted > 0, trace == 1);
        const GLuint texture = chcrt.hintTexture(request);
        ASSERT_NE(texture, 0u);
        glGetTextureImage(texture, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(pixels * sizeof(uint32_t)),
                          hints.data());
    }
    renderer.useTracer(nullptr);
}

// The hint pass's rule (ChcrtOptions::hintPassMaxLeft): a ray set's first trace has no hints and skips the pass; from
// two passes in a row that left too many rays on, the kind skips it, retrying every hintPassRetryInterval traces. With
// a share of 0 every pass leaves too many, with 1 none does; the hits stay pure BVH's either way.
TEST_F(RenderTest, HintPassStopsWhereItLeavesTooManyRaysAndRetries) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Shadow, stats);
    renderer.useTracer(nullptr);
    renderer.traceRayPass(camera, RayType::Shadow, 0, stats);
    const std::vector<Hit> reference = renderer.readHits(0);
    for (double maxLeft : {0.0, 1.0}) {
        ChcrtOptions options;
        options.partition.maxSubtreeHeight = 8;
        options.adaptive = false;
        options.queries = ChcrtQueries::BoundsOnly;
        options.hitHints = true;
        options.hintPass = true;
        options.hintPassMaxLeft = maxLeft;
        options.hintPassRetryInterval = 3;
        ChcrtTracer chcrt(bvh_, options);
        renderer.useTracer(&chcrt);
        std::vector<uint64_t> passes;
        size_t differing = 0;
        for (int trace = 0; trace < 13; ++trace) {
            renderer.traceRayPass(camera, RayType::Shadow, 0, stats);
            passes.push_back(chcrt.lastStats().hintPasses);
            const std::vector<Hit> culled = renderer.readHits(0);
            differing += countDifferingHits(reference, culled, true);
        }
        const std::vector<uint64_t> expected =
            // No hints in the first trace; the first pass over them does not count; two passes that left too many
            // stop it; a retry after hintPassRetryInterval traces, and after twice as many once the retry left too
            // many again.
            maxLeft == 0.0 ? std::vector<uint64_t>{0, 1, 1, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1}
                           : std::vector<uint64_t>{0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
        EXPECT_EQ(passes, expected) << "hintPassMaxLeft " << maxLeft;
        EXPECT_EQ(differing, 0u) << "hintPassMaxLeft " << maxLeft;
    }
}

// The adaptive choice does not count a culling trace whose hint pass left too many rays: the rule stops that pass, so
// the trace is no sample of what culling costs from then on. Culling is told it takes 1.5x the pure pass in traces
// that ran the hint pass and 0.9x in the others: where every hint pass leaves too many rays (share 0) culling must win
// once the rule has stopped the pass; where none does (share 1) the passes are counted and culling loses.
TEST_F(RenderTest, TracesWhoseHintPassLeftTooManyRaysAreNotCountedByTheAdaptiveChoice) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    FrameStats stats;
    const Camera camera = raysAtNearPathStart(renderer, RayType::Shadow, stats);
    for (double maxLeft : {0.0, 1.0}) {
        ChcrtOptions options;
        options.partition.maxSubtreeHeight = 8;
        options.queries = ChcrtQueries::BoundsOnly;
        options.hitHints = true;
        options.hintPass = true;
        options.hintPassMaxLeft = maxLeft;
        const ChcrtTracer* tracer = nullptr; // the trace's statistics are the tracer's when the choice is told
        options.adaptiveTiming = [&tracer](uint32_t arm, double) {
            if (arm == AdaptiveChoice::kPureArm) return 10.0;
            return tracer->lastStats().hintPasses != 0 ? 15.0 : 9.0;
        };
        ChcrtTracer chcrt(bvh_, options);
        tracer = &chcrt;
        renderer.useTracer(&chcrt);
        int culled = 0;
        for (int trace = 0; trace < 24; ++trace) {
            renderer.traceRayPass(camera, RayType::Shadow, 0, stats);
            culled += chcrt.lastStats().fallbackTraces == 0;
        }
        renderer.useTracer(nullptr);
        if (maxLeft == 0.0) {
            EXPECT_GE(culled, 16) << "culling kept out by the traces of a hint pass its rule stops";
        } else {
            EXPECT_LE(culled, 8) << "the hint passes that finish enough rays are what culling costs";
        }
    }
}

// Hit hints are kept per sample index: the shadow rays of two samples aim at different points of the area light, so
// tracing sample 1 must leave sample 0's hints as sample 0's trace wrote them (one image per ray kind would hold
// sample 1's hits), and each sample's hints name leaves only where its own rays hit.
TEST_F(RenderTest, EachShadowSampleKeepsItsOwnHints) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 8;
    options.adaptive = false;
    options.queries = ChcrtQueries::BoundsOnly;
    options.hitHints = true;
    ChcrtTracer chcrt(bvh_, options);
    renderer.useTracer(&chcrt);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    std::vector<uint32_t> hintsOf[2];
    std::vector<Hit> hitsOf[2];
    TraceRequest shadow[2];
    for (int sample = 0; sample < 2; ++sample) {
        shadow[sample].rayType = RayType::Shadow;
        shadow[sample].anyHit = true;
        shadow[sample].sampleIndex = sample;
        renderer.generateRayPass(camera, RayType::Shadow, sample, stats);
        renderer.traceRayPass(camera, RayType::Shadow, sample, stats);
        hitsOf[sample] = renderer.readHits(0);
        hintsOf[sample] = readHints(chcrt.hintTexture(shadow[sample]), settings.width, settings.height);
    }
    ASSERT_NE(chcrt.hintTexture(shadow[0]), chcrt.hintTexture(shadow[1]));
    EXPECT_EQ(readHints(chcrt.hintTexture(shadow[0]), settings.width, settings.height), hintsOf[0]);
    size_t samplesDiffer = 0;
    for (int sample = 0; sample < 2; ++sample) {
        size_t recorded = 0, withoutHit = 0;
        for (size_t i = 0; i < hintsOf[sample].size(); ++i) {
            if (hintsOf[sample][i] == CHCRT_NO_HIT_ID) continue;
            ++recorded;
            withoutHit += hitsOf[sample][i].triangleId == CHCRT_NO_HIT_ID;
        }
        EXPECT_GT(recorded, hintsOf[sample].size() / 20) << "sample " << sample;
        EXPECT_EQ(withoutHit, 0u) << "sample " << sample;
    }
    for (size_t i = 0; i < hitsOf[0].size(); ++i) {
        samplesDiffer += (hitsOf[0][i].triangleId == CHCRT_NO_HIT_ID) != (hitsOf[1][i].triangleId == CHCRT_NO_HIT_ID);
    }
    EXPECT_GT(samplesDiffer, 0u) << "the two samples' shadow rays should differ somewhere (penumbrae)";
}

// Hint images stay within ChcrtOptions::hintMemoryBytes: with room for two sets per ray kind, four shadow and four AO
// samples keep four images (samples 0 and 2, 1 and 3 share), with room for more eight; the hits stay pure BVH's.
TEST_F(RenderTest, HintImagesStayWithinTheirMemory) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    const CameraPath path = proceduralNearPath(spec_);
    const uint64_t bytesPerSet = 4ull * 96 * 72 * 4; // 4 bytes per ray, a quarter of the budget per ray kind
    for (const auto& [budget, images] : {std::pair<uint64_t, size_t>{2 * bytesPerSet, 4}, {uint64_t(1) << 30, 8}}) {
        ChcrtOptions options;
        options.partition.maxSubtreeHeight = 8;
        options.adaptive = false;
        options.queries = ChcrtQueries::BoundsOnly;
        options.hitHints = true;
        options.hintPass = true;
        options.hintMemoryBytes = budget;
        ChcrtTracer chcrt(bvh_, options);
        size_t differing = 0;
        FrameStats stats;
        for (int frame = 0; frame < 2; ++frame) {
            const Camera camera = path.cameraAtFrame(frame * 2);
            renderer.renderGBuffer(camera, stats);
            for (RayType type : {RayType::Shadow, RayType::Ao}) {
                for (int sample = 0; sample < 4; ++sample) {
                    renderer.generateRayPass(camera, type, sample, stats);
                    differing += traceAgainstPureBvh(renderer, chcrt, camera, type, sample, stats).differing;
                }
            }
        }
        EXPECT_EQ(chcrt.hintImageCount(), images) << "budget " << budget;
        EXPECT_EQ(differing, 0u) << "budget " << budget;
    }
}

// bench --steps traces a pass again from the hints the timed trace started from (ChcrtTracer::saveHints/restoreHints):
// a restore gives back every saved ray set's hints as they were, and removes the hints of ray sets made since.
TEST_F(RenderTest, RestoredHintsAreTheSavedOnes) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    const CameraPath path = proceduralNearPath(spec_);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 8;
    options.adaptive = false;
    options.queries = ChcrtQueries::BoundsOnly;
    options.hitHints = true;
    options.hintPass = true;
    ChcrtTracer chcrt(bvh_, options);
    renderer.useTracer(&chcrt);
    TraceRequest shadow, ao;
    shadow.rayType = RayType::Shadow;
    shadow.anyHit = true;
    ao.rayType = RayType::Ao;
    ao.anyHit = true;
    FrameStats stats;
    const auto traceFrame = [&](int frame, RayType type) {
        const Camera camera = path.cameraAtFrame(frame);
        renderer.renderGBuffer(camera, stats);
        renderer.generateRayPass(camera, type, 0, stats);
        renderer.traceRayPass(camera, type, 0, stats);
    };
    traceFrame(0, RayType::Shadow);
    const ChcrtTracer::HintSnapshot snapshot = chcrt.saveHints();
    const std::vector<uint32_t> saved = readHints(chcrt.hintTexture(shadow), settings.width, settings.height);
    ASSERT_EQ(chcrt.hintTexture(ao), 0u);
    traceFrame(4, RayType::Shadow); // another view: other hits, other hints
    traceFrame(4, RayType::Ao);
    ASSERT_NE(chcrt.hintTexture(ao), 0u);
    ASSERT_NE(readHints(chcrt.hintTexture(shadow), settings.width, settings.height), saved);
    chcrt.restoreHints(snapshot);
    EXPECT_EQ(readHints(chcrt.hintTexture(shadow), settings.width, settings.height), saved);
    EXPECT_EQ(chcrt.hintTexture(ao), 0u);
}

TEST_F(RenderTest, GpuCellListsWithRayBoundsShrunkBelowTheRoundingPadLoseHits) {
    // Negative control of the bounds-gpu cases: the GPU's lists from boxes that are too small must change hits.
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 8;
    options.adaptive = false;
    options.queries = ChcrtQueries::BoundsGpu;
    options.bounds.relativePad = -1.0f / 64.0f;
    ChcrtTracer shrunk(bvh_, options);
    const CameraPath path = proceduralNearPath(spec_);
    std::map<RayType, size_t> differing;
    FrameStats stats;
    for (int frame = 0; frame < 3; ++frame) {
        const Camera camera = path.cameraAtFrame(frame * 2);
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao}) {
            renderer.generateRayPass(camera, type, 0, stats);
            differing[type] += traceAgainstPureBvh(renderer, shrunk, camera, type, 0, stats).differing;
        }
    }
    EXPECT_GT(differing[RayType::Primary] + differing[RayType::Shadow] + differing[RayType::Ao], 0u);
    EXPECT_EQ(shrunk.totalStats().boundsFromCamera, 0u) << "the GPU's lists read the GPU's reduction";
}

// The recommended configurations of both kinds of renderer (recommendedChcrtOptions: bounds-only with fragment cell
// passes on software rasterisers, bounds-gpu with compute cell passes on GPUs), culling forced, find pure BVH's hits
// over consecutive frames, hints included; here both run on the test's renderer.
TEST_F(RenderTest, RecommendedConfigurationsOfSoftwareAndHardwareRenderersEqualPureBvh) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    const CameraPath path = proceduralNearPath(spec_);
    for (bool software : {true, false}) {
        ChcrtOptions options = recommendedChcrtOptions(RendererTraits{.software = software});
        options.adaptive = false;
        ChcrtTracer chcrt(bvh_, options);
        EXPECT_EQ(chcrt.options().computeCellPass, !software);
        size_t differing = 0, compared = 0;
        FrameStats stats;
        for (int frame = 0; frame < 4; ++frame) {
            const Camera camera = path.cameraAtFrame(frame * 2);
            renderer.renderGBuffer(camera, stats);
            for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
                renderer.generateRayPass(camera, type, 0, stats);
                const OracleComparison traced = traceAgainstPureBvh(renderer, chcrt, camera, type, 0, stats);
                differing += traced.differing;
                compared += traced.reference.size();
            }
        }
        renderer.useTracer(nullptr);
        EXPECT_EQ(differing, 0u) << (software ? "software" : "hardware") << " configuration";
        EXPECT_EQ(compared, 4u * 4u * 96u * 72u);
        EXPECT_EQ(chcrt.totalStats().fallbackTraces, 0u);
        EXPECT_EQ(stats.cappedRays, 0u);
    }
}

// A recommended configuration at height 8 whose adaptive choice has the further heights 6 and 10 and, on fixed times
// where culling wins, explores them at once: every height traces within a few traces.
ChcrtOptions exploringEveryHeight(bool software) {
    ChcrtOptions options = recommendedChcrtOptions(RendererTraits{.software = software});
    options.partition.maxSubtreeHeight = 8;
    options.adaptiveHeights = {6, 10};
    options.adaptiveTiming = [](uint32_t arm, double) { return arm == 0 ? 10.0 : 9.0; };
    options.adaptiveProbeInterval = 1;
    options.adaptiveProbeBudget = 1.0;
    return options;
}

// The tracers of the adaptive choice's further heights link no pass of their own while they trace: they take the
// passes the tracer that made them linked (whose defines do not depend on the height where cells over the list limit
// traverse the whole tree), so a height's first trace does not compile them again (llvmpipe: ~3 ms each). Both
// recommended configurations. Their hits are pure BVH's: the exactness cases with `adaptiveHeights` trace every arm.
TEST_F(RenderTest, TheAdaptiveHeightsTracersShareTheirPassPrograms) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    for (bool software : {true, false}) {
        SCOPED_TRACE(software ? "software configuration" : "hardware configuration");
        const ChcrtOptions options = exploringEveryHeight(software);
        ChcrtTracer probing(bvh_, options);
        ChcrtOptions single = options;
        single.adaptive = false;
        single.adaptiveHeights.clear();
        ChcrtTracer alone(bvh_, single);
        // Programs linked while each tracer traces the same ray sets (variants made on first use: the primary pass
        // that writes every ray, the reductions, ...).
        const auto linkedWhileTracing = [&](ChcrtTracer& tracer, std::set<uint64_t>& heights) {
            const int64_t before = liveGlObjects().programs;
            renderer.useTracer(&tracer);
            for (int trace = 0; trace < 24; ++trace) {
                for (RayType type : {RayType::Primary, RayType::Shadow}) {
                    renderer.generateRayPass(camera, type, 0, stats);
                    renderer.traceRayPass(camera, type, 0, stats);
                    if (tracer.lastStats().fallbackTraces == 0) heights.insert(tracer.lastStats().heightSum);
                }
            }
            renderer.useTracer(nullptr);
            return liveGlObjects().programs - before;
        };
        std::set<uint64_t> probed, once;
        const int64_t probingLinked = linkedWhileTracing(probing, probed);
        const int64_t aloneLinked = linkedWhileTracing(alone, once);
        EXPECT_EQ(probed, (std::set<uint64_t>{6, 8, 10})) << "every height traced";
        EXPECT_EQ(once, (std::set<uint64_t>{8}));
        EXPECT_GT(aloneLinked, 0);
        EXPECT_EQ(probingLinked, aloneLinked) << "the heights' tracers linked passes of their own";
    }
}

// The AO sets of one G-buffer share one reduction of its surface frames whichever heights of the adaptive choice trace
// them: the further heights' tracers bound their cells from the frames the first culled set reduced. Four G-buffers of
// six sets each, culling winning on fixed times so that every height traces.
TEST_F(RenderTest, TheAdaptiveHeightsShareOneSurfaceFramesReductionPerGBuffer) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    ChcrtOptions options = exploringEveryHeight(true);
    ASSERT_TRUE(options.hemisphereBounds);
    options.hintPass = false; // AO sets whose hints go through a hint pass are bounded from their rays instead
    ChcrtTracer chcrt(bvh_, options);
    renderer.useTracer(&chcrt);
    const CameraPath path = proceduralNearPath(spec_);
    FrameStats stats;
    std::set<uint64_t> heights;
    uint64_t culledGBuffers = 0, culledTraces = 0;
    for (int frame = 0; frame < 4; ++frame) {
        const Camera camera = path.cameraAtFrame(frame);
        renderer.renderGBuffer(camera, stats);
        bool culled = false;
        for (int sample = 0; sample < 6; ++sample) {
            renderer.generateRayPass(camera, RayType::Ao, sample, stats);
            renderer.traceRayPass(camera, RayType::Ao, sample, stats);
            if (chcrt.lastStats().fallbackTraces != 0) continue;
            heights.insert(chcrt.lastStats().heightSum);
            culled = true;
            ++culledTraces;
        }
        culledGBuffers += culled ? 1 : 0;
    }
    renderer.useTracer(nullptr);
    EXPECT_EQ(heights, (std::set<uint64_t>{6, 8, 10})) << "every height traced";
    EXPECT_GE(culledGBuffers, 2u);
    EXPECT_EQ(chcrt.totalStats().boundsFromHemisphere, culledTraces);
    EXPECT_EQ(chcrt.totalStats().boundsUpdates, culledGBuffers) << "one reduction of the frames per G-buffer";
}

// The adaptive choice is told which shadow ray sets have hit hints: where culling loses, only AdaptiveChoice::kSeedSets
// sets get a (cold) culled trace and its hints, the others are traced by the pure pass; where culling wins, every set
// is culled. Eight sets over six views, on fixed times.
TEST_F(RenderTest, ALosingCullingSeedsOnlyAFewRaySetsWithHints) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    for (const double cullingMs : {11.0, 9.0}) {
        SCOPED_TRACE(cullingMs > 10.0 ? "culling loses" : "culling wins");
        ChcrtOptions options = recommendedChcrtOptions(RendererTraits{.software = true});
        ASSERT_TRUE(options.hitHints);
        options.adaptiveTiming = [cullingMs](uint32_t arm, double) { return arm == 0 ? 10.0 : cullingMs; };
        ChcrtTracer chcrt(bvh_, options);
        renderer.useTracer(&chcrt);
        int culled = 0;
        for (int view = 0; view < 6; ++view) {
            for (int sample = 0; sample < 8; ++sample) {
                renderer.generateRayPass(camera, RayType::Shadow, sample, stats);
                renderer.traceRayPass(camera, RayType::Shadow, sample, stats);
                culled += chcrt.lastStats().fallbackTraces == 0;
            }
        }
        renderer.useTracer(nullptr);
        if (cullingMs > 10.0) {
            EXPECT_EQ(chcrt.hintImageCount(), size_t(AdaptiveChoice::kSeedSets));
            EXPECT_GT(culled, int(AdaptiveChoice::kSeedSets)) << "measured on the seeded sets";
            EXPECT_LE(culled, 48 / 4);
        } else {
            EXPECT_EQ(chcrt.hintImageCount(), 8u);
            EXPECT_GE(culled, 48 / 2);
        }
    }
}

// The GPU configuration's list decisions (bounds-gpu) of several termination heights link one program: it depends on
// the pieces per cell, not on the hierarchy, so the adaptive choice's heights take it from their shared cache instead
// of each linking it when their tracer is made (a GPU driver compiles at link time).
TEST_F(RenderTest, GpuCellListsOfSeveralHeightsLinkOneProgram) {
    makeProceduralRenderer("city:60k", RenderSettings{});
    const CullingHierarchy low = buildCullingHierarchy(bvh_, SubtreePartitionOptions{.maxSubtreeHeight = 6});
    const CullingHierarchy high = buildCullingHierarchy(bvh_, SubtreePartitionOptions{.maxSubtreeHeight = 10});
    ASSERT_NE(low.subtrees.size(), high.subtrees.size());
    const auto linkedBy = [](const std::function<void()>& make) {
        const int64_t before = liveGlObjects().programs;
        make();
        return liveGlObjects().programs - before;
    };
    auto cache = std::make_shared<ProgramCache>();
    std::unique_ptr<GpuCellLists> first, second, own, otherPieces;
    EXPECT_EQ(linkedBy([&] { first = std::make_unique<GpuCellLists>(low, 4, cache); }), 1);
    EXPECT_EQ(linkedBy([&] { second = std::make_unique<GpuCellLists>(high, 4, cache); }), 0);
    EXPECT_EQ(linkedBy([&] { own = std::make_unique<GpuCellLists>(high, 4); }), 1) << "a cache of its own links again";
    EXPECT_EQ(linkedBy([&] { otherPieces = std::make_unique<GpuCellLists>(high, 2, cache); }), 1)
        << "other pieces, another program";
}

// The renderer's frame targets are made again when its size changes (the viewer's resize, bench's supersampled
// reference), and a deleted texture's GL name can come back for the new one: whatever the tracer keeps per target
// (framebuffers over the active-ray masks and hit depths, hint images, visibility states) must follow, so that the
// hits after a change to another size and back are pure BVH's.
TEST_F(RenderTest, TracesAfterTheRendererChangedSizeEqualPureBvh) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    const CameraPath path = proceduralNearPath(spec_);
    ChcrtOptions options = recommendedChcrtOptions(RendererTraits{.software = true});
    options.adaptive = false;
    ChcrtTracer chcrt(bvh_, options);
    FrameStats stats;
    size_t differing = 0, compared = 0;
    for (int size : {96, 160, 96, 64, 96}) {
        RenderSettings s = settings;
        s.width = size;
        s.height = size * 3 / 4;
        renderer.setSettings(s);
        for (int frame = 0; frame < 2; ++frame) {
            const Camera camera = path.cameraAtFrame(frame);
            renderer.renderGBuffer(camera, stats);
            for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao}) {
                renderer.generateRayPass(camera, type, 0, stats);
                const OracleComparison traced = traceAgainstPureBvh(renderer, chcrt, camera, type, 0, stats);
                differing += traced.differing;
                compared += traced.reference.size();
            }
        }
        EXPECT_EQ(differing, 0u) << "after the change to " << s.width << "x" << s.height;
    }
    renderer.useTracer(nullptr);
    EXPECT_EQ(compared, 2u * 3u * (3u * 96u * 72u + 160u * 120u + 64u * 48u));
    EXPECT_EQ(chcrt.totalStats().fallbackTraces, 0u);
    EXPECT_GT(chcrt.totalStats().hintPasses, 0u);
}

// bounds-only primary rays skip the hit image's clear: their one cell pass draws every cell and stores every ray's
// hit, a miss too, and a trace with nothing to intersect clears the image at its end (ChcrtTracer, cellPassWritesAll_).
// Before each culled trace the hit image is filled with a hit that no ray has, so a pixel the trace did not write
// differs from pure BVH's: views into the scene, and one from outside it looking away (every list empty).
TEST_F(RenderTest, PrimaryCellPassesWriteEveryRaysHitIntoAnUnclearedImage) {
    const RenderSettings settings = smallTraceSettings();
    Renderer& renderer = makeProceduralRenderer("city:60k", settings);
    const CameraPath path = proceduralNearPath(spec_);
    const Aabb bounds = scene_.bounds();
    const glm::vec3 centre = 0.5f * (bounds.lower + bounds.upper);
    Camera away;
    away.eye = bounds.upper + (bounds.upper - bounds.lower);
    away.target = away.eye + (away.eye - centre);
    const GLuint hitTexture = renderer.targets().hits[0].hit.id();
    const std::array<GLuint, 4> stale = {std::bit_cast<GLuint>(1.0f), 7u, 0u, 0u}; // t = 1 on triangle 7
    const std::vector<Camera> cameras = {path.cameraAtFrame(0), path.cameraAtFrame(1), away, path.cameraAtFrame(2)};
    for (bool compute : {false, true}) { // the cell pass as points over the cells, and as a dispatch per cell
        ChcrtOptions options = recommendedChcrtOptions(RendererTraits{.software = true});
        options.adaptive = false;
        options.computeCellPass = compute;
        ChcrtTracer chcrt(bvh_, options);
        FrameStats stats;
        size_t differing = 0, staleDetected = 0;
        for (const Camera& camera : cameras) {
            renderer.generateRayPass(camera, RayType::Primary, 0, stats);
            renderer.useTracer(nullptr);
            renderer.traceRayPass(camera, RayType::Primary, 0, stats);
            const std::vector<Hit> reference = renderer.readHits(0);
            glClearTexImage(hitTexture, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, stale.data());
            const std::vector<Hit> filled = renderer.readHits(0);
            staleDetected += countDifferingHits(reference, filled, false);
            renderer.useTracer(&chcrt);
            renderer.traceRayPass(camera, RayType::Primary, 0, stats);
            const std::vector<Hit> culled = renderer.readHits(0);
            ASSERT_EQ(reference.size(), culled.size());
            differing += countDifferingHits(reference, culled, false);
        }
        renderer.useTracer(nullptr);
        EXPECT_EQ(staleDetected, cameras.size() * 96u * 72u) << "the stale hit must differ from every pixel's hit";
        EXPECT_EQ(differing, 0u) << (compute ? "compute" : "fragment") << " cell passes";
        EXPECT_EQ(chcrt.totalStats().boundsFromCamera, cameras.size());
        EXPECT_EQ(chcrt.totalStats().fallbackTraces, 0u);
    }
}

// A triangle hit computed before its own leaf's box (culling/README.md, "Exactness"): on the 1M plant's far path,
// frame 4, the primary ray of pixel (83, 114) meets triangle 575151 at a computed t of 224.27803 (224.283014 in double
// precision), nearer than the right answer, triangle 567924 at 224.281464, but in a leaf whose box the computed t
// lies before. Pure BVH reached 567924 first and pruned that leaf; CHC+RT's cell list reached the leaf first and kept
// 575151 (one differing pixel before hits' t was clamped to a box's entry: shared/intersect.h, hitRule).
TEST_F(RenderTest, AHitComputedBeforeItsLeafsBoxDoesNotDependOnTheVisitingOrder) {
    RenderSettings settings;
    settings.width = 256;
    settings.height = 256;
    Renderer& renderer = makeProceduralRenderer("plant", settings);
    const Camera camera = proceduralFarPath(spec_).cameraAtFrame(4);
    FrameStats stats;
    renderer.renderGBuffer(camera, stats);
    renderer.generateRayPass(camera, RayType::Primary, 0, stats);
    ChcrtOptions options = recommendedChcrtOptions(RendererTraits{.software = true});
    options.adaptive = false;
    ChcrtTracer chcrt(bvh_, options);
    const OracleComparison traced = traceAgainstPureBvh(renderer, chcrt, camera, RayType::Primary, 0, stats);
    renderer.useTracer(nullptr);
    ASSERT_EQ(traced.reference.size(), traced.traced.size());
    EXPECT_EQ(traced.differing, 0u);
    const size_t pixel = 114u * 256u + 83u;
    // The case is still there: the nearer triangle in double precision.
    EXPECT_EQ(traced.reference[pixel].triangleId, 567924u);
    EXPECT_EQ(traced.traced[pixel].triangleId, 567924u);
}

TEST_F(RenderTest, WithoutTemporalCoherenceEveryTraceStartsFromTheRootPair) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 64;
    Renderer& renderer = makeProceduralRenderer("interior:30k", settings);
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 8;
    options.pairs.minTileSize = 16;
    options.temporalCoherence = false;
    options.adaptive = false;
    ChcrtTracer chcrt(bvh_, options);
    renderer.useTracer(&chcrt);
    const Camera camera = proceduralNearPath(spec_).cameraAtFrame(0);
    FrameStats stats;
    for (int i = 0; i < 2; ++i) {
        renderer.generateRayPass(camera, RayType::Primary, 0, stats);
        renderer.traceRayPass(camera, RayType::Primary, 0, stats);
        // No previous fronts: no Phase 1 work, and the traversal starts with the single root query.
        EXPECT_EQ(chcrt.lastStats().queriesInvisible, 1u);
        EXPECT_EQ(chcrt.lastStats().queriesLazy, 0u);
        EXPECT_GT(chcrt.lastStats().queriesTraversal, 0u);
        EXPECT_EQ(chcrt.lastStats().subtreesScheduled, chcrt.lastStats().pairsNewlyVisible);
    }
}

std::string caseName(const ::testing::TestParamInfo<ExactnessCase>& info) {
    std::string scene = info.param.scene;
    for (char& ch : scene)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return scene + "_h" + std::to_string(info.param.maxSubtreeHeight) + "_tile" + std::to_string(info.param.minTileSize) +
           (info.param.tighterBounds ? "" : "_loose") + "_multi" + std::to_string(info.param.multiQueryPairs) +
           (info.param.adaptive ? "_adaptive" : "") + (info.param.leafCache ? "_leafcache" : "") +
           (info.param.rayExtent ? "" : "_noextent") + (info.param.mergedBatch ? "" : "_persubtree") +
           (info.param.queries == ChcrtQueries::Gl        ? ""
            : info.param.queries == ChcrtQueries::Batched ? "_batched"
                                                   : std::string(info.param.queries == ChcrtQueries::BoundsGpu ? "_gpu" : "") +
                                                         "_bounds_cell" + std::to_string(info.param.boundsCell) +
                                                         "_pieces" + std::to_string(info.param.boundsPieces)) +
           (info.param.boundsPreviousFront ? "_front" : "") + (info.param.adaptiveHeights.empty() ? "" : "_heights") +
           (info.param.cellListLimit ? "_limit" + std::to_string(info.param.cellListLimit) : "") +
           (info.param.hitHints ? "_hints" : "") + (info.param.computeCellPass ? "_compute" : "") +
           (info.param.hintPass ? "_hintpass" : "") + (info.param.closestHitHints ? "_closest" : "") +
           (info.param.shareShadowLists ? "_shared" : "") + (info.param.hemisphereBounds ? "_hemisphere" : "");
}

// Subtree height 8, well below the BVH depth at 60k triangles, so that object-space splits happen; tiles small enough for
// several screen-space levels at 96×72.
const ExactnessCase kExactnessCases[] = {
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16},
    {.scene = "interior:60k", .maxSubtreeHeight = 8, .minTileSize = 16},
    {.scene = "plant:60k", .maxSubtreeHeight = 8, .minTileSize = 16},
    {.scene = "city:60k", .maxSubtreeHeight = 24, .minTileSize = 32},
    // §5.1 options off (tighter bounds, multi-queries)
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .tighterBounds = false, .multiQueryPairs = 1},
    // §5.2 leaf cache on (off by default), once with multi-queries of 8 pairs
    {.scene = "plant:60k", .maxSubtreeHeight = 24, .minTileSize = 32, .leafCache = true},
    {.scene = "interior:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .multiQueryPairs = 8, .leafCache = true},
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .leafCache = true},
    // adaptive fallback on: culled and pure traces mix per ray set
    {.scene = "plant:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .adaptive = true},
    // no ray extent culling (on by default)
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .rayExtent = false},
    // batches traversed subtree by subtree (merged by default)
    {.scene = "plant:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .mergedBatch = false},
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .mergedBatch = false},
    // batched queries (the GL query's test, a round's pairs in one dispatch): heights, tiles of 4 pixels, loose bounds,
    // the adaptive choice, no ray extent culling
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::Batched},
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 4, .tighterBounds = false, .multiQueryPairs = 1,
     .queries = ChcrtQueries::Batched},
    {.scene = "plant:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .adaptive = true, .rayExtent = false,
     .queries = ChcrtQueries::Batched},
    // pairs decided by the ray bounds grid, cell lists: several heights, tiles smaller than a cell, cells from 4 to 16
    // pixels, 1 to 8 pieces
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly},
    {.scene = "interior:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly},
    {.scene = "plant:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly},
    {.scene = "city:60k", .maxSubtreeHeight = 24, .minTileSize = 32, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 16, .boundsPieces = 1},
    {.scene = "plant:60k", .maxSubtreeHeight = 12, .minTileSize = 4, .queries = ChcrtQueries::BoundsOnly,
     .boundsPieces = 8},
    {.scene = "interior:60k", .maxSubtreeHeight = 6, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 4, .boundsPieces = 2},
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .adaptive = true,
     .queries = ChcrtQueries::BoundsOnly},
    // the previous visible front first (two rounds, two reductions)
    {.scene = "interior:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .boundsPreviousFront = true},
    {.scene = "city:60k", .maxSubtreeHeight = 12, .minTileSize = 4, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 4, .boundsPieces = 8, .boundsPreviousFront = true},
    // the adaptive choice among the pure pass and three heights
    {.scene = "city:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .adaptive = true,
     .queries = ChcrtQueries::BoundsOnly, .adaptiveHeights = {6, 10}},
    // cells with more than 3 (or 12) subtrees traverse the whole BVH
    {.scene = "city:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .cellListLimit = 3},
    {.scene = "plant:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 4, .cellListLimit = 12},
    // hit hints: any-hit rays visit the leaf of their previous hit first
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .hitHints = true},
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .cellListLimit = 12, .hitHints = true},
    {.scene = "plant:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .adaptive = true,
     .queries = ChcrtQueries::BoundsOnly, .adaptiveHeights = {10}, .cellListLimit = 64, .hitHints = true},
    // cell lists decided on the GPU: heights, cells, pieces, list limits (3: cells over it traverse the whole tree),
    // hints, the adaptive choice
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu},
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .boundsCell = 4, .boundsPieces = 8, .cellListLimit = 3, .hitHints = true},
    {.scene = "plant:60k", .maxSubtreeHeight = 6, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .boundsCell = 16, .boundsPieces = 1, .cellListLimit = 12},
    {.scene = "city:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .adaptive = true,
     .queries = ChcrtQueries::BoundsGpu, .adaptiveHeights = {10}, .cellListLimit = 64, .hitHints = true},
    // the cell passes as compute dispatches (CPU and GPU lists, hints, cells of 4 and 16 pixels, the whole tree over a
    // list limit)
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .hitHints = true, .computeCellPass = true},
    {.scene = "plant:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .boundsCell = 4, .cellListLimit = 12, .hitHints = true, .computeCellPass = true},
    {.scene = "interior:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .boundsCell = 16, .boundsPieces = 2, .computeCellPass = true},
    // without a list limit the GPU's longest lists still go to the whole tree
    {.scene = "interior:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .boundsCell = 16, .boundsPieces = 2},
    // the hint pass (fragment and compute), the rays left traced compacted: cells of 4 to 16 pixels, a list limit, the
    // adaptive choice
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .hitHints = true, .hintPass = true},
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 4, .cellListLimit = 12, .hitHints = true, .computeCellPass = true, .hintPass = true},
    {.scene = "plant:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .adaptive = true,
     .queries = ChcrtQueries::BoundsOnly, .boundsCell = 16, .adaptiveHeights = {10}, .cellListLimit = 64,
     .hitHints = true, .hintPass = true},
    // closest-hit rays with hints too: in the cell pass (bounds-only), after the hint pass (bounds-only, compute;
    // bounds-gpu, the adaptive choice)
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .hitHints = true, .closestHitHints = true},
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 4, .cellListLimit = 12, .hitHints = true, .computeCellPass = true, .hintPass = true,
     .closestHitHints = true},
    {.scene = "plant:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .adaptive = true,
     .queries = ChcrtQueries::BoundsGpu, .adaptiveHeights = {10}, .cellListLimit = 64, .hitHints = true,
     .hintPass = true, .closestHitHints = true},
    // the hint pass before lists decided on the GPU (compute, as on GPUs, and fragment)
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .hitHints = true, .computeCellPass = true, .hintPass = true},
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .boundsCell = 4, .boundsPieces = 8, .cellListLimit = 3, .hitHints = true, .hintPass = true},
    // a frame's shadow ray sets sharing one grid swept to the light and its lists: after the hint pass (fragment and
    // compute), without hints (every active ray through the lists, a list limit), with the adaptive choice
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .hitHints = true, .hintPass = true, .shareShadowLists = true},
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 4, .boundsPieces = 8, .cellListLimit = 12, .shareShadowLists = true},
    {.scene = "plant:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 16, .boundsPieces = 2, .hitHints = true, .computeCellPass = true, .hintPass = true,
     .shareShadowLists = true},
    {.scene = "city:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .adaptive = true,
     .queries = ChcrtQueries::BoundsOnly, .boundsCell = 16, .adaptiveHeights = {10}, .cellListLimit = 64,
     .hitHints = true, .hintPass = true, .shareShadowLists = true},
    // ... and lists decided on the GPU: after the hint pass in compute (as on GPUs), without hints in fragment passes
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .boundsCell = 16, .cellListLimit = 12, .hitHints = true, .computeCellPass = true, .hintPass = true,
     .shareShadowLists = true},
    {.scene = "city:60k", .maxSubtreeHeight = 8, .minTileSize = 16, .queries = ChcrtQueries::BoundsGpu,
     .boundsCell = 8, .boundsPieces = 2, .shareShadowLists = true},
    // AO ray sets bounded from their G-buffer's surface frames: with hints in the cell pass (fragment, small cells, a
    // list limit), and in the recommended configuration (the hint pass, shared shadow lists, the adaptive choice)
    {.scene = "interior:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .queries = ChcrtQueries::BoundsOnly,
     .boundsCell = 4, .boundsPieces = 8, .cellListLimit = 12, .hitHints = true, .hemisphereBounds = true},
    {.scene = "plant:60k", .maxSubtreeHeight = 12, .minTileSize = 16, .adaptive = true,
     .queries = ChcrtQueries::BoundsOnly, .boundsCell = 16, .adaptiveHeights = {10}, .cellListLimit = 64,
     .hitHints = true, .hintPass = true, .shareShadowLists = true, .hemisphereBounds = true},
};

INSTANTIATE_TEST_SUITE_P(ProceduralScenes, ChcrtExactnessTest, ::testing::ValuesIn(kExactnessCases), caseName);

} // namespace
} // namespace chcrt::test
