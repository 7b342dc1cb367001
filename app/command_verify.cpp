// `chcrt verify`: checks a tracing method against its oracle on each selected frame's rays.
//   --method bvh (pure BVH GLSL tracing): against Embree, counting pixels whose hits differ beyond the stated
//     tolerance (renderer/render/hit_comparison.h).
//   any other GPU method: against pure BVH GLSL tracing, exactly (same triangle id and bit-identical t), as
//     conservative methods must be.
// Exit 0 when no pixel differs (or at most --max-diff) and no ray reached the shader loop cap; 4 otherwise.
#include "app/commands.h"
#include "app/methods.h"
#include "app/report.h"
#include "app/session.h"
#include "renderer/core/error.h"
#include "renderer/outofcore/out_of_core_tracer.h"
#include "renderer/reference/embree_tracer.h"
#include "renderer/render/hit_comparison.h"

#include <cstdio>

namespace chcrt::app {
namespace {

void printDifference(const Scene& scene, const Ray& ray, const Hit& method, const Hit& reference, size_t pixel,
                     int width, int frame) {
    std::printf("    frame %d pixel (%zu, %zu): origin (%.9g, %.9g, %.9g) dir (%.9g, %.9g, %.9g) [%.9g, %.9g]\n"
                "      method: id %u t %.9g   reference: id %u t %.9g\n",
                frame, pixel % size_t(width), pixel / size_t(width), ray.origin.x, ray.origin.y, ray.origin.z,
                ray.direction.x, ray.direction.y, ray.direction.z, ray.tmin, ray.tmax, method.triangleId, method.t,
                reference.triangleId, reference.t);
    for (const Hit* hit : {&method, &reference}) {
        if (!hit->hit()) continue;
        const ExactIntersection x = intersectInDouble(scene, ray, hit->triangleId);
        std::printf("      triangle %u in double precision: t %.9g, barycentrics (%.3g, %.3g, %.3g)\n", hit->triangleId,
                    x.t, 1.0 - x.u - x.v, x.u, x.v);
    }
}

} // namespace

int runVerify(const VerifyOptions& options) {
    const CommonOptions& o = options.common;
    findGpuMethod(options.method);
    const bool againstEmbree = options.method == kPureBvhMethod;
    std::vector<RayType> rayTypes;
    for (const std::string& name : splitList(options.rayTypes)) rayTypes.push_back(parseRayType(name));
    const RenderSettings settings = toRenderSettings(o, 1);
    SceneSession session = openSceneSession(o);
    if (!session.sceneInCore) {
        throw InputError("verify compares with in-core tracing: " + o.scene + " was not loaded in core (--load-in-core on)");
    }
    const std::vector<int> frames = selectFrames(o, session.path, "spread:5");
    GpuSession gpu = openGpuSession(o, session, settings);
    Renderer& renderer = *gpu.renderer;
    const std::unique_ptr<Tracer> method = makeTracer(options.method, session, /*alwaysCull=*/true);
    std::unique_ptr<EmbreeTracer> embree;
    if (againstEmbree) embree = std::make_unique<EmbreeTracer>(session.scene);
    HitTolerance tolerance;
    tolerance.absoluteT *= renderer.sceneDiagonal();

    std::printf("verify: method %s against %s, %s (%s triangles), path %s, %zu frame(s), %dx%d, %d spp\n",
                options.method.c_str(), againstEmbree ? "Embree" : "pure BVH tracing (exact)",
                session.scene.name.c_str(), formatCount(session.scene.triangleCount()).c_str(),
                session.path.name.c_str(), frames.size(), settings.width, settings.height, settings.samplesPerPixel);
    if (againstEmbree) {
        std::printf("  tolerance: |dt| <= %.0e * t + %.1e + the triangle's float rounding bound; ties at equal t and "
                    "border hits within %.0e (barycentric, + rounding bound) are not differences\n",
                    double(tolerance.relativeT), double(tolerance.absoluteT), double(tolerance.barycentricEpsilon));
    }
    uint64_t totalDiffering = 0, totalCapped = 0;
    int shown = 0;
    nlohmann::json rows = nlohmann::json::array();
    session.progress->begin("Verifying", uint64_t(rayTypes.size()) * frames.size());
    uint64_t done = 0;
    for (RayType type : rayTypes) {
        HitComparison total;
        for (int frame : frames) {
            const Camera camera = session.path.cameraAtFrame(frame);
            FrameStats stats;
            if (type != RayType::Primary) renderer.renderGBuffer(camera, stats);
            HitComparison frameResult;
            for (int sample = 0; sample < settings.samplesPerPixel; ++sample) {
                renderer.generateRayPass(camera, type, sample, stats);
                renderer.useTracer(method.get());
                renderer.traceRayPass(camera, type, sample, stats);
                const std::vector<Ray> rays = renderer.readRays(0);
                const std::vector<Hit> hits = renderer.readHits(0);
                if (againstEmbree) {
                    std::vector<Hit> reference(rays.size());
                    embree->trace(rays, reference, false); // closest hit: same hit/miss as any-hit, and ids
                    std::vector<size_t> differing;
                    frameResult.add(
                        compareHits(session.scene, rays, hits, reference, isAnyHit(type), tolerance, &differing));
                    for (size_t pixel : differing) {
                        if (shown >= options.showDifferences) break;
                        printDifference(session.scene, rays[pixel], hits[pixel], reference[pixel], pixel, settings.width, frame);
                        ++shown;
                    }
                } else {
                    renderer.useTracer(nullptr);
                    renderer.traceRayPass(camera, type, sample, stats);
                    frameResult.add(compareHitsExactly(rays, hits, renderer.readHits(0), isAnyHit(type)));
                }
                renderer.useTracer(nullptr);
            }
            totalCapped += stats.cappedRays;
            total.add(frameResult);
            rows.push_back({{"ray_type", toString(type)}, {"frame", frame}, {"active_rays", frameResult.activeRays},
                            {"differing", frameResult.differing}, {"edge_cases", frameResult.edgeCases},
                            {"ties", frameResult.ties}, {"capped_rays", stats.cappedRays}});
            session.progress->update(++done);
        }
        std::printf("  %-8s %s active rays: %llu differing, %llu border cases, %llu equal-t ties, max rel. t error "
                    "%.1e\n",
                    toString(type), formatCount(total.activeRays).c_str(), (unsigned long long)total.differing,
                    (unsigned long long)total.edgeCases, (unsigned long long)total.ties, total.maxRelativeTError);
        totalDiffering += total.differing;
    }
    session.progress->end();
    if (totalCapped > 0) {
        std::printf("  FAIL: %llu rays reached the shader loop cap\n", (unsigned long long)totalCapped);
    }
    if (auto* ooc = dynamic_cast<outofcore::OutOfCoreTracer*>(method.get())) {
        const outofcore::GpuCacheStats& c = ooc->cache().stats();
        std::printf("  out of core: %u GPU cache slots (%.1f of %.1f MB allocated, %s), %llu hits, %llu misses, %llu "
                    "evictions, %.1f MB uploaded\n",
                    c.slots, double(c.allocatedBytes) / double(1u << 20), double(ooc->options().gpuCacheBytes) / double(1u << 20),
                    outofcore::toString(ooc->options().policy), (unsigned long long)c.hits, (unsigned long long)c.misses,
                    (unsigned long long)c.evictions,
                    double(c.uploadedNodeBytes + c.uploadedTriangleBytes) / double(1u << 20));
    }
    const bool pass = totalDiffering <= options.maxDiffering && totalCapped == 0;
    std::printf("%s: %llu differing pixel(s)\n", pass ? "PASS" : "FAIL", (unsigned long long)totalDiffering);
    if (!o.statsJson.empty()) {
        writeJsonFile(o.statsJson, {{"command", "verify"}, {"method", options.method}, {"scene", toJson(session.scene)},
                                    {"path", session.path.name}, {"pass", pass}, {"differing", totalDiffering},
                                    {"capped_rays", totalCapped}, {"frames", rows}});
    }
    return pass ? kExitOk : kExitCheckFailed;
}

} // namespace chcrt::app
