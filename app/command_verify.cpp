// `chcrt verify`: traces each selected frame's rays with the GLSL tracer and with Embree (the oracle) and counts
// pixels whose hits differ beyond the stated tolerance (renderer/render/hit_comparison.h). Exit 0 when no pixel
// differs (or at most --max-diff) and no ray reached the shader loop cap; 4 otherwise.
#include "app/commands.h"
#include "app/report.h"
#include "app/session.h"
#include "renderer/core/error.h"
#include "renderer/reference/embree_tracer.h"
#include "renderer/render/hit_comparison.h"

#include <cstdio>

namespace chcrt::app {

int runVerify(const VerifyOptions& options) {
    const CommonOptions& o = options.common;
    if (options.method != "bvh") {
        throw InputError("--method: unknown method '" + options.method + "' (available: bvh)");
    }
    std::vector<RayType> rayTypes;
    for (const std::string& name : splitList(options.rayTypes)) rayTypes.push_back(parseRayType(name));
    const RenderSettings settings = toRenderSettings(o, 1);
    SceneSession session = openSceneSession(o);
    const std::vector<int> frames = selectFrames(o, session.path, "spread:5");
    GpuSession gpu = openGpuSession(o, session, settings);
    Renderer& renderer = *gpu.renderer;
    const EmbreeTracer embree(session.scene);
    HitTolerance tolerance;
    tolerance.absoluteT *= renderer.sceneDiagonal();

    std::printf("verify: method %s against Embree, %s (%s triangles), path %s, %zu frame(s), %dx%d, %d spp\n",
                options.method.c_str(), session.scene.name.c_str(), formatCount(session.scene.triangleCount()).c_str(),
                session.path.name.c_str(), frames.size(), settings.width, settings.height, settings.samplesPerPixel);
    std::printf("  tolerance: |dt| <= %.0e * t + %.1e; ties at equal t and border hits within %.0e (barycentric) "
                "are not differences\n",
                double(tolerance.relativeT), double(tolerance.absoluteT), double(tolerance.barycentricEpsilon));
    uint64_t totalDiffering = 0, totalCapped = 0;
    nlohmann::json rows = nlohmann::json::array();
    for (RayType type : rayTypes) {
        HitComparison total;
        for (int frame : frames) {
            const Camera camera = session.path.cameraAtFrame(frame);
            FrameStats stats;
            if (type != RayType::Primary) renderer.renderGBuffer(camera, stats);
            HitComparison frameResult;
            for (int sample = 0; sample < settings.samplesPerPixel; ++sample) {
                renderer.generateRayPass(camera, type, sample, stats);
                renderer.traceRayPass(camera, type, sample, stats);
                const std::vector<Ray> rays = renderer.readRays(0);
                std::vector<Hit> reference(rays.size());
                embree.trace(rays, reference, false); // closest hit: same hit/miss as any-hit, and ids for the report
                frameResult.add(compareHits(session.scene, rays, renderer.readHits(0), reference, isAnyHit(type), tolerance));
            }
            totalCapped += stats.cappedRays;
            total.add(frameResult);
            rows.push_back({{"ray_type", toString(type)}, {"frame", frame}, {"active_rays", frameResult.activeRays},
                            {"differing", frameResult.differing}, {"edge_cases", frameResult.edgeCases},
                            {"ties", frameResult.ties}, {"capped_rays", stats.cappedRays}});
        }
        std::printf("  %-8s %s active rays: %llu differing, %llu border cases, %llu equal-t ties, max rel. t error "
                    "%.1e\n",
                    toString(type), formatCount(total.activeRays).c_str(), (unsigned long long)total.differing,
                    (unsigned long long)total.edgeCases, (unsigned long long)total.ties, total.maxRelativeTError);
        totalDiffering += total.differing;
    }
    if (totalCapped > 0) {
        std::printf("  FAIL: %llu rays reached the shader loop cap\n", (unsigned long long)totalCapped);
    }
    const bool pass = totalDiffering <= options.maxDiffering && totalCapped == 0;
    std::printf("%s: %llu differing pixel(s)\n", pass ? "PASS" : "FAIL", (unsigned long long)totalDiffering);
    if (!o.statsJson.empty()) {
        writeJsonFile(o.statsJson, {{"command", "verify"}, {"method", options.method}, {"scene", toJson(session.scene)},
                                    {"path", session.path.name}, {"pass", pass}, {"differing", totalDiffering},
                                    {"frames", rows}});
    }
    return pass ? kExitOk : kExitCheckFailed;
}

} // namespace chcrt::app
