#include "app/methods.h"

#include "app/method_tracers.h"
#include "app/report.h"
#include "renderer/core/error.h"

#include <algorithm>

namespace chcrt::app {
namespace {

using Area = ParameterArea;

// CHC+RT §7, Table 4: a pair counts as visible only when more rays than the threshold pass its query; the
// aggressive variant measures what culling loses, so it always culls.
void aggressiveDefaults(CommonOptions& d, const CommonOptions&, uint64_t) {
    d.chcrt.visibleThreshold = 20;
    d.chcrt.queries = ChcrtQueries::Gl; // counts rays per query
    d.chcrt.adaptive = false;
}

// chcrt in core: the recommended configuration (recommendedChcrtOptions, culling/README.md "Adaptive choice"); out
// of core the prepared file's cut with batched queries (the GL queries' test, a round of pairs per dispatch: on the
// 140M city's near path 168.6 against 195.7 ms per frame and 337 against 403 cold uploads, far path exact 7.2 against
// 7.5-8.2 s per frame, the same images; docs/outofcore.md), each intersection round traced in one cell pass
// (cellIntersect: near frames 180-188 -> 145-154 ms, far -5 to -8 %, the same images; culling/README.md "Cell
// intersection") over 16-pixel ray bounds cells (kRecommendedBoundsCellSize). A forced --chcrt-height leaves no other height to try.
// The renderer is not known yet: these are the software renderer's choices, and the tracer's factory takes the
// renderer's list decisions once its context is current (MethodInfo::recommendedChcrt, app/method_tracers.cpp).
void recommendedChcrtDefaults(CommonOptions& d, const CommonOptions& user, uint64_t) {
    if (user.outOfCoreScene.enabled) {
        d.chcrt.queries = ChcrtQueries::Batched;
        d.chcrt.cellIntersect = true;
        d.chcrt.bounds.cellSize = kRecommendedBoundsCellSize;
        d.chcrt.hitHints = true;
        d.chcrt.hintPass = true;
        d.chcrt.hintPassMaxLeft = 0.5f;
        return;
    }
    d.chcrt = recommendedChcrtOptions();
    if (user.isGiven("--chcrt-height")) d.chcrt.adaptiveHeights.clear();
}

void noAdaptDefaults(CommonOptions& d, const CommonOptions& user, uint64_t triangles) {
    recommendedChcrtDefaults(d, user, triangles);
    d.chcrt.adaptive = false;
}

// chcrt-lod (issue #19): out-of-core CHC+RT tracing a subtree's LOD proxy where its error projects below one pixel
// (docs/outofcore.md, "LOD proxies"): the threshold at which the measured far-view PSNR against exact tracing stays
// high while most far subtrees are served as proxies. Its pairs are decided by the ray bounds grid (bounds-only), not
// by batched tests: with proxies a view's working set fits the cache, and one intersection round per trace instead of
// a round per batched test took the 140M city's far frames from 514 to 190 ms and its near frames from 113 to 95 ms
// with the same images and uploads (exact out-of-core tracing keeps the ray-exact tests: there the grid's looser
// lists made the near path upload 670 MB per primary trace into a cache that held it with batched tests).
void lodDefaults(CommonOptions& d, const CommonOptions& user, uint64_t triangles) {
    recommendedChcrtDefaults(d, user, triangles);
    d.outOfCore.lodPixels = 1.0f;
    d.chcrt.queries = ChcrtQueries::BoundsOnly;
    d.chcrt.cellIntersect = false; // bounds-only always intersects by cells
}

// Exact skipping for every ray type (bvh+ls-exact falls back to pure BVH when it would not pay: method_tracers.cpp).
void exactLineSpaceDefaults(CommonOptions& d, const CommonOptions&, uint64_t) {
    d.lineSpaceTracing.baseModes = ls::LineSpaceModes::allExact();
}

// bvh+ls: the configuration of linespace/README.md's measurements that is good on every measured scene. N = 6,
// D = 6, T = 8: D = 6 was the fastest depth on every scene of the RC table (69k-1M triangles; 14k-17k triangles per
// Line Space node on the dragon and the 1M city), and larger scenes get one level more per doubling, so that a node
// holds at most about as many triangles (kTrianglesPerLineSpace), up to D = 12 (361 MB at N = 6 on the dragon).
// Diffuse rays use representative candidates (dragon 2.2x at 37.3 dB final, 1 spp; city 1.6x at 29.7 dB). Shadow
// and bounce-shadow rays are exact: exact skipping gives the hits of no skipping and measured 0.49-1.03x of pure
// BVH (69-98 % of the shafts filled on every scene), so they run without Line Spaces ("off"). AO rays too: AO
// candidates pay on the dragon (AO 1.9x at 38.4 dB, 4 spp) but take the city to 23.8 dB (1 spp; short AO rays start
// inside large nodes, linespace/README.md "The city target, swept"), and no measured property of a scene tells the
// two apart (the patch edge over the AO length at D = 6: dragon 0.79, bunny 0.80, castle 0.87, city 0.69, interior
// 0.77, plant 0.63), so they are opt-in: --ls-modes ao=candidate (the dragon's indirect target).
constexpr uint64_t kTrianglesPerLineSpace = 24576; // 1.5M / 2^6
uint32_t lineSpaceDepthFor(uint64_t triangles) {
    uint32_t depth = 6;
    while (depth < 12 && triangles > (kTrianglesPerLineSpace << depth)) ++depth;
    return depth;
}

void candidateLineSpaceDefaults(CommonOptions& d, const CommonOptions&, uint64_t triangles) {
    d.lineSpace.depth = lineSpaceDepthFor(triangles);
    ls::LineSpaceModes& m = d.lineSpaceTracing.baseModes;
    m.primary = m.shadow = m.bounceShadow = m.ao = ls::LineSpaceMode::Off;
    m.diffuse = ls::LineSpaceMode::Candidate;
}

// SS Algorithm 1 "deep enough": the level above the N-tree's leaves.
void nTreeDefaults(CommonOptions& d, const CommonOptions& user, uint64_t) {
    d.ntreeShadow.shadowLevel = user.ntree.depth > 0 ? user.ntree.depth - 1 : 0;
}

std::vector<MethodInfo> registerMethods() {
    const std::vector<Area> chcrt = {Area::Chcrt};
    const std::vector<Area> lineSpace = {Area::LineSpace, Area::LineSpaceModes, Area::LineSpaceCache};
    const std::vector<Area> chcrtLineSpace = {Area::Chcrt, Area::LineSpace, Area::LineSpaceCache};
    return {
        {.name = kPureBvhMethod, .description = "pure BVH traversal in GLSL (the baseline)"},
        {.name = "chcrt",
         .description = "CHC+RT: occlusion-query culling of BVH subtrees per screen tile (conservative, exact)",
         .areas = chcrt, .outOfCoreForm = true, .chcrtDebugImages = true, .recommendedChcrt = true,
         .setDefaults = recommendedChcrtDefaults,
         .makeTracer = makeChcrtTracer},
        {.name = "chcrt-aggressive", .exact = false,
         .description = "CHC+RT culling pairs whose query passes <= 20 rays (approximate)",
         .areas = {Area::Chcrt, Area::ChcrtVisibility}, .outOfCoreForm = true, .chcrtDebugImages = true,
         .setDefaults = aggressiveDefaults, .makeTracer = makeChcrtTracer},
        {.name = "chcrt-lod", .exact = false,
         .description = "CHC+RT out of core tracing a subtree's level-of-detail proxy where its error projects below "
                        "--lod-pixels (approximate; prepared scenes with proxies)",
         .areas = {Area::Chcrt, Area::Lod}, .outOfCoreForm = true, .chcrtDebugImages = true,
         .setDefaults = lodDefaults, .makeTracer = makeChcrtTracer},
        {.name = "chcrt-noadapt",
         .description = "CHC+RT without the adaptive fallback to a pure pass (always culls; exact)",
         .areas = chcrt, .outOfCoreForm = true, .chcrtDebugImages = true, .recommendedChcrt = true,
         .setDefaults = noAdaptDefaults,
         .makeTracer = makeChcrtTracer},
        {.name = "bvh+ls-exact",
         .description = "BVH with exact empty-space skipping at binary Line Space nodes (pure BVH where more than "
                        "half the shafts are filled)",
         .areas = lineSpace, .needs = kNeedsLineSpaces, .setDefaults = exactLineSpaceDefaults,
         .makeTracer = makeLineSpaceTracer, .cacheBuild = lineSpaceCacheBuild},
        {.name = "bvh+ls", .exact = false,
         .description = "BVH + Line Space: representative candidates for diffuse rays, exact shadows and AO "
                        "(approximate; --ls-modes ao=candidate also for AO)",
         .areas = lineSpace, .needs = kNeedsLineSpaces, .setDefaults = candidateLineSpaceDefaults,
         .makeTracer = makeLineSpaceTracer, .cacheBuild = lineSpaceCacheBuild},
        {.name = "chcrt+ls-exact",
         .description = "CHC+RT with exact empty-space skipping at Line Space nodes inside its subtrees",
         .areas = chcrtLineSpace, .needs = kNeedsLineSpaces, .chcrtDebugImages = true,
         .makeTracer = makeChcrtTracer, .cacheBuild = lineSpaceCacheBuild},
        {.name = "chcrt+ls", .exact = false,
         .description = "CHC+RT with Line Spaces in its subtrees: any-hit rays (shadow, AO) end at occupied shafts "
                        "(SS 4.1), closest-hit rays skip empty ones (approximate)",
         .areas = chcrtLineSpace, .needs = kNeedsLineSpaces, .chcrtDebugImages = true,
         .makeTracer = makeChcrtTracer, .cacheBuild = lineSpaceCacheBuild},
        {.name = "ntree+ls", .exact = false,
         .description = "shadow rays over an N-tree with binary Line Spaces, occluded at occupied shafts of level d-1 "
                        "(soft-shadow paper; approximate); other rays: pure BVH",
         .areas = {Area::NTree, Area::LineSpaceCache}, .needs = kNeedsNTree, .setDefaults = nTreeDefaults,
         .makeTracer = makeNTreeTracer, .cacheBuild = nTreeCacheBuild},
        {.name = "embree", .description = "Embree on the CPU: the reference of pure BVH tracing (read-back rays)",
         .gpu = false, .needs = kNeedsEmbree},
    };
}

bool isMethodParameter(const Parameter& p) { return isMethodArea(p.area); }

} // namespace

bool MethodInfo::reads(ParameterArea area) const {
    return std::find(areas.begin(), areas.end(), area) != areas.end();
}

std::vector<std::string> benchTraceOrder(const std::vector<std::string>& methods, size_t passIndex) {
    std::vector<std::string> order = methods;
    const auto others = order.begin() + (!order.empty() && order.front() == kPureBvhMethod ? 1 : 0);
    if (passIndex % 2 == 1) std::reverse(others, order.end());
    return order;
}

std::string describeNeeds(uint8_t needs) {
    std::string text;
    const auto add = [&](uint8_t bit, const char* what) {
        if (needs & bit) text += (text.empty() ? "" : ", ") + std::string(what);
    };
    add(kNeedsLineSpaces, "Line Spaces (built or --ls-cache)");
    add(kNeedsNTree, "N-tree (built or --ls-cache)");
    add(kNeedsEmbree, "Embree, the scene in core");
    return text.empty() ? "-" : text;
}

const std::vector<MethodInfo>& methodRegistry() {
    static const std::vector<MethodInfo> methods = registerMethods();
    return methods;
}

std::vector<const MethodInfo*> gpuMethods() {
    std::vector<const MethodInfo*> out;
    for (const MethodInfo& m : methodRegistry()) {
        if (m.gpu) out.push_back(&m);
    }
    return out;
}

std::string methodNames(bool withReference) {
    std::string names;
    for (const MethodInfo& m : methodRegistry()) {
        if (m.gpu || withReference) names += (names.empty() ? "" : ", ") + m.name;
    }
    return names;
}

const MethodInfo& findMethod(const std::string& name) {
    for (const MethodInfo& m : methodRegistry()) {
        if (m.name == name) return m;
    }
    throw InputError("unknown method '" + name + "' (available: " + methodNames() + ")");
}

const MethodInfo& findGpuMethod(const std::string& name) {
    const MethodInfo& m = findMethod(name);
    if (!m.gpu) throw InputError("method " + name + " is not a GPU tracing method (bench compares it; verify checks bvh against it)");
    return m;
}

Table methodTable() {
    Table table;
    table.header = {"method", "what it does", "hits", "needs", "out of core"};
    for (const MethodInfo& m : methodRegistry()) {
        table.rows.push_back({m.name, m.description, !m.gpu ? "reference (CPU)" : m.exact ? "exact" : "approximate",
                              describeNeeds(m.needs), m.outOfCoreForm ? "yes" : "-"});
    }
    return table;
}

CommonOptions methodDefaults(const MethodInfo& method, const CommonOptions& user, uint64_t triangles) {
    CommonOptions d = user;
    copyParameters(CommonOptions{}, d, isMethodParameter); // the areas' structs' own defaults, nothing given
    if (method.setDefaults) method.setDefaults(d, user, triangles);
    return d;
}

CommonOptions resolveMethodOptions(const MethodInfo& method, const CommonOptions& user, uint64_t triangles) {
    CommonOptions resolved = methodDefaults(method, user, triangles);
    // Every given flag, also of areas the method does not read: its factory refuses those it must (a visibility
    // threshold for exact CHC+RT) and ignores the others.
    copyParameters(user, resolved, [&](const Parameter& p) { return isMethodArea(p.area) && user.isGiven(p.flag); });
    return resolved;
}

uint64_t sceneTriangles(const SceneSession& session) {
    return session.sceneInCore ? session.scene.triangleCount() : session.fileTriangles;
}

std::unique_ptr<Tracer> makeTracer(const std::string& name, const SceneSession& session, bool alwaysCull) {
    const MethodInfo& method = findGpuMethod(name);
    if (session.options.outOfCoreScene.enabled && !method.outOfCoreForm) {
        throw InputError("--out-of-core: method " + name + " has no out-of-core form (pure BVH and Line Space tracing "
                         "need the whole scene on the GPU); use --method chcrt or chcrt-aggressive");
    }
    if (!method.makeTracer) return nullptr; // "bvh"
    const CommonOptions resolved = resolveMethodOptions(method, session.options, sceneTriangles(session));
    return method.makeTracer(method, session, resolved, alwaysCull);
}

std::function<void(Progress&)> methodCacheBuild(const std::string& name, const SceneSession& session) {
    const MethodInfo& method = findGpuMethod(name);
    const CommonOptions& o = session.options;
    if (!method.cacheBuild || o.lineSpaceTracing.cacheDirectory.empty() || o.outOfCoreScene.enabled) return {};
    return method.cacheBuild(method, session, resolveMethodOptions(method, o, sceneTriangles(session)));
}

} // namespace chcrt::app
