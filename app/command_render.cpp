// `chcrt render` and `chcrt demo`: shaded frames of a walkthrough to image files, with a timing summary.
#include "app/commands.h"
#include "app/outofcore_report.h"
#include "app/methods.h"
#include "app/report.h"
#include "app/session.h"
#include "renderer/core/error.h"
#include "renderer/core/frame_range.h"
#include "renderer/core/image_io.h"
#include "renderer/gl/context.h"

#include <cstdio>
#include <filesystem>

namespace chcrt::app {
namespace {

bool isHdrFormat(const std::string& file) {
    const std::string ext = std::filesystem::path(file).extension().string();
    return ext == ".exr" || ext == ".EXR" || ext == ".hdr" || ext == ".HDR";
}

} // namespace

int runRender(const RenderOptions& options) {
    const CommonOptions& o = options.common;
    const RenderSettings settings = toRenderSettings(o, 4);
    if (options.output.empty()) throw InputError("no output file: give -o out.png (#### is replaced by the frame number)");
    const MethodInfo& method = findGpuMethod(options.method);
    const ChcrtDebugImage debugKind =
        options.debugImage.empty() ? ChcrtDebugImage::None : parseChcrtDebugImage(options.debugImage);
    if (debugKind != ChcrtDebugImage::None && !method.chcrtDebugImages) {
        throw InputError("--debug-image needs a CHC+RT method (--method chcrt, chcrt-aggressive or chcrt-noadapt)");
    }
    SceneSession session = openSceneSession(o);
    const std::vector<int> frames = selectFrames(o, session.path, "0");
    GpuSession gpu = openGpuSession(o, session, settings);
    Renderer& renderer = *gpu.renderer;
    const std::unique_ptr<Tracer> tracer = makeTracer(options.method, session);
    auto* outOfCore = dynamic_cast<outofcore::OutOfCoreTracer*>(tracer.get()); // --out-of-core (Table 3 stats)
    auto* chcrtTracer = outOfCore ? &outOfCore->chcrt() : dynamic_cast<ChcrtTracer*>(tracer.get()); // CHC+RT statistics and debug images
    if (chcrtTracer) chcrtTracer->setDebugImage(debugKind);
    if (outOfCore && !session.sceneInCore) installOutOfCorePrimary(renderer, *outOfCore); // docs/outofcore.md
    renderer.useTracer(tracer.get());

    nlohmann::json frameJson = nlohmann::json::array();
    std::vector<std::string> written;
    FrameStats sum;
    renderer.warmUp(session.path.cameraAtFrame(frames.front()));
    // Progress per pass, so that a single slow frame (many samples, a big scene) shows progress too.
    uint64_t passesDone = 0;
    session.progress->begin("Rendering", uint64_t(frames.size()) * renderer.passesPerFrame());
    renderer.setPassCallback([&] { session.progress->update(++passesDone); });
    for (size_t i = 0; i < frames.size(); ++i) {
        if (chcrtTracer) {
            chcrtTracer->resetStats();
            chcrtTracer->clearDebugImage();
        }
        const outofcore::OutOfCoreStats oocBefore = outOfCore ? outOfCore->snapshot() : outofcore::OutOfCoreStats{};
        const FrameStats stats = renderer.renderFrame(session.path.cameraAtFrame(frames[i]));
        const std::string file = formatFramePath(options.output, frames[i], int(frames.size()));
        if (debugKind != ChcrtDebugImage::None) {
            // The debug image accumulates over every CHC+RT trace of the frame (all ray sets).
            ImageRgba32f image;
            image.width = chcrtTracer->debugWidth();
            image.height = chcrtTracer->debugHeight();
            const std::vector<float> rgb =
                colorizeChcrtDebugImage(debugKind, chcrtTracer->readDebugImage(), image.width, image.height);
            image.pixels.resize(size_t(image.width) * image.height * 4, 1.0f);
            for (size_t p = 0; p < rgb.size() / 3; ++p) {
                for (int c = 0; c < 3; ++c) image.pixels[p * 4 + size_t(c)] = rgb[p * 3 + size_t(c)];
            }
            writeImage(file, image, /*alreadyDisplayEncoded=*/true);
        } else {
            writeImage(file, isHdrFormat(file) ? renderer.readHdrImage() : renderer.readDisplayImage());
        }
        written.push_back(file);
        nlohmann::json j = toJson(stats, uint64_t(settings.width) * settings.height);
        j["frame"] = frames[i];
        j["output"] = file;
        j["method"] = options.method;
        if (chcrtTracer) j["chcrt"] = chcrtStatsJson(chcrtTracer->totalStats(), 1.0);
        if (outOfCore) {
            j["outofcore"] =
                outOfCoreStatsJson(outofcore::OutOfCoreStats::difference(outOfCore->snapshot(), oocBefore), 1.0, *outOfCore);
        }
        frameJson.push_back(j);
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
    renderer.setPassCallback(nullptr);
    session.progress->end();

    const double n = double(frames.size());
    const GlInfo info = queryGlInfo();
    std::printf("%s: %s, %s triangles (%s unique), BVH %.2f s (SAH %.1f, %u nodes)\n",
                options.demo ? "demo" : "render", session.scene.name.c_str(),
                formatCount(session.scene.triangleCount()).c_str(),
                formatCount(session.scene.stats.uniqueTriangles).c_str(), session.bvh.stats.buildSeconds,
                session.bvh.stats.sahCost, session.bvh.stats.nodeCount);
    std::printf("  scene %.2f s, GL setup %.2f s on %s\n", session.sceneSeconds, gpu.setupSeconds,
                info.renderer.c_str());
    std::printf("  %zu frame(s) %dx%d, %d spp, effects %s, primary visibility %s, path %s\n", frames.size(),
                settings.width, settings.height, settings.samplesPerPixel, toString(renderer.settings().effects).c_str(),
                toString(renderer.settings().primaryVisibility), session.path.name.c_str()); // as rendered (out of core may change them)
    std::printf("  per frame: %.1f ms total = G-buffer %.1f + ray generation %.1f + tracing %.1f + shading %.1f\n",
                sum.totalMs / n, sum.gbufferMs / n, sum.raygenMs / n, sum.traceMs() / n, sum.shadeMs / n);
    for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) { // primary: --primary traced
        const TraceStats& t = sum.trace[size_t(type)];
        if (t.passes == 0) continue;
        std::printf("    %-8s %3llu passes/frame, %.1f ms/frame\n", toString(type),
                    (unsigned long long)(t.passes / frames.size()), t.milliseconds / n);
    }
    std::printf("  %.2f Mrays/s (all generated rays, method %s)\n",
                sum.traceMs() > 0 ? double(sum.raysGenerated) / (sum.traceMs() * 1000.0) : 0.0, options.method.c_str());
    std::printf("  wrote %s%s\n", written.front().c_str(),
                written.size() > 1 ? (" ... " + written.back()).c_str() : "");
    if (sum.cappedRays > 0) {
        std::fprintf(stderr, "warning: %llu rays reached the shader loop cap; their results are incomplete\n",
                     (unsigned long long)sum.cappedRays);
    }
    if (!o.statsJson.empty()) {
        nlohmann::json j = {{"command", options.demo ? "demo" : "render"},
                            {"scene", toJson(session.scene)},
                            {"bvh", toJson(session.bvh.stats)},
                            {"path", session.path.name},
                            {"width", settings.width},
                            {"height", settings.height},
                            {"spp", settings.samplesPerPixel},
                            {"effects", toString(settings.effects)},
                            {"primary", toString(settings.primaryVisibility)},
                            {"seed", settings.seed},
                            {"gl_renderer", info.renderer},
                            {"frames", frameJson}};
        writeJsonFile(o.statsJson, j);
    }
    return kExitOk;
}

} // namespace chcrt::app
