// `chcrt bench`: compares tracing methods on the same rays, per ray type, over frames of a walkthrough.
// Method: for every run, frame and sample the rays are generated once and every method traces those same rays
// (ratios within one run: runs vary by ±40 % here), pure BVH first and the others in alternating order
// (benchTraceOrder); only tracing is timed (glFinish before and after). One untimed warm-up run compiles shaders and
// fills caches. ms_median = median over runs of the mean tracing time per frame (all samples of a frame). Mrays/s
// counts active rays (pixels without a surface shoot no secondary rays). diff_pixels / psnr_db compare with pure BVH
// GLSL tracing (chcrt-lod's psnr_db: with exact out-of-core CHC+RT, whose hits equal pure BVH's, through the same
// primary resolve): for embree, diff_pixels counts hit-buffer pixels that differ beyond the stated tolerance
// (renderer/render/hit_comparison.h) and psnr_db is null (it produces hits, not an image).
#include "app/commands.h"
#include "app/outofcore_report.h"
#include "app/methods.h"
#include "app/report.h"
#include "app/session.h"
#include "linespace/linespace_image_error.h"
#include "linespace/linespace_tracer.h"
#include "linespace/ntree_tracer.h"
#include "renderer/core/error.h"
#include "renderer/core/statistics.h"
#include "renderer/gl/context.h"
#include "renderer/reference/embree_tracer.h"
#include "renderer/render/hit_comparison.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <thread>

namespace chcrt::app {
namespace {

struct MethodResult {
    std::vector<double> runMs; // mean ms per frame, per timed run
    uint64_t activeRays = 0;   // per timed run, summed over frames and samples
    HitComparison comparison;
    ChcrtStats chcrt;          // CHC+RT counters over the timed runs (chcrt methods only)
    outofcore::OutOfCoreStats outOfCore; // --out-of-core: Table 3 counters over the timed runs
    nlohmann::json outOfCoreFrames = nlohmann::json::array(); // per trace of the first timed run
    uint64_t steps = 0, stepRays = 0; // --steps: traversal steps over the active rays of the last timed run
    // Per frame (index into Bench::frames): its tracing time per timed run (all samples), and CHC+RT counters
    // summed over the timed runs, for the curves along the walkthrough (row field frame_times).
    std::vector<std::vector<double>> frameRunMs;
    std::vector<ChcrtStats> frameChcrt;
};

uint64_t countActive(const std::vector<Ray>& rays) {
    return uint64_t(std::count_if(rays.begin(), rays.end(), [](const Ray& r) { return r.tmax > r.tmin; }));
}

// Adds the steps of the active rays (encoding of ChcrtDebugImage::Cost); a capped ray's count is incomplete.
void addSteps(const std::vector<Ray>& rays, const std::vector<uint32_t>& steps, const std::string& method,
              MethodResult& result) {
    for (size_t i = 0; i < rays.size() && i < steps.size(); ++i) {
        if (!(rays[i].tmax > rays[i].tmin)) continue;
        if (steps[i] & CHCRT_TRACE_STEPS_CAPPED) {
            throw std::runtime_error("rays reached the shader loop cap while counting steps (" + method + ")");
        }
        result.steps += steps[i] & CHCRT_TRACE_STEPS_COUNT;
        ++result.stepRays;
    }
}

} // namespace

namespace {

// Everything a benchmark traces with: the scene, its renderer, the methods' tracers and the references.
struct Bench {
    const BenchOptions& options;
    RenderSettings settings; // as given (out of core the renderer may drop the diffuse effect)
    SceneSession session;
    GpuSession gpu;
    std::vector<int> frames;
    std::vector<std::string> methods;        // as given (embree included)
    std::vector<std::string> gpuMethodNames; // traced on the GPU: pure BVH first (the reference), when in core
    std::map<std::string, std::unique_ptr<Tracer>> tracers;
    outofcore::OutOfCoreTracer* gbufferTracer = nullptr; // scene not in core: primary visibility for secondary rays
    RenderSettings rendererSettings;     // the renderer's as opened (LOD image errors switch primary visibility)
    std::unique_ptr<Tracer> lodReference; // exact out-of-core CHC+RT for chcrt-lod's image error, when not benchmarked
    std::unique_ptr<EmbreeTracer> embree;
    HitTolerance tolerance;
    std::map<std::string, ls::ImageError> imageErrors;
    MachineSnapshot started = takeMachineSnapshot(); // load average before the benchmark, for the JSON

