// `chcrt bench`: compares tracing methods on the same rays, per ray type, over frames of a walkthrough.
// Method: for every run, frame and sample the rays are generated once and every method traces those same rays
// (ratios within one run, as DEVELOPERS.md asks); only tracing is timed (glFinish before and after). One
// untimed warm-up run compiles shaders and fills caches. ms_median = median over runs of the mean tracing
// time per frame (all samples of a frame). Mrays/s counts active rays (pixels without a surface shoot no
// secondary rays). diff_pixels / psnr_db compare with pure BVH GLSL tracing: for embree, diff_pixels counts
// hit-buffer pixels that differ beyond the stated tolerance (renderer/render/hit_comparison.h) and psnr_db is
// null (it produces hits, not an image).
#include "app/commands.h"
#include "app/outofcore_report.h"
#include "app/methods.h"
#include "app/report.h"
#include "app/session.h"
#include "linespace/linespace_image_error.h"
#include "linespace/linespace_tracer.h"
#include "linespace/ntree_tracer.h"
#include "renderer/core/error.h"
#include "renderer/gl/context.h"
#include "renderer/reference/embree_tracer.h"
#include "renderer/render/hit_comparison.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

namespace chcrt::app {
namespace {

struct MethodResult {
    std::vector<double> runMs; // mean ms per frame, per timed run
    uint64_t activeRays = 0;   // per timed run, summed over frames and samples
    HitComparison comparison;
    ChcrtStats chcrt;          // CHC+RT counters over the timed runs (chcrt methods only)
    outofcore::OutOfCoreStats outOfCore; // --out-of-core: Table 3 counters over the timed runs
    nlohmann::json outOfCoreFrames = nlohmann::json::array(); // per trace of the first timed run
    uint64_t steps = 0, stepRays = 0; // --steps: traversal steps over the active rays of the first timed run
};

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

uint64_t countActive(const std::vector<Ray>& rays) {
    return uint64_t(std::count_if(rays.begin(), rays.end(), [](const Ray& r) { return r.tmax > r.tmin; }));
}

// Adds the steps of the active rays (encoding of ChcrtDebugImage::Cost); a capped ray's count is incomplete.
void addSteps(const std::vector<Ray>& rays, const std::vector<uint32_t>& steps, const std::string& method,
              MethodResult& result) {
    for (size_t i = 0; i < rays.size() && i < steps.size(); ++i) {
        if (!(rays[i].tmax > rays[i].tmin)) continue;
        if (steps[i] & kChcrtCostCappedBit) {
            throw std::runtime_error("rays reached the shader loop cap while counting steps (" + method + ")");
        }
        result.steps += steps[i] & kChcrtCostStepMask;
        ++result.stepRays;
    }
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
    const RenderSettings settings = toRenderSettings(o, 1);

    SceneSession session = openSceneSession(o);
    const std::vector<int> frames = selectFrames(o, session.path, "spread:5");
    GpuSession gpu = openGpuSession(o, session, settings);
    Renderer& renderer = *gpu.renderer;
    // Pure BVH tracing always runs: it is the reference for speedups and differing pixels. Not for an
    // --out-of-core scene that is not loaded in core: there is no whole-scene BVH to trace (docs/outofcore.md).
    if (!session.sceneInCore && wantEmbree) throw InputError("--method embree needs the scene in core (--load-in-core on)");
    std::vector<std::string> gpuMethodNames;
    if (session.sceneInCore) gpuMethodNames.push_back("bvh");
    std::map<std::string, std::unique_ptr<Tracer>> tracers;
    for (const std::string& m : methods) {
        if (!findMethod(m).gpu || m == kPureBvhMethod) continue;
        gpuMethodNames.push_back(m);
        tracers[m] = makeTracer(m, session);
    }
    outofcore::OutOfCoreTracer* gbufferTracer = nullptr; // scene not in core: primary visibility for secondary rays
    for (const auto& [name, tracer] : tracers) {
        auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(tracer.get());
        if (ooc && !session.sceneInCore && !gbufferTracer) gbufferTracer = ooc;
    }
    if (gbufferTracer) installOutOfCorePrimary(renderer, *gbufferTracer);
    std::unique_ptr<EmbreeTracer> embree;
    if (wantEmbree) embree = std::make_unique<EmbreeTracer>(session.scene);
    const float diagonal = renderer.sceneDiagonal();
    HitTolerance tolerance;
    tolerance.absoluteT *= diagonal;

    // Image error of approximate methods against pure BVH tracing (Line Space issue): whole frames with the
    // effects and spp of the command line, rendered once per tracer (untimed), final and indirect-only images.
    std::map<std::string, ls::ImageError> imageErrors;
    for (const std::string& m : gpuMethodNames) {
        if (m != "bvh" && !findGpuMethod(m).exact) {
            imageErrors[m] = ls::measureImageError(renderer, *tracers[m], session.path, frames);
        }
    }
    const auto finiteOrNull = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };

    Table table;
    table.header = {"scene", "path", "ray_type", "method", "size", "spp", "ms/frame", "Mrays/s", "speedup", "diff_px",
                    "PSNR dB"};
    if (options.steps) table.header.push_back("steps/ray");
    nlohmann::json rowsJson = nlohmann::json::array();
    const int totalRuns = options.warmupRuns + options.runs;
    session.progress->begin("Benchmarking", uint64_t(rayTypes.size()) * totalRuns * frames.size());
    uint64_t progressDone = 0;
    for (RayType type : rayTypes) {
        std::map<std::string, MethodResult> results;
        for (int run = 0; run < totalRuns; ++run) {
            const bool timed = run >= options.warmupRuns;
            const bool compare = run == options.warmupRuns; // compare hits once, in the first timed run
            std::map<std::string, double> runMs;
            for (int frame : frames) {
                const Camera camera = session.path.cameraAtFrame(frame);
                FrameStats scratch;
                if (type != RayType::Primary) {
                    // Not in core: the G-buffer comes from out-of-core primary rays (docs/outofcore.md).
                    if (gbufferTracer) renderer.useTracer(gbufferTracer);
                    renderer.renderGBuffer(camera, scratch);
                    renderer.useTracer(nullptr);
                }
                for (int sample = 0; sample < settings.samplesPerPixel; ++sample) {
                    renderer.generateRayPass(camera, type, sample, scratch);
                    // Read back once per pass, outside the timed tracing: for the comparisons and the ray count.
                    std::vector<Ray> rays;
                    if (compare || timed) rays = renderer.readRays(0);
                    const bool comparing = compare && session.sceneInCore && (embree || gpuMethodNames.size() > 1);
                    std::vector<Hit> bvhHits;
                    for (const std::string& m : gpuMethodNames) {
                        renderer.useTracer(m == "bvh" ? nullptr : tracers[m].get());
                        FrameStats methodStats;
                        auto* outOfCore =
                            m == "bvh" ? nullptr : dynamic_cast<outofcore::OutOfCoreTracer*>(tracers[m].get());
                        const outofcore::OutOfCoreStats oocBefore =
                            outOfCore ? outOfCore->snapshot() : outofcore::OutOfCoreStats{};
                        renderer.traceRayPass(camera, type, sample, methodStats);
                        if (outOfCore && timed) {
                            const outofcore::OutOfCoreStats d =
                                outofcore::OutOfCoreStats::difference(outOfCore->snapshot(), oocBefore);
                            results[m].outOfCore += d;
                            if (compare) {
                                nlohmann::json f = outOfCoreStatsJson(d, 1.0, *outOfCore);
                                f["frame"] = frame;
                                f["sample"] = sample;
                                results[m].outOfCoreFrames.push_back(f);
                            }
                        }
                        if (methodStats.cappedRays > 0) {
                            throw std::runtime_error("rays reached the shader loop cap during the benchmark (" + m + ")");
                        }
                        runMs[m] += methodStats.traceMs();
                        ChcrtTracer* c = nullptr;
                        if (m != "bvh") {
                            c = dynamic_cast<ChcrtTracer*>(tracers[m].get());
                            if (auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(tracers[m].get())) c = &ooc->chcrt();
                            if (c) {
                                if (timed) results[m].chcrt += c->totalStats(); // CHC+RT counters (no warm-up)
                                c->resetStats();
                            }
                        }
                        if (comparing) {
                            if (m == "bvh") {
                                bvhHits = renderer.readHits(0);
                            } else {
                                results[m].comparison.differing +=
                                    compareHitsExactly(rays, renderer.readHits(0), bvhHits, isAnyHit(type)).differing;
                            }
                        }
                        if (!options.steps || !compare) continue;
                        // Work, not time: pure BVH's cost target of the timed trace; CHC+RT counts only with its
                        // cost debug image, so it traces the pass once more, untimed (its fronts advance once
                        // more; debug traces do not feed the adaptive choice).
                        if (m == "bvh") {
                            addSteps(rays, renderer.readTraceSteps(0), m, results[m]);
                        } else if (c) {
                            c->setDebugImage(ChcrtDebugImage::Cost);
                            c->clearDebugImage();
                            FrameStats untimed;
                            renderer.traceRayPass(camera, type, sample, untimed);
                            addSteps(rays, c->readDebugImage(), m, results[m]);
                            c->setDebugImage(ChcrtDebugImage::None);
                            c->resetStats();
                        }
                    }
                    renderer.useTracer(nullptr);
                    if (!timed) continue;
                    const uint64_t active = countActive(rays);
                    for (const std::string& m : methods) results[m].activeRays += active;
                    if (!embree) continue;
                    std::vector<Hit> hits(rays.size());
                    const auto start = std::chrono::steady_clock::now();
                    embree->trace(rays, hits, isAnyHit(type));
                    runMs["embree"] +=
                        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
                    if (compare) {
                        // Closest-hit Embree for the comparison, so ids are known (any-hit results carry none).
                        std::vector<Hit> reference(rays.size());
                        embree->trace(rays, reference, false);
                        results["embree"].comparison.add(
                            compareHits(session.scene, rays, bvhHits, reference, isAnyHit(type), tolerance));
                    }
                }
                session.progress->update(++progressDone);
            }
            if (!timed) continue;
            for (const std::string& m : methods) results[m].runMs.push_back(runMs[m] / double(frames.size()));
            if (std::find(methods.begin(), methods.end(), "bvh") == methods.end()) {
                results["bvh"].runMs.push_back(runMs["bvh"] / double(frames.size())); // reference for speedups
            }
        }
        const double bvhMs = median(results["bvh"].runMs);
        for (const std::string& m : methods) {
            const MethodResult& r = results[m];
            const double ms = median(r.runMs);
            const double raysPerFrame = double(r.activeRays) / double(options.runs) / double(frames.size());
            const double mrays = ms > 0 ? raysPerFrame / (ms * 1000.0) : 0.0;
            const double speedup = ms > 0 ? bvhMs / ms : 0.0;
            const uint64_t diff = m == "bvh" ? 0 : r.comparison.differing; // bvh is the reference itself
            table.rows.push_back({session.scene.name, session.path.name, toString(type), m,
                                  std::to_string(settings.width) + "x" + std::to_string(settings.height),
                                  std::to_string(settings.samplesPerPixel), formatFixed(ms, 1), formatFixed(mrays, 2),
                                  formatFixed(speedup, 2), session.sceneInCore ? std::to_string(diff) : "-",
                                  imageErrors.count(m) ? formatFixed(imageErrors[m].finalPsnrDb, 1) : "-"});
            const bool stepsCounted = options.steps && r.stepRays > 0;
            const double stepsPerRay = stepsCounted ? double(r.steps) / double(r.stepRays) : 0.0;
            if (options.steps) table.rows.back().push_back(stepsCounted ? formatFixed(stepsPerRay, 1) : "-");
            rowsJson.push_back({{"scene", session.scene.name},
                                {"path", session.path.name},
                                {"ray_type", toString(type)},
                                {"method", m},
                                {"width", settings.width},
                                {"height", settings.height},
                                {"spp", settings.samplesPerPixel},
                                {"frames", frames.size()},
                                {"runs", options.runs},
                                {"ms_median", ms},
                                {"ms_runs", r.runMs},
                                {"mrays_per_s", mrays},
                                {"active_rays_per_frame", raysPerFrame},
                                {"speedup_vs_bvh", speedup},
                                {"diff_pixels", session.sceneInCore ? nlohmann::json(diff) : nlohmann::json(nullptr)},
                                {"edge_cases", m == "bvh" ? 0 : r.comparison.edgeCases},
                                {"psnr_db", nullptr},
                                {"steps_per_ray", stepsCounted ? nlohmann::json(stepsPerRay) : nlohmann::json(nullptr)}});
            if (imageErrors.count(m)) {
                const ls::ImageError& e = imageErrors[m];
                nlohmann::json& row = rowsJson.back();
                row["psnr_db"] = finiteOrNull(e.finalPsnrDb);
                row["image_error"] = {{"frames", e.frames}, {"effects", toString(settings.effects)},
                                      {"spp", settings.samplesPerPixel}, {"final_mae", e.finalMae},
                                      {"final_psnr_db", finiteOrNull(e.finalPsnrDb)},
                                      {"final_pixels_over_2_255", e.finalOver2Of255}, {"indirect_mae", e.indirectMae},
                                      {"indirect_psnr_db", finiteOrNull(e.indirectPsnrDb)}};
                if (type == RayType::Shadow && raysPerFrame > 0) {
                    // The hit comparison runs in the first timed run: differing any-hit answers / active rays.
                    row["shadow_samples_differing_fraction"] =
                        double(diff) / (raysPerFrame * double(frames.size()));
                }
            }
            if (auto* lsTracer = dynamic_cast<ls::LineSpaceTracer*>(m == "bvh" ? nullptr : tracers[m].get())) {
                const ls::LineSpaceStats& st = lsTracer->buildStats;
                rowsJson.back()["linespace"] = {
                    {"params", lsTracer->paramsText}, {"modes", lsTracer->modes().toString()},
                    {"cache", lsTracer->cacheOutcome}, {"build_s", st.buildSeconds}, {"spaces", st.spaceCount},
                    {"bytes", st.totalBytes()}, {"mb", double(st.totalBytes()) / 1e6},
                    {"binary_filled", st.binaryShafts ? double(st.binaryFilled) / double(st.binaryShafts) : 0.0},
                    {"candidate_filled", st.candidateShafts ? double(st.candidateFilled) / double(st.candidateShafts) : 0.0},
                    {"bytes_per_shaft", double(st.totalBytes()) / double(std::max<uint64_t>(1, st.binaryShafts + st.candidateShafts))},
                    {"gpu_bytes", lsTracer->gpu().gpuBytes()}};
            }
            if (auto* nt = dynamic_cast<ls::NTreeTracer*>(m == "bvh" ? nullptr : tracers[m].get())) {
                const ls::NTreeStats& st = nt->buildStats;
                rowsJson.back()["ntree"] = {
                    {"params", nt->paramsText}, {"cache", nt->cacheOutcome}, {"build_s", st.buildSeconds},
                    {"nodes", st.nodeCount},
                    {"spaces", st.subdividedCount},
                    {"binary_filled", st.binaryShafts ? double(st.binaryFilled) / double(st.binaryShafts) : 0.0},
                    {"linespace_mb", double(st.lineSpaceBytes) / 1e6}, {"node_pool_mb", double(st.nodeBytes) / 1e6},
                    {"gpu_bytes", nt->gpuBytes()}, {"shadow_level", nt->options().shadowLevel},
                    {"start_exact", nt->options().startExact}, {"near_edges", nt->options().nearEdges}};
            }
            if (auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(m == "bvh" ? nullptr : tracers[m].get())) {
                nlohmann::json j = outOfCoreStatsJson(r.outOfCore, double(options.runs) * double(frames.size()), *ooc);
                j["frames"] = r.outOfCoreFrames;
                rowsJson.back()["outofcore"] = j;
            }
            if (r.chcrt.traces > 0) {
                rowsJson.back()["chcrt"] = chcrtStatsJson(r.chcrt, double(options.runs) * double(frames.size()));
            }
        }
    }
    session.progress->end();

    const GlInfo info = queryGlInfo();
    std::printf("bench: %s (%s triangles%s), %zu frame(s) of %s, median of %d run(s) after %d warm-up, %s\n",
                session.scene.name.c_str(),
                formatCount(session.sceneInCore ? session.scene.triangleCount() : session.fileTriangles).c_str(),
                session.sceneInCore ? "" : ", not in core", frames.size(),
                session.path.name.c_str(), options.runs, options.warmupRuns, info.renderer.c_str());
    std::fputs(table.toText().c_str(), stdout);
    if (!options.jsonFile.empty()) {
        writeJsonFile(options.jsonFile, {{"scene", toJson(session.scene)},
                                         {"bvh", toJson(session.bvh.stats)},
                                         {"gl_renderer", info.renderer},
                                         {"rows", rowsJson}});
    }
    if (!options.csvFile.empty()) writeTextFileAtomically(options.csvFile, table.toCsv());
    if (!options.markdownFile.empty()) writeTextFileAtomically(options.markdownFile, table.toMarkdown());
    return kExitOk;
}

} // namespace chcrt::app
