// `chcrt verify`: checks a tracing method against its oracle on each selected frame's rays.
//   --method bvh (pure BVH GLSL tracing): against Embree, counting pixels whose hits differ beyond the stated
//     tolerance (renderer/render/hit_comparison.h).
//   any other GPU method: against pure BVH GLSL tracing, exactly (same triangle id and bit-identical t), as
//     conservative methods must be.
//   --reference embree | fragment | compute chooses the oracle instead: Embree, or pure BVH tracing in that shader
//     stage, exactly (bvh in the compute stage against the fragment stage: the same bits are required).
// Exit 0 when no pixel differs (or at most --max-diff) and no ray reached the shader loop cap; 4 otherwise.
#include "app/commands.h"
#include "app/methods.h"
#include "app/report.h"
#include "app/session.h"
#include "culling/outofcore/out_of_core_tracer.h"
#include "renderer/core/error.h"
#include "renderer/reference/embree_tracer.h"
#include "renderer/render/bvh_tracer.h"
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

// What verify compares: the method's hits against Embree (bvh) or against pure BVH tracing (every other method).
struct VerifyContext {
    const VerifyOptions& options;
    const SceneSession& session;
    Renderer& renderer;
    Tracer* method = nullptr;
    EmbreeTracer* embree = nullptr; // against Embree
    Tracer* reference = nullptr;    // exact comparisons: this pure tracer, nullptr = the renderer's own
    HitTolerance tolerance;
    int shown = 0;                  // differing pixels printed so far (--show-diff)
};

// "embree", "bvh-fragment" or "bvh-compute" (JSON "reference").
std::string referenceName(const VerifyContext& v) {
    if (v.embree) return "embree";
    const TraceStage stage = v.reference ? static_cast<const BvhTracer*>(v.reference)->stage() : v.renderer.pureTracerStage();
    return std::string("bvh-") + toString(stage);
}

void printHeader(const VerifyContext& v, const RenderSettings& settings, size_t frames) {
    const std::string oracle = v.embree ? std::string("Embree")
                                        : "pure BVH tracing (exact, " + referenceName(v).substr(4) + " stage)";
    std::printf("verify: method %s (%s stage) against %s, %s (%s triangles), path %s, %zu frame(s), %dx%d, %d spp\n",
                v.options.method.c_str(), toString(v.renderer.pureTracerStage()), oracle.c_str(),
                v.session.scene.name.c_str(), formatCount(v.session.scene.triangleCount()).c_str(),
                v.session.path.name.c_str(), frames, settings.width, settings.height, settings.samplesPerPixel);
    if (v.embree) {
        std::printf("  tolerance: |dt| <= %.0e * t + %.1e + the triangle's float rounding bound; ties at equal t and "
                    "border hits within %.0e (barycentric, + rounding bound) are not differences\n",
                    double(v.tolerance.relativeT), double(v.tolerance.absoluteT), double(v.tolerance.barycentricEpsilon));
    }
}

// One frame's rays of one type, every sample: the method's hits against the oracle's.
HitComparison verifyFrame(VerifyContext& v, RayType type, int frame, FrameStats& stats) {
    Renderer& renderer = v.renderer;
    const Camera camera = v.session.path.cameraAtFrame(frame);
    if (type != RayType::Primary) renderer.renderGBuffer(camera, stats);
    HitComparison result;
    for (int sample = 0; sample < renderer.settings().samplesPerPixel; ++sample) {
        renderer.generateRayPass(camera, type, sample, stats);
        renderer.useTracer(v.method);
        renderer.traceRayPass(camera, type, sample, stats);
        const std::vector<Ray> rays = renderer.readRays(0);
        const std::vector<Hit> hits = renderer.readHits(0);
        std::vector<Hit> reference(rays.size());
        std::vector<size_t> differing;
        if (v.embree) {
            v.embree->trace(rays, reference, false); // closest hit: same hit/miss as any-hit, and ids
            result.add(compareHits(v.session.scene, rays, hits, reference, isAnyHit(type), v.tolerance, &differing));
        } else {
            renderer.useTracer(v.reference);
            renderer.traceRayPass(camera, type, sample, stats);
            reference = renderer.readHits(0);
            result.add(compareHitsExactly(rays, hits, reference, isAnyHit(type), &differing));
        }
        for (size_t pixel : differing) {
            if (v.shown >= v.options.showDifferences) break;
            printDifference(v.session.scene, rays[pixel], hits[pixel], reference[pixel], pixel,
                            renderer.settings().width, frame);
            ++v.shown;
        }
        renderer.useTracer(nullptr);
    }
    return result;
}

