#include "app/method_tracers.h"

#include "culling/chcrt_tracer.h"
#include "linespace/linespace_cache.h"
#include "linespace/linespace_gpu.h"
#include "linespace/linespace_tracer.h"
#include "linespace/ntree_cache.h"
#include "linespace/ntree_tracer.h"
#include "renderer/core/error.h"
#include "renderer/outofcore/chs_file.h"
#include "renderer/render/trace_stage.h"
#include "culling/outofcore/out_of_core_tracer.h"

#include <cstdio>
#include <filesystem>

namespace chcrt::app {
namespace {

// Where a Line Space or N-tree build went, for the line each tracer prints: a cache file is tens of MB that must
// not land in a folder silently (under -q the line is printed only when a file was written).
void reportCache(const char* what, const std::string& method, ls::CacheOutcome outcome,
                 const std::filesystem::path& dir, const std::string& details, bool quiet) {
    const bool stored = outcome != ls::CacheOutcome::Loaded && !dir.empty();
    if (quiet && !stored) return;
    const std::string where = dir.empty() ? ", not cached (--ls-cache \"\")"
                              : stored    ? ", stored in " + dir.string() + "/"
                                          : " " + dir.string() + "/";
    std::fprintf(stderr, "%s: %s %s%s%s%s\n", method.c_str(), what, ls::toString(outcome), where.c_str(),
                 details.empty() ? "" : ": ", details.c_str());
}

// Line Spaces of the session's BVH with `params`: from the cache directory, or built (and cached). Their dense
// part (the binary bitsets, and the candidate Line Spaces' bitsets and offsets), held on the host and again on the
// GPU, is checked against the memory budget with the session's first: the cut's node count times N^4 grows
// quickly with --ls-n and --ls-depth.
ls::LineSpaces loadLineSpaces(const SceneSession& session, const CommonOptions& o, const ls::LineSpaceParams& params,
                              ls::CacheOutcome& outcome) {
    const uint64_t spaces = ls::selectLineSpaceNodes(session.bvh, params.depth, params.triangleThreshold).size();
    const auto words = [](uint64_t shafts) { return (shafts + 31) / 32; };
    const uint64_t n = params.n;
    const uint64_t n4 = n * n * n * n;
    const uint64_t perSpace = 4 * (words(15 * n4) + (params.candidates ? 2 * words(30 * n4) : 0));
    MemoryParts parts = sessionMemory(session);
    parts.emplace_back(std::to_string(spaces) + " Line Spaces (" + params.toString() + ")", 2 * spaces * perSpace);
    checkMemoryBudget(parts);
    return ls::loadOrBuildLineSpaces(session.bvh, params, o.lineSpaceTracing.cacheDirectory, *session.progress, &outcome);
}

// --out-of-core: a prepared scene traced through the GPU subtree cache (CHC+RT §5.4, docs/outofcore.md).
void checkOutOfCore(const CommonOptions& o) {
    if (!outofcore::isPreparedScenePath(o.scene)) {
        throw InputError("--out-of-core needs a prepared scene (--scene file.chs; see chcrt prepare)");
    }
}

// Line Spaces inside CHC+RT's subtrees (chcrt+ls*): the subtree shader is compiled per any-hit, not per ray type:
// any-hit rays (shadow, AO) get shadow termination (SS 4.1) in chcrt+ls, closest-hit rays (primary, diffuse) exact
// skipping.
void addSubtreeLineSpaces(const MethodInfo& method, const SceneSession& session, const CommonOptions& o,
                          ChcrtOptions& options) {
    if (o.outOfCoreScene.enabled) {
        throw InputError("--out-of-core: " + method.name + " needs the whole BVH's Line Spaces; use chcrt");
    }
    const ls::LineSpaceParams params = lineSpaceBuildParams(method, o);
    ls::CacheOutcome outcome = ls::CacheOutcome::Built;
    const ls::LineSpaces spaces = loadLineSpaces(session, o, params, outcome);
    reportCache("Line Spaces in subtrees", method.name, outcome, o.lineSpaceTracing.cacheDirectory,
                params.toString() + ", " + spaces.stats.summary(), o.quiet);
    auto gpu = std::make_shared<ls::LineSpaceGpu>(spaces, session.bvh, session.scene);
    const ls::LineSpaceMode anyHitMode = method.exact ? ls::LineSpaceMode::Exact : ls::LineSpaceMode::Shadow;
    const float angle = o.lineSpaceTracing.candidateAngleDegrees;
    options.subtreeDefines = [gpu, anyHitMode, angle](bool anyHit) {
        return gpu->defines(anyHit ? anyHitMode : ls::LineSpaceMode::Exact, angle);
    };
    options.bindSubtreeResources = [gpu] { gpu->bind(); };
    options.queries = ChcrtQueries::Gl; // the Line Space traversal takes one subtree root per call
    options.adaptive = false;           // the fallback's pure pass has no Line Spaces
    if (!o.quiet) {
        std::fprintf(stderr, "%s: Line Spaces %s (%s): %s\n", method.name.c_str(), ls::toString(outcome),
                     params.toString().c_str(), spaces.stats.summary().c_str());
    }
}

} // namespace

ls::LineSpaceModes lineSpaceModes(const CommonOptions& o) {
    ls::LineSpaceModes modes = o.lineSpaceTracing.baseModes;
    modes.parse(o.lineSpaceTracing.modes);
    return modes;
}

ls::LineSpaceParams lineSpaceBuildParams(const MethodInfo& method, const CommonOptions& o) {
    ls::LineSpaceParams params = o.lineSpace;
    params.candidates = false;
    if (!method.reads(ParameterArea::LineSpaceModes)) return params; // chcrt+ls*: binary Line Spaces only
    const ls::LineSpaceModes modes = lineSpaceModes(o);
    for (ls::LineSpaceMode m : {modes.primary, modes.shadow, modes.ao, modes.diffuse, modes.bounceShadow}) {
        if (m == ls::LineSpaceMode::Candidate || m == ls::LineSpaceMode::CandidateExactStart) params.candidates = true;
    }
    return params;
}

// The part of a CHC+RT configuration that depends on the GL renderer, decided here because the methods' defaults are
// resolved before there is a context. The cell passes run in the stage --shader-stage names (auto: autoTraceStage,
// compute on GPUs, fragment on software rasterisers, or CHCRT_SHADER_STAGE); methods that start from the recommended
// configuration in core take its list decisions for this renderer (recommendedChcrtOptions(traits): bounds-gpu on
// GPUs, bounds-only on llvmpipe) unless --chcrt-queries is given. Same hits whatever is chosen.
void applyRendererChoices(const MethodInfo& method, const CommonOptions& o, ChcrtOptions& options) {
    if (method.recommendedChcrt && !o.outOfCoreScene.enabled && !o.isGiven("--chcrt-queries")) {
        options.queries = recommendedChcrtOptions(currentRendererTraits()).queries;
    }
    options.computeCellPass = resolveTraceStage(o.shaderStage) == TraceStage::Compute;
}

std::unique_ptr<Tracer> makeChcrtTracer(const MethodInfo& method, const SceneSession& session, const CommonOptions& o,
                                        bool alwaysCull) {
    ChcrtOptions options = o.chcrt;
    if (alwaysCull) options.adaptive = false;
    applyRendererChoices(method, o, options);
    if (!method.reads(ParameterArea::ChcrtVisibility) && options.visibleThreshold > 0) {
        throw InputError("--chcrt-threshold > 0 makes culling approximate: use --method chcrt-aggressive");
    }
    if (o.isGiven("--chcrt-cell-intersect") && options.cellIntersect && options.queries != ChcrtQueries::Batched) {
        throw InputError(std::string("--chcrt-cell-intersect on applies to --chcrt-queries batched, not ") +
                         toString(options.queries) + " (bounds-only and bounds-gpu always intersect by cells; gl "
                         "queries test against depth, which cell passes do not write)");
    }
    if (method.reads(ParameterArea::LineSpace)) addSubtreeLineSpaces(method, session, o, options);
    const bool lod = method.reads(ParameterArea::Lod);
    if (lod && !(o.outOfCore.lodPixels > 0.0f)) {
        throw InputError("--lod-pixels must be above 0 for " + method.name + " (exact tracing is --method chcrt)");
    }
    if (lod && !o.outOfCoreScene.enabled) {
        throw InputError(method.name + " traces the LOD proxies of a prepared scene: give --scene file.chs --out-of-core");
    }
    if (o.outOfCoreScene.enabled) {
        checkOutOfCore(o);
        outofcore::OutOfCoreOptions outOfCore = o.outOfCore;
        if (!lod) outOfCore.lodPixels = 0.0f; // exact methods never trace proxies, whatever --lod-pixels says
        return std::make_unique<outofcore::OutOfCoreTracer>(o.scene, outOfCore, options, method.name);
    }
    return std::make_unique<ChcrtTracer>(session.bvh, options, method.name);
}

std::unique_ptr<Tracer> makeLineSpaceTracer(const MethodInfo& method, const SceneSession& session,
                                            const CommonOptions& o, bool forceLineSpaces) {
    ls::LineSpaceModes modes = lineSpaceModes(o);
    const ls::LineSpaceParams params = lineSpaceBuildParams(method, o);
    ls::CacheOutcome outcome = ls::CacheOutcome::Built;
    const ls::LineSpaces spaces = loadLineSpaces(session, o, params, outcome);
    // Exact skipping only pays where shafts are empty: measured on llvmpipe (docs/benchmarks.md), 0.49-1.03x of
    // pure BVH on every scene we have, whose binary Line Spaces are 69-98 % filled (bunny 70 %: 0.76-1.03x, dragon
    // 74 %: 0.55-1.02x, city 91 %: 0.74-0.96x). A shaft visit costs about a node visit, so skipping can only win
    // where most shafts are empty. Without an explicit --ls-modes, bvh+ls-exact therefore falls back to pure BVH
    // traversal when more than half of the shafts are filled (all measured scenes); verify never falls back.
    const double binaryFill = spaces.stats.binaryShafts ? double(spaces.stats.binaryFilled) / double(spaces.stats.binaryShafts) : 1.0;
    if (method.exact && o.lineSpaceTracing.modes.empty() && !forceLineSpaces && binaryFill > 0.5) {
        modes = ls::LineSpaceModes{};
        modes.primary = modes.shadow = modes.ao = modes.diffuse = modes.bounceShadow = ls::LineSpaceMode::Off;
        if (!o.quiet) {
            std::fprintf(stderr, "%s: %.1f %% of the binary shafts are filled: exact skipping would be slower here, "
                                 "tracing with pure BVH (force it with --ls-modes)\n",
                         method.name.c_str(), 100.0 * binaryFill);
        }
    }
    auto gpu = std::make_shared<ls::LineSpaceGpu>(spaces, session.bvh, session.scene);
    auto tracer = std::make_unique<ls::LineSpaceTracer>(method.name, gpu, modes, o.lineSpaceTracing.candidateAngleDegrees);
    tracer->buildStats = spaces.stats;
    tracer->cacheOutcome = ls::toString(outcome);
    tracer->paramsText = params.toString();
    reportCache("Line Spaces", method.name, outcome, o.lineSpaceTracing.cacheDirectory,
                params.toString() + ", " + spaces.stats.summary() + "; modes " + modes.toString(), o.quiet);
    return tracer;
}

std::unique_ptr<Tracer> makeNTreeTracer(const MethodInfo& method, const SceneSession& session, const CommonOptions& o,
                                        bool /*alwaysCull*/) {
    ls::CacheOutcome outcome = ls::CacheOutcome::Built;
    const ls::NTree tree =
        ls::loadOrBuildNTree(session.bvh, o.ntree, o.lineSpaceTracing.cacheDirectory, *session.progress, &outcome);
    auto gpu = std::make_shared<ls::NTreeGpu>(tree);
    auto tracer = std::make_unique<ls::NTreeTracer>(method.name, gpu, o.ntreeShadow);
    tracer->buildStats = tree.stats;
    tracer->cacheOutcome = ls::toString(outcome);
    tracer->paramsText = o.ntree.toString();
    char details[256];
    std::snprintf(details, sizeof details, "; GPU %.2f MB; shadow level %u, start node %s, near %.2f",
                  double(gpu->gpuBytes()) / 1e6, o.ntreeShadow.shadowLevel, o.ntreeShadow.startExact ? "exact" : "skip",
                  double(o.ntreeShadow.nearEdges));
    reportCache("N-tree", method.name, outcome, o.lineSpaceTracing.cacheDirectory,
                o.ntree.toString() + ", " + tree.stats.summary() + details, o.quiet);
    return tracer;
}

std::function<void(Progress&)> lineSpaceCacheBuild(const MethodInfo& method, const SceneSession& session,
                                                   const CommonOptions& o) {
    const Bvh& bvh = session.bvh;
    const std::filesystem::path dir = o.lineSpaceTracing.cacheDirectory;
    const ls::LineSpaceParams params = lineSpaceBuildParams(method, o);
    return [&bvh, params, dir](Progress& progress) {
        // A cached file is loaded (and validated) once, by makeTracer, not here as well.
        if (std::filesystem::exists(ls::lineSpaceCachePath(dir, ls::lineSpaceInputHash(bvh), params))) return;
        ls::loadOrBuildLineSpaces(bvh, params, dir, progress);
    };
}

std::function<void(Progress&)> nTreeCacheBuild(const MethodInfo& /*method*/, const SceneSession& session,
                                               const CommonOptions& o) {
    const Bvh& bvh = session.bvh;
    const std::filesystem::path dir = o.lineSpaceTracing.cacheDirectory;
    const ls::NTreeParams params = o.ntree;
    return [&bvh, params, dir](Progress& progress) {
        if (std::filesystem::exists(ls::nTreeCachePath(dir, ls::nTreeInputHash(bvh), params))) return;
        ls::loadOrBuildNTree(bvh, params, dir, progress);
    };
}

} // namespace chcrt::app
