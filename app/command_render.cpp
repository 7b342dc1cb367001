// `chcrt render` and `chcrt demo`: shaded frames of a walkthrough to image files, with a timing summary.
#include "app/commands.h"
#include "app/build_info.h"
#include "app/outofcore_report.h"
#include "app/methods.h"
#include "app/render_records.h"
#include "app/resource_log.h"
#include "app/report.h"
#include "app/session.h"
#include "renderer/core/error.h"
#include "renderer/core/frame_range.h"
#include "renderer/core/image_io.h"
#include "renderer/core/timing.h"
#include "renderer/gl/context.h"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <unistd.h>

namespace chcrt::app {
namespace {

bool isHdrFormat(const std::string& file) {
    const std::string ext = std::filesystem::path(file).extension().string();
    return ext == ".exr" || ext == ".EXR" || ext == ".hdr" || ext == ".HDR";
}

// The method's tracer and its CHC+RT / out-of-core views, installed in the renderer.
struct RenderTracer {
    std::unique_ptr<Tracer> tracer;
    outofcore::OutOfCoreTracer* outOfCore = nullptr; // --out-of-core (Table 3 statistics)
    ChcrtTracer* chcrt = nullptr;                    // CHC+RT statistics and debug images
    ChcrtDebugImage debugImage = ChcrtDebugImage::None;
};

// --debug-image, checked before anything is loaded.
ChcrtDebugImage debugImageOf(const RenderOptions& options) {
    const MethodInfo& method = findGpuMethod(options.method);
    const ChcrtDebugImage kind =
        options.debugImage.empty() ? ChcrtDebugImage::None : parseChcrtDebugImage(options.debugImage);
    if (kind != ChcrtDebugImage::None && !method.chcrtDebugImages) {
        throw InputError("--debug-image needs a CHC+RT method (--method chcrt, chcrt-aggressive or chcrt-noadapt)");
    }
    return kind;
}

RenderTracer makeRenderTracer(const RenderOptions& options, ChcrtDebugImage debugImage, const SceneSession& session,
                              Renderer& renderer) {
    RenderTracer t;
    t.debugImage = debugImage;
    t.tracer = makeTracer(options.method, session);
    t.outOfCore = dynamic_cast<outofcore::OutOfCoreTracer*>(t.tracer.get());
    t.chcrt = t.outOfCore ? &t.outOfCore->chcrt() : dynamic_cast<ChcrtTracer*>(t.tracer.get());
    if (t.chcrt) t.chcrt->setDebugImage(t.debugImage);
    if (t.outOfCore && needsOutOfCorePrimary(*t.outOfCore, session.sceneInCore)) {
        installOutOfCorePrimary(renderer, *t.outOfCore); // docs/outofcore.md
    }
    renderer.useTracer(t.tracer.get());
    return t;
}

// Writes the frame just rendered: the shaded image, or the CHC+RT debug image accumulated over every trace of
// the frame (all ray sets).
void writeFrameImage(const std::string& file, const RenderTracer& t, Renderer& renderer) {
    if (t.debugImage == ChcrtDebugImage::None) {
        writeImage(file, isHdrFormat(file) ? renderer.readHdrImage() : renderer.readDisplayImage());
        return;
    }
    ImageRgba32f image;
    image.width = t.chcrt->debugWidth();
    image.height = t.chcrt->debugHeight();
    const std::vector<float> rgb = colorizeChcrtDebugImage(t.debugImage, t.chcrt->readDebugImage(), image.width, image.height);
    image.pixels.resize(size_t(image.width) * image.height * 4, 1.0f);
    for (size_t p = 0; p < rgb.size() / 3; ++p) {
        for (int c = 0; c < 3; ++c) image.pixels[p * 4 + size_t(c)] = rgb[p * 3 + size_t(c)];
    }
    writeImage(file, image, /*alreadyDisplayEncoded=*/true);
}

void addFrameStats(FrameStats& sum, const FrameStats& stats) {
    sum.totalMs += stats.totalMs;
    sum.gbufferMs += stats.gbufferMs;
    sum.raygenMs += stats.raygenMs;
    sum.shadeMs += stats.shadeMs;
    for (size_t t = 0; t < sum.trace.size(); ++t) {
        sum.trace[t].milliseconds += stats.trace[t].milliseconds;
        sum.trace[t].passes += stats.trace[t].passes;
    }
    sum.raysGenerated += stats.raysGenerated;
    sum.cappedRays += stats.cappedRays;
}

struct RenderedFrames {
    // Every selected frame's image, resumed ones included: how many, the first and the last (a walkthrough of any
    // length keeps its memory flat: nothing here grows with the frames unless --stats-json asks for them).
    size_t written = 0;
    std::string firstWritten, lastWritten;
    size_t rendered = 0;              // frames rendered by this run (the others were proven done by records)
    FrameStats sum;                   // of the frames rendered by this run
    outofcore::OutOfCoreStats outOfCore; // --out-of-core: Table 3 counters summed over those frames
    std::vector<int> incomplete;      // --out-of-core frames with subtree requests postponed (--uploads-per-trace)
    nlohmann::json json = nlohmann::json::array(); // every frame's statistics, kept only for --stats-json
};

// The run-level fields of --stats-json, also the header line of --records.
nlohmann::json runJson(const RenderOptions& options, const SceneSession& session, const RenderSettings& settings,
                       const std::string& glRenderer) {
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    nlohmann::json json = {{"command", options.demo ? "demo" : "render"},
            {"scene", toJson(session.scene)},
            {"bvh", toJson(session.bvh.stats)},
            {"path", session.path.name},
            {"width", settings.width},
            {"height", settings.height},
            {"spp", settings.samplesPerPixel},
            {"effects", toString(settings.effects)},
            {"primary", toString(settings.primaryVisibility)},
            {"seed", settings.seed},
            {"gl_renderer", glRenderer},
            {"host", host},
            {"commit", buildCommit()},
            {"flags_digest", flagsDigest(options.words)},
            {"arguments", options.words},
            {"shader_stage", toString(resolveTraceStage(preferredTraceStage()))}};
    json.update(glJson(queryGlInfo())); // gl_renderer again, with vendor, version and software_renderer
    return json;
}

// --resume: the frames whose records prove them done (render_records.h), with their recorded statistics.
std::map<int, nlohmann::json> framesProvenDone(const RenderOptions& options, const std::vector<int>& frames) {
    std::map<int, nlohmann::json> done;
    if (!options.resume) return done;
    const RecordsFile records = readRecordsFile(options.records);
    const std::string digest = flagsDigest(options.words);
    for (const FrameRecord& r : records.frames) {
        if (recordProvesFrame(r, formatFramePath(options.output, r.frame, int(frames.size())), digest, buildCommit())) {
            done[r.frame] = r.stats;
        }
    }
    return done;
}

// Test hooks, right after frame k's image and record are written: CHCRT_FAULT_KILL_AFTER_FRAME=k kills the process
// with SIGKILL, as a scheduler's kill would (the farm's fault tests, docs/farm.md); CHCRT_FAULT_STALL_AFTER_FRAME=k
// waits there until a signal ends the process (a task for scancel to cancel); CHCRT_FAULT_STOP_AFTER_FRAME=k
// stops it with SIGSTOP, so that a test can change the files it reads (a prepared scene truncated or overwritten
// under an out-of-core render) before it continues it with SIGCONT (docs/robustness.md).
void faultInjectedAfterFrame(int frame) {
    const auto at = [frame](const char* variable) {
        const char* value = std::getenv(variable);
        return value != nullptr && *value != '\0' && std::atoi(value) == frame;
    };
    if (at("CHCRT_FAULT_KILL_AFTER_FRAME")) std::raise(SIGKILL);
    if (at("CHCRT_FAULT_STOP_AFTER_FRAME")) std::raise(SIGSTOP);
    if (at("CHCRT_FAULT_STALL_AFTER_FRAME")) {
        std::fflush(nullptr);
        for (;;) ::pause();
    }
}

// A frame that fails on its input (a prepared scene's subtree that cannot be read or is corrupted) names the frame;
// nothing of it is written.
FrameStats renderFrameNamingIt(Renderer& renderer, const Camera& camera, int frame) {
    try {
        return renderer.renderFrame(camera);
    } catch (const InputError& e) {
        throw InputError("frame " + std::to_string(frame) + " not rendered: " + e.what());
    }
}

RenderedFrames renderFrames(const RenderOptions& options, const SceneSession& session, Renderer& renderer,
                            const RenderTracer& t, const std::vector<int>& frames, const std::string& glRenderer,
                            std::chrono::steady_clock::time_point started) {
    RenderedFrames out;
    const std::map<int, nlohmann::json> done = framesProvenDone(options, frames);
    std::unique_ptr<RecordsWriter> records;
    if (!options.records.empty()) records = std::make_unique<RecordsWriter>(options.records);
    if (options.resume && !options.common.quiet) {
        std::printf("resume: %zu of %zu frame(s) already rendered (records in %s)\n", done.size(), frames.size(),
                    options.records.c_str());
    }
    std::vector<int> todo;
    for (int frame : frames) {
        if (!done.count(frame)) todo.push_back(frame);
    }
    if (!todo.empty()) renderer.warmUp(session.path.cameraAtFrame(todo.front()));
    if (records) {
        // Start-up: scene, BVH, GL set-up and the warm-up frame (shader compilation), what a farm task pays once.
        nlohmann::json header = runJson(options, session, renderer.settings(), glRenderer);
        header["startup_s"] = millisecondsSince(started) / 1000.0;
        records->append({{"header", header}});
    }
    // Progress per pass, so that a single slow frame (many samples, a big scene) shows progress too.
    uint64_t passesDone = 0;
    session.progress->beginItems("Rendering", todo.size(), renderer.passesPerFrame(), "frame");
    renderer.setPassCallback([&] { session.progress->update(++passesDone); });
    const RenderSettings& settings = renderer.settings();
    const std::string digest = flagsDigest(options.words);
    ResourceLog resourceLog;
    const bool keepJson = !options.common.statsJson.empty();
    if (!options.resourceLog.empty()) resourceLog = ResourceLog(options.resourceLog, options.resourceEvery);
    size_t todoIndex = 0; // of the frame being rendered, for the read-ahead's next cameras
    for (int frame : frames) {
        const std::string file = formatFramePath(options.output, frame, int(frames.size()));
        if (out.written++ == 0) out.firstWritten = file;
        out.lastWritten = file;
        if (const auto d = done.find(frame); d != done.end()) {
            if (keepJson) out.json.push_back(d->second);
            continue;
        }
        if (t.chcrt) {
            t.chcrt->resetStats();
            t.chcrt->clearDebugImage();
        }
        const outofcore::OutOfCoreStats oocBefore = t.outOfCore ? t.outOfCore->snapshot() : outofcore::OutOfCoreStats{};
        const FrameStats stats = renderFrameNamingIt(renderer, session.path.cameraAtFrame(frame), frame);
        // Read ahead while this frame's image is written and the next one renders (--prefetch-frames).
        if (t.outOfCore) prefetchAfterFrame(*t.outOfCore, session.path, todo, todoIndex++, settings.width, settings.height);
        writeFrameImage(file, t, renderer);
        // The frame's statistics as JSON only for a file that keeps them: a long walkthrough without one allocates
        // nothing per frame for them (the soak runs, docs/robustness.md).
        const bool wantJson = keepJson || records;
        nlohmann::json j;
        if (wantJson) {
            j = toJson(stats, uint64_t(settings.width) * settings.height);
            j["frame"] = frame;
            j["resources"] = sampleResourcesJson();
            j["output"] = file;
            j["method"] = options.method;
            if (t.chcrt) j["chcrt"] = chcrtStatsJson(t.chcrt->totalStats(), 1.0);
        }
        if (t.outOfCore) {
            const outofcore::OutOfCoreStats frameStats =
                outofcore::OutOfCoreStats::difference(t.outOfCore->snapshot(), oocBefore);
            if (wantJson) j["outofcore"] = outOfCoreStatsJson(frameStats, 1.0, *t.outOfCore);
            out.outOfCore += frameStats;
            if (frameStats.cachePostponed > 0) out.incomplete.push_back(frame);
        }
        if (records) {
            records->append({{"frame", frame},
                             {"output", file},
                             {"image_checksum", fileChecksum(file)},
                             {"flags_digest", digest},
                             {"commit", buildCommit()},
                             {"stats", j}});
        }
        if (keepJson) out.json.push_back(std::move(j));
        addFrameStats(out.sum, stats);
        if (out.rendered % kReleaseFreedMemoryEvery == kReleaseFreedMemoryEvery - 1) releaseFreedMemory();
        resourceLog.frameDone(out.rendered, out.rendered + 1 == todo.size(), {{"path_frame", frame}});
        ++out.rendered;
        faultInjectedAfterFrame(frame);
    }
    renderer.setPassCallback(nullptr);
    session.progress->end();
    if (records) records->append({{"end", {{"frames", frames.size()}, {"rendered", out.rendered}}}});
    return out;
}

// --out-of-core: the cache's share of the frames, and frames left incomplete by the per-trace upload limit (their
// rays' hits in subtrees that were not uploaded are missing: visibly missing shadows).
void printOutOfCoreSummary(const RenderTracer& t, const RenderedFrames& r, double frames) {
    if (!t.outOfCore) return;
    const outofcore::OutOfCoreStats& s = r.outOfCore;
    const outofcore::OutOfCoreOptions& o = t.outOfCore->options();
    const double mb = 1.0 / double(1u << 20);
    std::printf("  out of core: GPU cache %.0f MB (%s), %u of %zu subtrees resident; per frame %.1f MB uploaded, "
                "%.0f misses, %.1f MB read from the file\n",
                double(o.gpuCacheBytes) * mb, outofcore::toString(o.policy), s.residentSubtrees,
                t.outOfCore->file().subtrees().size(),
                double(s.uploadedBvhBytes + s.uploadedGeometryBytes) * mb / frames, double(s.cacheMisses) / frames,
                double(s.hostBytesRead) * mb / frames);
    std::printf("  prefetch (%u frame(s) ahead, %.0f MB per frame): per frame %.1f reads, %.1f hits, %.1f MB wasted, "
                "%.1f skipped; peak host cache %.1f of %.0f MB, peak GPU cache %.1f of %.0f MB\n",
                o.prefetchFrames, double(o.prefetchBytesPerFrame) * mb, double(s.prefetchReads) / frames,
                double(s.prefetchHits) / frames, double(s.prefetchWastedBytes) * mb / frames,
                double(s.prefetchSkipped) / frames, double(s.hostPeakResidentBytes) * mb, double(o.hostCacheBytes) * mb,
                double(s.peakResidentBytes) * mb, double(o.gpuCacheBytes) * mb);
    if (!r.incomplete.empty()) {
        std::string list;
        for (size_t i = 0; i < r.incomplete.size(); ++i) list += (i ? "," : "") + std::to_string(r.incomplete[i]);
        std::fprintf(stderr,
                     "warning: %zu frame(s) incomplete (%s): %llu subtree request(s) postponed by --uploads-per-trace "
                     "%u; their rays' hits are missing (--uploads-per-trace 0 finishes every frame)\n",
                     r.incomplete.size(), list.c_str(), (unsigned long long)s.cachePostponed, o.maxUploadsPerTrace);
    }
}

void printSummary(const RenderOptions& options, const SceneSession& session, const GpuSession& gpu,
                  const RenderTracer& tracer, const RenderedFrames& r, const std::string& glRenderer) {
    const Renderer& renderer = *gpu.renderer;
    const size_t frames = std::max<size_t>(r.rendered, 1); // per-frame figures of the frames rendered by this run
    const double n = double(frames);
    const FrameStats& sum = r.sum;
    if (session.sceneInCore) {
        std::printf("%s: %s, %s triangles (%s unique), BVH %.2f s (SAH %.1f, %u nodes)\n", options.demo ? "demo" : "render",
                    session.scene.name.c_str(), formatCount(session.scene.triangleCount()).c_str(),
                    formatCount(session.scene.stats.uniqueTriangles).c_str(), session.bvh.stats.buildSeconds,
                    session.bvh.stats.sahCost, session.bvh.stats.nodeCount);
    } else { // its geometry stays in the file: the in-core scene is a one-triangle stand-in (docs/outofcore.md)
        std::printf("%s: %s, %s triangles in the prepared file, not loaded in core (traced out of core)\n",
                    options.demo ? "demo" : "render", session.scene.name.c_str(),
                    formatCount(session.fileTriangles).c_str());
    }
    std::printf("  scene %.2f s, GL setup %.2f s on %s\n", session.sceneSeconds, gpu.setupSeconds, glRenderer.c_str());
    std::printf("  %zu frame(s) %dx%d, %d spp, effects %s, primary visibility %s, path %s\n", r.rendered,
                renderer.settings().width, renderer.settings().height, renderer.settings().samplesPerPixel,
                toString(renderer.settings().effects).c_str(), toString(renderer.settings().primaryVisibility),
                session.path.name.c_str()); // as rendered (out of core may change them)
    if (r.rendered < r.written) {
        std::printf("  %zu frame(s) resumed: their records prove them done (not rendered again)\n",
                    r.written - r.rendered);
    }
    std::printf("  per frame: %.1f ms total = G-buffer %.1f + ray generation %.1f + tracing %.1f + shading %.1f\n",
                sum.totalMs / n, sum.gbufferMs / n, sum.raygenMs / n, sum.traceMs() / n, sum.shadeMs / n);
    for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) { // primary: --primary traced
        const TraceStats& t = sum.trace[size_t(type)];
        if (t.passes == 0) continue;
        std::printf("    %-8s %3llu shader passes/frame, %.1f ms/frame\n", toString(type),
                    (unsigned long long)(t.passes / frames), t.milliseconds / n);
    }
    std::printf("  %.2f Mrays/s (all generated rays, method %s)\n",
                sum.traceMs() > 0 ? double(sum.raysGenerated) / (sum.traceMs() * 1000.0) : 0.0, options.method.c_str());
    printOutOfCoreSummary(tracer, r, n);
    std::printf("  %s %s%s\n", r.rendered == r.written ? "wrote" : "frames in", r.firstWritten.c_str(),
                r.written > 1 ? (" ... " + r.lastWritten).c_str() : "");
    if (sum.cappedRays > 0) {
        std::fprintf(stderr, "warning: %llu rays reached the shader loop cap; their results are incomplete\n",
                     (unsigned long long)sum.cappedRays);
    }
}

void writeStatsJson(const RenderOptions& options, const SceneSession& session, const RenderSettings& settings,
                    const RenderedFrames& r, const std::string& glRenderer) {
    nlohmann::json j = runJson(options, session, settings, glRenderer);
    j["frames"] = r.json;
    writeJsonFile(options.common.statsJson, j);
}

} // namespace