void printOutOfCoreCache(const Tracer* method) {
    const auto* ooc = dynamic_cast<const outofcore::OutOfCoreTracer*>(method);
    if (!ooc) return;
    const outofcore::GpuCacheStats& c = ooc->cache().stats();
    std::printf("  out of core: %u GPU cache slots (%.1f of %.1f MB allocated, %s), %llu hits, %llu misses, %llu "
                "evictions, %.1f MB uploaded\n",
                c.slots, double(c.allocatedBytes) / double(1u << 20), double(ooc->options().gpuCacheBytes) / double(1u << 20),
                outofcore::toString(ooc->options().policy), (unsigned long long)c.hits, (unsigned long long)c.misses,
                (unsigned long long)c.evictions, double(c.uploadedNodeBytes + c.uploadedTriangleBytes) / double(1u << 20));
}

} // namespace

int runVerify(const VerifyOptions& options) {
    const CommonOptions& o = options.common;
    findGpuMethod(options.method);
    std::vector<RayType> rayTypes;
    for (const std::string& name : splitList(options.rayTypes)) rayTypes.push_back(parseRayType(name));
    const RenderSettings settings = toRenderSettings(o, 1);
    checkOutputFiles({o.statsJson});
    SceneSession session = openSceneSession(o);
    if (!session.sceneInCore) {
        throw InputError("verify compares with in-core tracing: " + o.scene + " was not loaded in core (--load-in-core on)");
    }
    const std::vector<int> frames = selectFrames(o, session.path, "spread:5");
    GpuSession gpu = openGpuSession(o, session, settings);
    const std::unique_ptr<Tracer> method = makeTracer(options.method, session, /*alwaysCull=*/true);
    std::unique_ptr<EmbreeTracer> embree;
    std::unique_ptr<BvhTracer> reference;
    if (options.reference == "embree" || (options.reference == "auto" && options.method == kPureBvhMethod)) {
        embree = std::make_unique<EmbreeTracer>(session.scene);
    } else if (options.reference != "auto") {
        reference = std::make_unique<BvhTracer>(parseTraceStage(options.reference));
    }
    VerifyContext v{options, session, *gpu.renderer, method.get(), embree.get(), reference.get()};
    v.tolerance.absoluteT *= v.renderer.sceneDiagonal();
    printHeader(v, settings, frames.size());

    uint64_t totalDiffering = 0, totalCapped = 0;
    nlohmann::json rows = nlohmann::json::array();
    session.progress->begin("Verifying", uint64_t(rayTypes.size()) * frames.size());
    uint64_t done = 0;
    for (RayType type : rayTypes) {
        HitComparison total;
        for (int frame : frames) {
            FrameStats stats;
            const HitComparison frameResult = verifyFrame(v, type, frame, stats);
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
    if (totalCapped > 0) std::printf("  FAIL: %llu rays reached the shader loop cap\n", (unsigned long long)totalCapped);
    printOutOfCoreCache(method.get());
    const bool pass = totalDiffering <= options.maxDiffering && totalCapped == 0;
    std::printf("%s: %llu differing pixel(s)\n", pass ? "PASS" : "FAIL", (unsigned long long)totalDiffering);
    if (!o.statsJson.empty()) {
        nlohmann::json json = {{"command", "verify"}, {"method", options.method}, {"scene", toJson(session.scene)},
                               {"path", session.path.name}, {"pass", pass}, {"differing", totalDiffering},
                               {"capped_rays", totalCapped}, {"frames", rows},
                               {"shader_stage", toString(v.renderer.pureTracerStage())},
                               {"reference", referenceName(v)}};
        json.update(glJson(queryGlInfo()));
        writeJsonFile(o.statsJson, json);
    }
    return pass ? kExitOk : kExitCheckFailed;
}

} // namespace chcrt::app