    Tracer* tracer(const std::string& m) const { return m == kPureBvhMethod ? nullptr : tracers.at(m).get(); }
    Renderer& renderer() { return *gpu.renderer; }
};

// Makes `t` the renderer's tracer with the G-buffer it needs: a tracer of LOD proxies (or any out-of-core tracer of a
// scene not in core) resolves its own primary hits; otherwise the session's G-buffer tracer, or the in-core passes.
void useTracerWithPrimary(Bench& b, Tracer* t) {
    Renderer& renderer = b.renderer();
    auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(t);
    if (ooc && needsOutOfCorePrimary(*ooc, b.session.sceneInCore)) {
        installOutOfCorePrimary(renderer, *ooc);
    } else if (b.gbufferTracer) {
        installOutOfCorePrimary(renderer, *b.gbufferTracer);
    } else {
        renderer.setOutOfCorePrimary({});
        renderer.setSettings(b.rendererSettings);
    }
    renderer.useTracer(t);
}

// The exact reference of chcrt-lod's image error: exact CHC+RT through the same GPU cache design and the same primary
// resolve, so that the proxies are the only difference (its hits equal pure BVH's: `verify`). Not in core a benchmarked
// exact out-of-core method serves (it resolves the session's G-buffer anyway); else one is made, so that the timed
// tracers are not changed by the measurement (a resolve records subtrees on every primary trace).
outofcore::OutOfCoreTracer& lodReference(Bench& b) {
    for (const auto& [name, tracer] : b.tracers) {
        auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(tracer.get());
        if (ooc && !b.session.sceneInCore && !ooc->lodEnabled() && findGpuMethod(name).exact) return *ooc;
    }
    if (!b.lodReference) b.lodReference = makeTracer("chcrt", b.session);
    return dynamic_cast<outofcore::OutOfCoreTracer&>(*b.lodReference);
}

// Pure BVH tracing always runs: it is the reference for speedups and differing pixels. Not for an --out-of-core
// scene that is not loaded in core: there is no whole-scene BVH to trace (docs/outofcore.md).
void makeTracers(Bench& b, bool wantEmbree) {
    if (!b.session.sceneInCore && wantEmbree) throw InputError("--method embree needs the scene in core (--load-in-core on)");
    if (b.session.sceneInCore) b.gpuMethodNames.push_back(kPureBvhMethod);
    for (const std::string& m : b.methods) {
        if (!findMethod(m).gpu || m == kPureBvhMethod) continue;
        b.gpuMethodNames.push_back(m);
        b.tracers[m] = makeTracer(m, b.session);
    }
    // Not in core, the secondary rays of every method start from one G-buffer: an exact method's when there is one.
    for (bool exactOnly : {true, false}) {
        for (const auto& [name, tracer] : b.tracers) {
            auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(tracer.get());
            if (ooc && !b.session.sceneInCore && !b.gbufferTracer && (!exactOnly || !ooc->lodEnabled())) b.gbufferTracer = ooc;
        }
    }
    b.rendererSettings = b.renderer().settings();
    if (b.gbufferTracer) installOutOfCorePrimary(b.renderer(), *b.gbufferTracer);
    if (wantEmbree) b.embree = std::make_unique<EmbreeTracer>(b.session.scene);
    b.tolerance.absoluteT *= b.renderer().sceneDiagonal();
    // Image error of approximate methods against pure BVH tracing (Line Space issue): whole frames with the
    // effects and spp of the command line, rendered once per tracer (untimed), final and indirect-only images.
    // chcrt-lod (issue #19) against exact out-of-core CHC+RT, each frame with its own tracer's primary resolve.
    for (const std::string& m : b.gpuMethodNames) {
        if (m == kPureBvhMethod || findGpuMethod(m).exact) continue;
        auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(b.tracers[m].get());
        if (ooc && ooc->lodEnabled()) {
            outofcore::OutOfCoreTracer& reference = lodReference(b);
            const ls::UseTracer use = [&b, &reference](Tracer* t) {
                if (t != &reference) return useTracerWithPrimary(b, t);
                installOutOfCorePrimary(b.renderer(), reference); // the same resolve as chcrt-lod's, also in core
                b.renderer().useTracer(t);
            };
            b.imageErrors[m] = ls::measureImageError(b.renderer(), *ooc, &reference, use, b.session.path, b.frames,
                                                     b.options.referenceSupersample);
        } else {
            b.imageErrors[m] = ls::measureImageError(b.renderer(), *b.tracers[m], b.session.path, b.frames,
                                                     b.options.referenceSupersample);
        }
    }
}

// One pass of rays, as every method traces it in a run.
struct Pass {
    RayType type;
    int frame = 0, sample = 0;
    size_t frameIndex = 0; // into Bench::frames
    Camera camera;
    bool timed = false, compare = false; // compare hits once, in the first timed run
    // --steps: count the work in the last timed run, whose traces are like most of those the median reports (in the
    // first, sample sets can still be on their first culled trace, without hints, or on the adaptive choice's pure
    // passes: castle street, 16 shadow spp, chcrt 26.2 steps per ray counted there against 4.6 for chcrt-noadapt).
    bool countSteps = false;
    std::vector<Ray> rays;
    std::vector<Hit> bvhHits;
    std::vector<uint32_t> bvhSteps; // --steps: pure BVH's cost image of the pass (in core)
};

// Work, not time (--steps): pure BVH's cost target of the timed trace; CHC+RT counts only with its cost debug
// image, so it traces the pass once more, untimed, from the hit hints the timed trace started from (`hintsBefore`),
// and leaves the hints the timed trace left (its fronts advance once more; debug traces do not feed the adaptive
// choice). A timed trace that the adaptive choice gave to a pure pass did pure BVH's work: those steps are counted
// (in core, where pure BVH traced the pass first), not those culling would have done.
void countSteps(Bench& b, Pass& pass, const std::string& m, ChcrtTracer* chcrt,
                const ChcrtTracer::HintSnapshot* hintsBefore, MethodResult& result) {
    if (m == kPureBvhMethod) {
        pass.bvhSteps = b.renderer().readTraceSteps(0);
        addSteps(pass.rays, pass.bvhSteps, m, result);
    } else if (chcrt && chcrt->lastStats().fallbackTraces > 0 && !pass.bvhSteps.empty()) {
        addSteps(pass.rays, pass.bvhSteps, m, result);
    } else if (chcrt) {
        const ChcrtTracer::HintSnapshot hintsAfter = chcrt->saveHints();
        if (hintsBefore) chcrt->restoreHints(*hintsBefore);
        chcrt->setDebugImage(ChcrtDebugImage::Cost);
        chcrt->clearDebugImage();
        FrameStats untimed;
        b.renderer().traceRayPass(pass.camera, pass.type, pass.sample, untimed);
        addSteps(pass.rays, chcrt->readDebugImage(), m, result);
        chcrt->setDebugImage(ChcrtDebugImage::None);
        chcrt->restoreHints(hintsAfter);
        chcrt->resetStats();
    }
}

// Traces the pass with one GPU method: its time, CHC+RT and out-of-core counters, hits against pure BVH.
void tracePass(Bench& b, Pass& pass, const std::string& m, double& runMs, MethodResult& result, bool comparing) {
    Renderer& renderer = b.renderer();
    renderer.useTracer(b.tracer(m));
    FrameStats methodStats;
    auto* outOfCore = dynamic_cast<outofcore::OutOfCoreTracer*>(b.tracer(m));
    const outofcore::OutOfCoreStats oocBefore = outOfCore ? outOfCore->snapshot() : outofcore::OutOfCoreStats{};
    ChcrtTracer* chcrt = outOfCore ? &outOfCore->chcrt() : dynamic_cast<ChcrtTracer*>(b.tracer(m));
    const bool counting = pass.countSteps;
    std::optional<ChcrtTracer::HintSnapshot> hintsBefore;
    if (counting && chcrt) hintsBefore = chcrt->saveHints();
    renderer.traceRayPass(pass.camera, pass.type, pass.sample, methodStats);
    if (outOfCore && pass.timed) {
        const outofcore::OutOfCoreStats d = outofcore::OutOfCoreStats::difference(outOfCore->snapshot(), oocBefore);
        result.outOfCore += d;
        if (pass.compare) {
            nlohmann::json f = outOfCoreStatsJson(d, 1.0, *outOfCore);
            f["frame"] = pass.frame;
            f["sample"] = pass.sample;
            result.outOfCoreFrames.push_back(f);
        }
    }
    if (methodStats.cappedRays > 0) throw std::runtime_error("rays reached the shader loop cap during the benchmark (" + m + ")");
    runMs += methodStats.traceMs();
    if (chcrt) {
        if (pass.timed) {
            result.chcrt += chcrt->totalStats(); // CHC+RT counters (no warm-up)
            if (result.frameChcrt.size() <= pass.frameIndex) result.frameChcrt.resize(b.frames.size());
            result.frameChcrt[pass.frameIndex] += chcrt->totalStats();
        }
        chcrt->resetStats();
    }
    if (comparing) {
        if (m == kPureBvhMethod) pass.bvhHits = renderer.readHits(0);
        else result.comparison.differing += compareHitsExactly(pass.rays, renderer.readHits(0), pass.bvhHits, isAnyHit(pass.type)).differing;
    }
    if (counting) countSteps(b, pass, m, chcrt, hintsBefore ? &*hintsBefore : nullptr, result);
}

// Embree on the pass's read-back rays (timed), and its hits against pure BVH's in the comparing run.
void traceEmbree(Bench& b, const Pass& pass, double& runMs, MethodResult& result) {
    std::vector<Hit> hits(pass.rays.size());
    const auto start = std::chrono::steady_clock::now();
    b.embree->trace(pass.rays, hits, isAnyHit(pass.type));
    runMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!pass.compare) return;
    // Closest-hit Embree for the comparison, so ids are known (any-hit results carry none).
    std::vector<Hit> reference(pass.rays.size());
    b.embree->trace(pass.rays, reference, false);
    result.comparison.add(compareHits(b.session.scene, pass.rays, pass.bvhHits, reference, isAnyHit(pass.type), b.tolerance));
}

// The time each method spent on one frame of a timed run (its runMs grew by that much over the frame).
void addFrameTimes(const Bench& b, size_t frameIndex, const std::map<std::string, double>& before,
                   std::map<std::string, double>& after, std::map<std::string, MethodResult>& results) {
    for (auto& [m, ms] : after) {
        MethodResult& r = results[m];
        if (r.frameRunMs.size() < b.frames.size()) r.frameRunMs.resize(b.frames.size());
        const auto was = before.find(m);
        r.frameRunMs[frameIndex].push_back(ms - (was == before.end() ? 0.0 : was->second));
    }
}

// Every run, frame and sample of one ray type: the rays are generated once and each method traces those.
std::map<std::string, MethodResult> benchRayType(Bench& b, RayType type, uint64_t& progressDone) {
    Renderer& renderer = b.renderer();
    const int samples = b.settings.samplesPerPixel;
    std::map<std::string, MethodResult> results;
    for (int run = 0; run < b.options.warmupRuns + b.options.runs; ++run) {
        std::map<std::string, double> runMs;
        for (size_t frameIndex = 0; frameIndex < b.frames.size(); ++frameIndex) {
            const int frame = b.frames[frameIndex];
            Pass pass{type, frame, 0, frameIndex, b.session.path.cameraAtFrame(frame), run >= b.options.warmupRuns,
                      run == b.options.warmupRuns,
                      b.options.steps && run == b.options.warmupRuns + b.options.runs - 1};
            const std::map<std::string, double> msBefore = runMs;
            FrameStats scratch;
            if (type != RayType::Primary) {
                // Not in core: the G-buffer comes from out-of-core primary rays (docs/outofcore.md).
                if (b.gbufferTracer) renderer.useTracer(b.gbufferTracer);
                renderer.renderGBuffer(pass.camera, scratch);
                renderer.useTracer(nullptr);
            }
            for (pass.sample = 0; pass.sample < samples; ++pass.sample) {
                renderer.generateRayPass(pass.camera, type, pass.sample, scratch);
                // Read back once per pass, outside the timed tracing: for the comparisons and the ray count.
                pass.rays = pass.compare || pass.timed ? renderer.readRays(0) : std::vector<Ray>{};
                pass.bvhHits.clear();
                pass.bvhSteps.clear();
                const bool comparing = pass.compare && b.session.sceneInCore && (b.embree || b.gpuMethodNames.size() > 1);
                const size_t passIndex =
                    (size_t(run) * b.frames.size() + frameIndex) * size_t(samples) + size_t(pass.sample);
                for (const std::string& m : benchTraceOrder(b.gpuMethodNames, passIndex)) {
                    tracePass(b, pass, m, runMs[m], results[m], comparing);
                }
                renderer.useTracer(nullptr);
                if (!pass.timed) continue;
                const uint64_t active = countActive(pass.rays);
                for (const std::string& m : b.methods) results[m].activeRays += active;
                if (b.embree) traceEmbree(b, pass, runMs["embree"], results["embree"]);
            }
            // Read ahead for the next frames while this run goes on (--prefetch-frames; untimed, as it overlaps).
            for (const std::string& m : b.gpuMethodNames) {
                if (auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(b.tracer(m))) {
                    prefetchAfterFrame(*ooc, b.session.path, b.frames, frameIndex, b.settings.width, b.settings.height);
                }
            }
            if (pass.timed) addFrameTimes(b, frameIndex, msBefore, runMs, results);
            b.session.progress->update(++progressDone);
        }
        if (run < b.options.warmupRuns) continue;
        for (const std::string& m : b.methods) results[m].runMs.push_back(runMs[m] / double(b.frames.size()));
        if (std::find(b.methods.begin(), b.methods.end(), kPureBvhMethod) == b.methods.end()) {
            results[kPureBvhMethod].runMs.push_back(runMs[kPureBvhMethod] / double(b.frames.size())); // reference for speedups
        }
    }
    return results;
}

nlohmann::json finiteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json lineSpaceJson(const ls::LineSpaceTracer& t) {
    const ls::LineSpaceStats& st = t.buildStats;
    return {{"params", t.paramsText}, {"modes", t.modes().toString()},
            {"cache", t.cacheOutcome}, {"build_s", st.buildSeconds}, {"spaces", st.spaceCount},
            {"bytes", st.totalBytes()}, {"mb", double(st.totalBytes()) / 1e6},
            {"binary_filled", st.binaryShafts ? double(st.binaryFilled) / double(st.binaryShafts) : 0.0},
            {"candidate_filled", st.candidateShafts ? double(st.candidateFilled) / double(st.candidateShafts) : 0.0},
            {"bytes_per_shaft", double(st.totalBytes()) / double(std::max<uint64_t>(1, st.binaryShafts + st.candidateShafts))},
            {"gpu_bytes", t.gpu().gpuBytes()}};
}

nlohmann::json nTreeJson(const ls::NTreeTracer& nt) {
    const ls::NTreeStats& st = nt.buildStats;
    return {{"params", nt.paramsText}, {"cache", nt.cacheOutcome}, {"build_s", st.buildSeconds},
            {"nodes", st.nodeCount}, {"spaces", st.subdividedCount},
            {"binary_filled", st.binaryShafts ? double(st.binaryFilled) / double(st.binaryShafts) : 0.0},
            {"linespace_mb", double(st.lineSpaceBytes) / 1e6}, {"node_pool_mb", double(st.nodeBytes) / 1e6},
            {"gpu_bytes", nt.gpuBytes()}, {"shadow_level", nt.options().shadowLevel},
            {"start_exact", nt.options().startExact}, {"near_edges", nt.options().nearEdges}};
}

// The image error of an approximate method (Line Space issue) in its JSON row.
void addImageError(nlohmann::json& row, const ls::ImageError& e, const RenderSettings& settings, RayType type,
                   uint64_t diff, double raysPerFrame, size_t frames) {
    row["psnr_db"] = finiteOrNull(e.finalPsnrDb);
    row["image_error"] = {{"frames", e.frames}, {"effects", toString(settings.effects)},
                          {"spp", settings.samplesPerPixel}, {"final_mae", e.finalMae},
                          {"final_psnr_db", finiteOrNull(e.finalPsnrDb)},
                          {"final_pixels_over_2_255", e.finalOver2Of255}, {"indirect_mae", e.indirectMae},
                          {"indirect_psnr_db", finiteOrNull(e.indirectPsnrDb)},
                          {"reference_supersample", e.referenceSupersample},
                          {"filtered_psnr_db", finiteOrNull(e.filteredPsnrDb)},
                          {"sampling_floor_psnr_db", finiteOrNull(e.samplingFloorPsnrDb)}};
    if (type == RayType::Shadow && raysPerFrame > 0) {
        // The hit comparison runs in the first timed run: differing any-hit answers / active rays.
        row["shadow_samples_differing_fraction"] = double(diff) / (raysPerFrame * double(frames));
    }
}

// frame_times: each frame's tracing time per timed run and, for CHC+RT rows, its counters as means over the timed
// runs (the `frames` field already holds the frame count, which readers of older JSON rely on).
nlohmann::json frameTimesJson(const Bench& b, const MethodResult& r) {
    nlohmann::json frames = nlohmann::json::array();
    for (size_t i = 0; i < r.frameRunMs.size() && i < b.frames.size(); ++i) {
        nlohmann::json f = {{"frame", b.frames[i]}, {"ms_runs", r.frameRunMs[i]}};
        if (i < r.frameChcrt.size() && r.frameChcrt[i].traces > 0) {
            const ChcrtStats& c = r.frameChcrt[i];
            const double runs = double(b.options.runs);
            f["chcrt"] = {{"traces", double(c.traces) / runs},
                          {"fallback_traces", double(c.fallbackTraces) / runs},
                          {"queries", double(c.queries) / runs},
                          {"subtrees_scheduled", double(c.subtreesScheduled) / runs},
                          {"phase1_ms", c.phase1Ms / runs},
                          {"phase2_ms", c.phase2Ms / runs},
                          {"phase3_ms", c.phase3Ms / runs},
                          {"fallback_ms", c.fallbackMs / runs}};
        }
        frames.push_back(std::move(f));
    }
    return frames;
}

// The CHC+RT configuration a row ran (after the method's defaults), so that tables can tell thresholds and forced
// heights apart without knowing the command line.
nlohmann::json chcrtOptionsJson(const ChcrtOptions& o) {
    return {{"threshold", o.visibleThreshold},
            {"height", o.partition.maxSubtreeHeight},
            {"adaptive", o.adaptive},
            {"adaptive_heights", o.adaptiveHeights},
            {"queries", toString(o.queries)},
            {"cell_pass", o.computeCellPass ? "compute" : "fragment"},
            {"min_tile", o.pairs.minTileSize}};
}

// Milliseconds per traversal step (--steps): `msPerFrame` over the steps the row's active rays of a frame took; 0
// when steps were not counted.
double msPerStep(const Bench& b, const MethodResult& r, double msPerFrame) {
    if (!b.options.steps || r.stepRays == 0 || r.steps == 0) return 0.0;
    const double raysPerFrame = double(r.activeRays) / double(b.options.runs) / double(b.frames.size());
    return msPerFrame / (double(r.steps) / double(r.stepRays) * raysPerFrame);
}

// Speedup over pure BVH: the median over the timed runs of pure BVH's time over the method's in the same run; 0
// without pure BVH's runs. Within a run every method traces each pass right after the others (benchTraceOrder), so a
// run's ratio is taken under one state of the machine; the ratio of the two medians mixes runs, and on a machine whose
// speed changed during a process (pure BVH at 11.5 ms a frame for four runs of the castle's primary rays, then 15.8)
// it fell outside the spread of the runs' own ratios (1.03 against 1.12-1.19 but for the run of the change).
double pairedSpeedup(const std::vector<double>& bvhRunMs, const std::vector<double>& runMs) {
    std::vector<double> ratios;
    for (size_t i = 0; i < std::min(bvhRunMs.size(), runMs.size()); ++i) {
        if (bvhRunMs[i] > 0 && runMs[i] > 0) ratios.push_back(bvhRunMs[i] / runMs[i]);
    }
    return median(ratios);
}

// The table row and JSON row of one method and ray type. `bvhRunMs`: pure BVH's time per frame in each timed run
// (empty where it did not run); `bvhMsPerStep`: its ms per step (0 without --steps).
void addRows(Bench& b, RayType type, const std::string& m, const MethodResult& r,
             const std::vector<double>& bvhRunMs, double bvhMsPerStep, Table& table, nlohmann::json& rowsJson) {
    const RenderSettings& settings = b.settings;
    const SceneSession& session = b.session;
    const double frames = double(b.frames.size());
    const double ms = median(r.runMs);
    const double raysPerFrame = double(r.activeRays) / double(b.options.runs) / frames;
    const double mrays = ms > 0 ? raysPerFrame / (ms * 1000.0) : 0.0;
    // Without pure BVH (a prepared scene not loaded in core) there is nothing to compare with.
    const double speedup = pairedSpeedup(bvhRunMs, r.runMs);
    const double bvhMs = median(bvhRunMs);
    const uint64_t diff = m == kPureBvhMethod ? 0 : r.comparison.differing; // bvh is the reference itself
    const auto imageError = b.imageErrors.find(m);
    // Rows traced through the GPU subtree cache are marked: beside in-core rows of the same method name they are
    // another measurement (docs/outofcore.md).
    const auto gpuTracer = b.tracers.find(m); // embree and pure BVH have none
    const bool outOfCore = gpuTracer != b.tracers.end() &&
                           dynamic_cast<const outofcore::OutOfCoreTracer*>(gpuTracer->second.get()) != nullptr;
    table.rows.push_back({session.scene.name, session.path.name, toString(type), outOfCore ? m + " (out of core)" : m,
                          std::to_string(settings.width) + "x" + std::to_string(settings.height),
                          std::to_string(settings.samplesPerPixel), formatFixed(ms, 1), formatFixed(mrays, 2),
                          speedup > 0 ? formatFixed(speedup, 2) : "-", session.sceneInCore ? std::to_string(diff) : "-",
                          imageError != b.imageErrors.end() ? formatFixed(imageError->second.finalPsnrDb, 1) : "-"});
    const bool stepsCounted = b.options.steps && r.stepRays > 0;
    const double stepsPerRay = stepsCounted ? double(r.steps) / double(r.stepRays) : 0.0;
    // What a traversal step costs (--steps): pure BVH's whole trace per step, and a CHC+RT row's subtree passes per
    // step against that (only when every trace culled: the adaptive choice's pure passes have no subtree passes).
    const double rowMsPerStep = m == kPureBvhMethod ? msPerStep(b, r, ms) : 0.0;
    const bool allCulled = r.chcrt.traces > 0 && r.chcrt.fallbackTraces == 0;
    const double subtreeMsPerStep =
        allCulled ? msPerStep(b, r, r.chcrt.estimatedPassMs(r.chcrt.subtreePassMs) / (double(b.options.runs) * frames))
                  : 0.0;
    const double stepCost = subtreeMsPerStep > 0 && bvhMsPerStep > 0 ? subtreeMsPerStep / bvhMsPerStep : 0.0;
    if (b.options.steps) {
        table.rows.back().push_back(stepsCounted ? formatFixed(stepsPerRay, 1) : "-");
        table.rows.back().push_back(stepCost > 0 ? formatFixed(stepCost, 2) : "-");
    }
    if (b.options.referenceSupersample > 1) {
        const bool measured = imageError != b.imageErrors.end();
        table.rows.back().push_back(measured ? formatFixed(imageError->second.filteredPsnrDb, 1) : "-");
        table.rows.back().push_back(measured ? formatFixed(imageError->second.samplingFloorPsnrDb, 1) : "-");
    }
    table.rows.back().push_back(r.chcrt.traces ? formatFixed(100.0 * r.chcrt.culledShare(), 0) + "%" : "-");
    table.rows.back().push_back(r.chcrt.culledTraces() ? formatFixed(r.chcrt.meanHeight(), 1) : "-");
    nlohmann::json row = {{"scene", session.scene.name},
                          {"out_of_core", outOfCore},
                          {"path", session.path.name},
                          {"ray_type", toString(type)},
                          {"method", m},
                          {"width", settings.width},
                          {"height", settings.height},
                          {"spp", settings.samplesPerPixel},
                          {"frames", b.frames.size()},
                          {"runs", b.options.runs},
                          {"ms_median", ms},
                          {"ms_runs", r.runMs},
                          {"mrays_per_s", mrays},
                          {"active_rays_per_frame", raysPerFrame},
                          {"speedup_vs_bvh", speedup > 0 ? nlohmann::json(speedup) : nlohmann::json(nullptr)},
                          {"speedup_of_medians",
                           ms > 0 && bvhMs > 0 ? nlohmann::json(bvhMs / ms) : nlohmann::json(nullptr)},
                          {"diff_pixels", session.sceneInCore ? nlohmann::json(diff) : nlohmann::json(nullptr)},
                          {"edge_cases", m == kPureBvhMethod ? 0 : r.comparison.edgeCases},
                          {"psnr_db", nullptr},
                          {"steps_per_ray", stepsCounted ? nlohmann::json(stepsPerRay) : nlohmann::json(nullptr)},
                          {"ms_per_step", rowMsPerStep > 0 ? nlohmann::json(rowMsPerStep) : nlohmann::json(nullptr)},
                          {"subtree_ms_per_step",
                           subtreeMsPerStep > 0 ? nlohmann::json(subtreeMsPerStep) : nlohmann::json(nullptr)},
                          {"step_cost_vs_bvh", stepCost > 0 ? nlohmann::json(stepCost) : nlohmann::json(nullptr)}};
    if (imageError != b.imageErrors.end()) {
        addImageError(row, imageError->second, settings, type, diff, raysPerFrame, b.frames.size());
    }
    const Tracer* tracer = findMethod(m).gpu ? b.tracer(m) : nullptr;
    if (const auto* lsTracer = dynamic_cast<const ls::LineSpaceTracer*>(tracer)) row["linespace"] = lineSpaceJson(*lsTracer);
    if (const auto* nt = dynamic_cast<const ls::NTreeTracer*>(tracer)) row["ntree"] = nTreeJson(*nt);
    if (const auto* ooc = dynamic_cast<const outofcore::OutOfCoreTracer*>(tracer)) {
        nlohmann::json j = outOfCoreStatsJson(r.outOfCore, double(b.options.runs) * frames, *ooc);
        j["frames"] = r.outOfCoreFrames;
        row["outofcore"] = j;
    }
    row["frame_times"] = frameTimesJson(b, r);
    if (r.chcrt.traces > 0) {
        row["chcrt"] = chcrtStatsJson(r.chcrt, double(b.options.runs) * frames);
        Tracer* t = b.tracer(m); // a GPU method: only those count CHC+RT traces
        auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(t);
        const ChcrtTracer* chcrt = ooc ? &ooc->chcrt() : dynamic_cast<const ChcrtTracer*>(t);
        if (chcrt) row["chcrt"]["options"] = chcrtOptionsJson(chcrt->options());
    }
    rowsJson.push_back(std::move(row));
}

// The settings every row of the file shares, as they ran (defaults included), for readers that compare files.
nlohmann::json settingsJson(const Bench& b) {
    const RenderSettings& s = b.settings;
    return {{"width", s.width}, {"height", s.height}, {"spp", s.samplesPerPixel}, {"effects", toString(s.effects)},
            {"seed", s.seed}, {"rotation", s.rotationDegrees}, {"ao_length", s.aoLengthFraction},
            {"exposure", s.exposure}, {"primary", toString(s.primaryVisibility)}, {"runs", b.options.runs},
            {"warmup", b.options.warmupRuns}, {"steps", b.options.steps},
            {"shader_stage", toString(b.gpu.renderer->pureTracerStage())}};
}

void writeOutputs(const Bench& b, const Table& table, const nlohmann::json& rowsJson) {
    const MachineSnapshot finished = takeMachineSnapshot();
    const GlInfo info = queryGlInfo();
    const SceneSession& session = b.session;
    std::printf("bench: %s (%s triangles%s), %zu frame(s) of %s, median of %d run(s) after %d warm-up, %s on %s, "
                "%u cores\n",
                session.scene.name.c_str(), formatCount(sceneTriangles(session)).c_str(),
                session.sceneInCore ? "" : ", not in core", b.frames.size(), session.path.name.c_str(), b.options.runs,
                b.options.warmupRuns, info.renderer.c_str(), cpuModel().c_str(), std::thread::hardware_concurrency());
    std::fputs(table.toText().c_str(), stdout);
    // The two error columns measure different things, and a row's PSNR repeats on each of its ray types' rows.
    if (!b.imageErrors.empty()) std::printf("diff_px: pixels whose hits of that ray type differ from pure BVH's; frame PSNR: the whole shaded "
                "frame (all --effects) against pure BVH's, the same on every ray type's row of a method\n");
    if (!b.imageErrors.empty() && b.options.referenceSupersample > 1) {
        const int k = b.options.referenceSupersample;
        std::printf("filtered PSNR: the frame against exact frames rendered at %dx%d the resolution and box-filtered; exact "
                    "filtered: the exact 1-sample frame against the same (its sampling error)\n", k, k);
    }
    if (!b.options.jsonFile.empty()) {
        nlohmann::json json = {{"scene", toJson(session.scene)},
                               {"bvh", toJson(session.bvh.stats)},
                               {"machine", machineJson(b.started, finished)},
                               {"command_line", processCommandLine()},
                               {"settings", settingsJson(b)},
                               {"rows", rowsJson}};
        json.update(glJson(info));
        writeJsonFile(b.options.jsonFile, json);
    }
    if (!b.options.csvFile.empty()) writeTextFileAtomically(b.options.csvFile, table.toCsv());
    if (!b.options.markdownFile.empty()) writeTextFileAtomically(b.options.markdownFile, table.toMarkdown());
    std::string written; // every file a command writes is named in its output
    for (const std::string& file : {b.options.jsonFile, b.options.csvFile, b.options.markdownFile}) {
        if (!file.empty()) written += (written.empty() ? "" : ", ") + file;
    }
    if (!written.empty()) std::printf("wrote %s\n", written.c_str());
}

} // namespace