int runRender(const RenderOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    const CommonOptions& o = options.common;
    const RenderSettings settings = toRenderSettings(o, 4);
    if (options.output.empty()) throw InputError("no output file: give -o out.png (#### is replaced by the frame number)");
    const ChcrtDebugImage debugImage = debugImageOf(options);
    if (options.resume && options.records.empty()) throw InputError("--resume needs --records FILE (the records it resumes from)");
    checkImageOutputPath(formatFramePath(options.output, 0, 1)); // every frame's file is in that directory
    checkOutputFiles({o.statsJson, options.records, options.resourceLog});
    SceneSession session = openSceneSession(o);
    const std::vector<int> frames = selectFrames(o, session.path, "0");
    GpuSession gpu = openGpuSession(o, session, settings);
    const RenderTracer tracer = makeRenderTracer(options, debugImage, session, *gpu.renderer);
    const GlInfo info = queryGlInfo();
    const RenderedFrames rendered = renderFrames(options, session, *gpu.renderer, tracer, frames, info.renderer, started);
    printSummary(options, session, gpu, tracer, rendered, info.renderer);
    if (!o.statsJson.empty()) {
        writeStatsJson(options, session, settings, rendered, info.renderer);
        std::printf("  statistics in %s\n", o.statsJson.c_str());
    }
    if (!options.records.empty()) std::printf("  records in %s\n", options.records.c_str());
    return kExitOk;
}

} // namespace chcrt::app
