#include "app/methods.h"

#include "culling/chcrt_tracer.h"
#include "culling/outofcore/out_of_core_tracer.h"
#include "linespace/linespace_cache.h"
#include "linespace/linespace_tracer.h"
#include "linespace/ntree_cache.h"
#include "linespace/ntree_tracer.h"
#include "renderer/core/error.h"
#include "renderer/outofcore/chs_file.h"

#include <cstdio>
#include <filesystem>

namespace chcrt::app {

const std::vector<MethodInfo>& gpuMethods() {
    static const std::vector<MethodInfo> methods = {
        {"bvh", true, "pure BVH traversal in GLSL (the baseline)"},
        {"chcrt", true, "CHC+RT: occlusion-query culling of BVH subtrees per screen tile (conservative, exact)"},
        {"chcrt-aggressive", false, "CHC+RT culling pairs whose query passes <= 20 rays (approximate)"},
        {"chcrt-noadapt", true, "CHC+RT without the adaptive fallback to a pure pass (always culls; exact)"},
        {"bvh+ls-exact", true, "BVH with exact empty-space skipping at binary Line Space nodes (--ls-*)"},
        {"bvh+ls", false, "BVH + Line Space: shadow termination at occupied shafts, representative candidates for "
                          "AO/diffuse (approximate; --ls-modes)"},
        {"chcrt+ls-exact", true, "CHC+RT with exact empty-space skipping at Line Space nodes inside its subtrees (--ls-*)"},
        {"chcrt+ls", false, "CHC+RT with Line Spaces in its subtrees: any-hit rays (shadow, AO) end at occupied shafts "
                            "(SS 4.1), closest-hit rays skip empty ones (approximate)"},
        {"ntree+ls", false, "shadow rays over an N-tree with binary Line Spaces, occluded at occupied shafts of level "
                            "d-1 (soft-shadow paper; approximate; --ls-ntree N:d); other rays: pure BVH"},
    };
    return methods;
}

const MethodInfo& findGpuMethod(const std::string& name) {
    std::string names;
    for (const MethodInfo& m : gpuMethods()) {
        if (m.name == name) return m;
        names += (names.empty() ? "" : ", ") + m.name;
    }
    throw InputError("unknown method '" + name + "' (available: " + names + ", embree)");
}

namespace {

// The Line Space modes of a bvh+ls* method: its defaults plus --ls-modes.
ls::LineSpaceModes lineSpaceModes(const std::string& name, const CommonOptions& o) {
    ls::LineSpaceModes modes = name == "bvh+ls-exact" ? ls::LineSpaceModes::allExact() : ls::LineSpaceModes{};
    modes.parse(o.lsModes);
    return modes;
}

// Build parameters of the Line Spaces a method reads: --ls-n/--ls-depth/--ls-t; candidates only when a mode uses
// them (bvh+ls*) — chcrt+ls* subtrees use binary Line Spaces only.
ls::LineSpaceParams lineSpaceParams(const std::string& name, const CommonOptions& o) {
    ls::LineSpaceParams params;
    params.n = o.lsN;
    params.depth = o.lsDepth;
    params.triangleThreshold = o.lsT;
    params.candidates = false;
    if (name == "bvh+ls-exact" || name == "bvh+ls") {
        const ls::LineSpaceModes modes = lineSpaceModes(name, o);
        for (ls::LineSpaceMode m : {modes.primary, modes.shadow, modes.ao, modes.diffuse, modes.bounceShadow}) {
            if (m == ls::LineSpaceMode::Candidate || m == ls::LineSpaceMode::CandidateExactStart) params.candidates = true;
        }
    }
    return params;
}

ls::NTreeParams nTreeParams(const CommonOptions& o) { return ls::parseNTreeParams(o.lsNtree.empty() ? "6:3" : o.lsNtree); }

// Line Spaces from the cache (or built), uploaded, and a tracer with the modes of the method + --ls-modes.
// `forceLineSpaces`: no fallback to pure BVH traversal (verify checks the Line Space path itself).
std::unique_ptr<Tracer> makeLineSpaceTracer(const std::string& name, const SceneSession& session, bool forceLineSpaces) {
    const CommonOptions& o = session.options;
    if (!(o.lsAngle >= 0.0f && o.lsAngle <= 180.0f)) throw InputError("--ls-angle must be between 0 and 180");
    ls::LineSpaceModes modes = lineSpaceModes(name, o);
    const ls::LineSpaceParams params = lineSpaceParams(name, o);
    ls::CacheOutcome outcome = ls::CacheOutcome::Built;
    const ls::LineSpaces spaces = ls::loadOrBuildLineSpaces(session.bvh, params, o.lsCache, *session.progress, &outcome);
    // Exact skipping only pays where shafts are empty: measured on llvmpipe (docs/benchmarks.md), 0.49-1.03x of
    // pure BVH on every scene we have, whose binary Line Spaces are 69-98 % filled (bunny 70 %: 0.76-1.03x, dragon
    // 74 %: 0.55-1.02x, city 91 %: 0.74-0.96x). A shaft visit costs about a node visit, so skipping can only win
    // where most shafts are empty. Without an explicit --ls-modes, bvh+ls-exact therefore falls back to pure BVH
    // traversal when more than half of the shafts are filled (all measured scenes); verify never falls back.
    const double binaryFill = spaces.stats.binaryShafts ? double(spaces.stats.binaryFilled) / double(spaces.stats.binaryShafts) : 1.0;
    if (name == "bvh+ls-exact" && o.lsModes.empty() && !forceLineSpaces && binaryFill > 0.5) {
        modes = ls::LineSpaceModes{};
        modes.primary = modes.shadow = modes.ao = modes.diffuse = modes.bounceShadow = ls::LineSpaceMode::Off;
        if (!o.quiet) {
            std::fprintf(stderr, "%s: %.1f %% of the binary shafts are filled: exact skipping would be slower here, "
                                 "tracing with pure BVH (force it with --ls-modes)\n",
                         name.c_str(), 100.0 * binaryFill);
        }
    }
    auto gpu = std::make_shared<ls::LineSpaceGpu>(spaces, session.bvh, session.scene);
    auto tracer = std::make_unique<ls::LineSpaceTracer>(name, gpu, modes, o.lsAngle);
    tracer->buildStats = spaces.stats;
    tracer->cacheOutcome = ls::toString(outcome);
    tracer->paramsText = params.toString();
    if (!o.quiet) {
        std::fprintf(stderr, "%s: Line Spaces %s (%s): %s; modes %s\n", name.c_str(), ls::toString(outcome),
                     params.toString().c_str(), spaces.stats.summary().c_str(), modes.toString().c_str());
    }
    return tracer;
}

// N-tree with binary Line Spaces (soft-shadow paper), loaded from --ls-cache or built (5-200 s), uploaded, and its
// tracer.
std::unique_ptr<Tracer> makeNTreeTracer(const std::string& name, const SceneSession& session) {
    const CommonOptions& o = session.options;
    const ls::NTreeParams params = nTreeParams(o);
    ls::NTreeShadowOptions shadow;
    shadow.shadowLevel = o.lsNtreeLevel < 0 ? params.depth - 1 : uint32_t(o.lsNtreeLevel);
    if (o.lsNtreeStart != "exact" && o.lsNtreeStart != "skip") {
        throw InputError("--ls-ntree-start must be exact or skip, not '" + o.lsNtreeStart + "'");
    }
    shadow.startExact = o.lsNtreeStart == "exact";
    if (!(o.lsNtreeNear >= 0.0f && o.lsNtreeNear <= 1000.0f)) throw InputError("--ls-ntree-near must be in 0..1000");
    shadow.nearEdges = o.lsNtreeNear;
    ls::CacheOutcome outcome = ls::CacheOutcome::Built;
    const ls::NTree tree = ls::loadOrBuildNTree(session.bvh, params, o.lsCache, *session.progress, &outcome);
    auto gpu = std::make_shared<ls::NTreeGpu>(tree);
    auto tracer = std::make_unique<ls::NTreeTracer>(name, gpu, shadow);
    tracer->buildStats = tree.stats;
    tracer->cacheOutcome = ls::toString(outcome);
    tracer->paramsText = params.toString();
    if (!o.quiet) {
        std::fprintf(stderr, "%s: %s %s: %s; GPU %.2f MB; shadow level %u, start node %s, near %.2f\n", name.c_str(),
                     params.toString().c_str(), ls::toString(outcome), tree.stats.summary().c_str(),
                     double(gpu->gpuBytes()) / 1e6, shadow.shadowLevel, o.lsNtreeStart.c_str(),
                     double(shadow.nearEdges));
    }
    return tracer;
}

} // namespace

namespace {

// --out-of-core budgets (CHC+RT §5.4, docs/outofcore.md); InputError for a scene that is not prepared or bad values.
outofcore::OutOfCoreOptions outOfCoreOptions(const CommonOptions& o) {
    if (!outofcore::isPreparedScenePath(o.scene)) {
        throw InputError("--out-of-core needs a prepared scene (--scene file.chs; see chcrt prepare)");
    }
    if (o.gpuCacheMb < 1) throw InputError("--gpu-cache-mb must be at least 1");
    if (o.hostCacheMb < 1) throw InputError("--host-cache-mb must be at least 1");
    outofcore::OutOfCoreOptions out;
    out.gpuCacheBytes = uint64_t(o.gpuCacheMb) << 20;
    out.hostCacheBytes = uint64_t(o.hostCacheMb) << 20;
    out.policy = outofcore::parseCachePolicy(o.cachePolicy);
    out.maxUploadsPerTrace = o.uploadsPerTrace > 0 ? uint32_t(o.uploadsPerTrace) : 0u;
    return out;
}

// CHC+RT with the --chcrt-* parameters of the command line (culling/README.md).
std::unique_ptr<Tracer> makeChcrtTracer(const std::string& name, const SceneSession& session, bool alwaysCull) {
    const CommonOptions& o = session.options;
    // chcrt and chcrt-noadapt in core: the recommended configuration. The aggressive variant (Table 4), the Line
    // Space variants (one subtree root per call) and out of core (the prepared file's cut) keep the paper's.
    const bool recommended = (name == "chcrt" || name == "chcrt-noadapt") && !o.outOfCore;
    ChcrtOptions options = recommended ? recommendedChcrtOptions() : ChcrtOptions{};
    // CHC+RT §7, Table 4: a pair counts as visible only when more rays than the threshold pass its query.
    if (name == "chcrt-aggressive") {
        options.visibleThreshold = 20;
        options.queries = ChcrtQueries::Gl; // counts rays per query
    }
    // The aggressive variant measures what culling loses (Table 4), so it always culls too.
    if (name == "chcrt-noadapt" || name == "chcrt-aggressive" || alwaysCull) options.adaptive = false;
    if (o.chcrtThreshold >= 0) options.visibleThreshold = uint32_t(o.chcrtThreshold);
    if (o.chcrtMinTile >= 0) options.pairs.minTileSize = o.chcrtMinTile;
    if (o.chcrtHeight >= 0) {
        options.partition.maxSubtreeHeight = uint32_t(o.chcrtHeight);
        options.adaptiveHeights.clear(); // a forced height
    }
    if (o.chcrtMultiQuery >= 0) options.multiQueryPairs = o.chcrtMultiQuery;
    if (!o.chcrtQueries.empty()) options.queries = parseChcrtQueries(o.chcrtQueries);
    if (o.chcrtBoundsCell >= 0) options.bounds.cellSize = o.chcrtBoundsCell;
    if (o.chcrtBoundsPieces >= 0) options.bounds.pieces = o.chcrtBoundsPieces;
    const auto onOff = [](const std::string& value, const char* flag, bool& out) {
        if (value.empty()) return;
        if (value != "on" && value != "off") throw InputError(std::string(flag) + " must be on or off, not '" + value + "'");
        out = value == "on";
    };
    onOff(o.chcrtTighterBounds, "--chcrt-tighter-bounds", options.tighterBounds);
    onOff(o.chcrtLeafCache, "--chcrt-leaf-cache", options.leafCache);
    onOff(o.chcrtMergedBatch, "--chcrt-merged-batch", options.mergedBatch);
    onOff(o.chcrtRayExtent, "--chcrt-ray-extent", options.rayExtentCulling);
    if (name != "chcrt-aggressive" && options.visibleThreshold > 0) {
        throw InputError("--chcrt-threshold > 0 makes culling approximate: use --method chcrt-aggressive");
    }
    if (name == "chcrt+ls" || name == "chcrt+ls-exact") {
        if (o.outOfCore) throw InputError("--out-of-core: " + name + " needs the whole BVH's Line Spaces; use chcrt");
        if (!(o.lsAngle >= 0.0f && o.lsAngle <= 180.0f)) throw InputError("--ls-angle must be between 0 and 180");
        const ls::LineSpaceParams params = lineSpaceParams(name, o);
        ls::CacheOutcome outcome = ls::CacheOutcome::Built;
        const ls::LineSpaces spaces = ls::loadOrBuildLineSpaces(session.bvh, params, o.lsCache, *session.progress, &outcome);
        auto gpu = std::make_shared<ls::LineSpaceGpu>(spaces, session.bvh, session.scene);
        // The subtree shader is compiled per any-hit, not per ray type: any-hit rays (shadow, AO) get shadow
        // termination (SS 4.1) in chcrt+ls, closest-hit rays (primary, diffuse) exact skipping.
        const ls::LineSpaceMode anyHitMode = name == "chcrt+ls" ? ls::LineSpaceMode::Shadow : ls::LineSpaceMode::Exact;
        const float angle = o.lsAngle;
        options.subtreeDefines = [gpu, anyHitMode, angle](bool anyHit) {
            return gpu->defines(anyHit ? anyHitMode : ls::LineSpaceMode::Exact, angle);
        };
        options.bindSubtreeResources = [gpu] { gpu->bind(); };
        options.queries = ChcrtQueries::Gl; // the Line Space traversal takes one subtree root per call
        options.adaptive = false; // the fallback's pure pass has no Line Spaces
        if (!o.quiet) {
            std::fprintf(stderr, "%s: Line Spaces %s (%s): %s\n", name.c_str(), ls::toString(outcome),
                         params.toString().c_str(), spaces.stats.summary().c_str());
        }
    }
    if (o.outOfCore) return std::make_unique<outofcore::OutOfCoreTracer>(o.scene, outOfCoreOptions(o), options, name);
    return std::make_unique<ChcrtTracer>(session.bvh, options, name);
}

} // namespace

bool hasOutOfCoreForm(const std::string& name) {
    return name.rfind("chcrt", 0) == 0 && name.find("+ls") == std::string::npos;
}

std::function<void(Progress&)> methodCacheBuild(const std::string& name, const SceneSession& session) {
    const CommonOptions& o = session.options;
    if (o.lsCache.empty() || o.outOfCore) return {};
    const Bvh& bvh = session.bvh;
    const std::filesystem::path dir = o.lsCache;
    if (name == "bvh+ls-exact" || name == "bvh+ls" || name == "chcrt+ls" || name == "chcrt+ls-exact") {
        const ls::LineSpaceParams params = lineSpaceParams(name, o);
        return [&bvh, params, dir](Progress& progress) {
            // A cached file is loaded (and validated) once, by makeTracer, not here as well.
            if (std::filesystem::exists(ls::lineSpaceCachePath(dir, ls::lineSpaceInputHash(bvh), params))) return;
            ls::loadOrBuildLineSpaces(bvh, params, dir, progress);
        };
    }
    if (name == "ntree+ls") {
        const ls::NTreeParams params = nTreeParams(o);
        return [&bvh, params, dir](Progress& progress) {
            if (std::filesystem::exists(ls::nTreeCachePath(dir, ls::nTreeInputHash(bvh), params))) return;
            ls::loadOrBuildNTree(bvh, params, dir, progress);
        };
    }
    return {};
}

std::unique_ptr<Tracer> makeTracer(const std::string& name, const SceneSession& session, const GpuSession& gpu) {
    return makeTracer(name, session, gpu, false);
}

std::unique_ptr<Tracer> makeTracer(const std::string& name, const SceneSession& session, const GpuSession& /*gpu*/,
                                   bool alwaysCull) {
    findGpuMethod(name);
    if (session.options.outOfCore && name.rfind("chcrt", 0) != 0) {
        throw InputError("--out-of-core: method " + name + " has no out-of-core form (pure BVH and Line Space tracing "
                         "need the whole scene on the GPU); use --method chcrt or chcrt-aggressive");
    }
    if (name.rfind("chcrt", 0) == 0) return makeChcrtTracer(name, session, alwaysCull);
    if (name == "bvh+ls-exact" || name == "bvh+ls") return makeLineSpaceTracer(name, session, alwaysCull);
    if (name == "ntree+ls") return makeNTreeTracer(name, session);
    return nullptr; // "bvh"
}

} // namespace chcrt::app