int runBench(const BenchOptions& options) {
    const CommonOptions& o = options.common;
    const std::vector<std::string> methods = splitList(options.methods);
    std::vector<RayType> rayTypes;
    for (const std::string& name : splitList(options.rayTypes)) rayTypes.push_back(parseRayType(name));
    bool wantEmbree = false;
    for (const std::string& m : methods) wantEmbree |= !findMethod(m).gpu;
    if (options.runs < 1) throw InputError("--runs must be at least 1");
    if (options.warmupRuns < 0) throw InputError("--warmup must not be negative");
    checkOutputFiles({options.jsonFile, options.csvFile, options.markdownFile});
    Bench b{options, toRenderSettings(o, 1), openSceneSession(o)};
    b.methods = methods;
    b.frames = selectFrames(o, b.session.path, "spread:5");
    b.gpu = openGpuSession(o, b.session, b.settings);
    makeTracers(b, wantEmbree);

    Table table;
    table.header = {"scene", "path", "ray_type", "method", "size", "spp", "ms/frame", "Mrays/s", "speedup", "diff_px",
                    "frame PSNR dB"};
    if (options.steps) {
        table.header.push_back("steps/ray");
        table.header.push_back("step cost"); // a subtree pass's ms per step over pure BVH's
    }
    if (options.referenceSupersample > 1) {
        table.header.push_back("filtered PSNR dB");
        table.header.push_back("exact filtered dB");
    }
    // What a CHC+RT row ran: the share of its traces that culled (the rest were the adaptive choice's pure passes)
    // and the mean termination height of the culling traces.
    table.header.push_back("culled");
    table.header.push_back("H");
    nlohmann::json rowsJson = nlohmann::json::array();
    b.session.progress->begin("Benchmarking",
                              uint64_t(rayTypes.size()) * (options.warmupRuns + options.runs) * b.frames.size());
    uint64_t progressDone = 0;
    for (RayType type : rayTypes) {
        std::map<std::string, MethodResult> results = benchRayType(b, type, progressDone);
        const MethodResult& bvh = results[kPureBvhMethod];
        const double bvhMsPerStep = msPerStep(b, bvh, median(bvh.runMs));
        for (const std::string& m : methods) addRows(b, type, m, results[m], bvh.runMs, bvhMsPerStep, table, rowsJson);
    }
    b.session.progress->end();
    writeOutputs(b, table, rowsJson);
    return kExitOk;
}

} // namespace chcrt::app
