#include "culling/chcrt_tracer.h"

#include "culling/bvh_subtree_source.h"
#include "renderer/core/aabb.h"
#include "renderer/core/error.h"
#include "renderer/core/timing.h"
#include "renderer/render/bvh_tracer.h"
#include "renderer/render/trace_pass.h"
#include "renderer/render/trace_stage.h"
#include "shaders/shared/culling_layout.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <tuple>
#include <unordered_map>

namespace chcrt {
namespace {

using Clock = std::chrono::steady_clock;

// The bounds debug image's value of an unbounded cell (NaN bits: no t of a bounded cell has them).
constexpr uint32_t kUnboundedCell = 0xFFFFFFFFu;

ShaderProgram makeProgram(const char* fragment, bool anyHit, std::vector<ShaderDefine> defines = {}) {
    defines.push_back({"TRACE_ANY_HIT", anyHit ? "1" : "0"});
    return ShaderProgram({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"}, {GL_FRAGMENT_SHADER, fragment}},
                         defines);
}



// The kind of ray a request traces (its RayType, or the diffuse effect's bounce shadow rays).
uint64_t rayKind(const TraceRequest& request) {
    return request.bounceShadow ? uint64_t(CHCRT_RAY_BOUNCE_SHADOW) : uint64_t(request.rayType);
}

// §5.3: one visibility state for all primary rays, one for all shadow rays, one for the bounce shadow rays,
// and one per sample index for AO and diffuse rays (their directions differ per pass).
uint64_t rayStateKey(const TraceRequest& request) {
    const bool perSample = !request.bounceShadow && (request.rayType == RayType::Ao || request.rayType == RayType::Diffuse);
    return (rayKind(request) << 32) | uint64_t(perSample ? uint32_t(request.sampleIndex) : 0u);
}

// Hit hints are kept per ray set and sample index, for every ray kind. A sample's rays (§5.3: one light point, AO
// or diffuse direction per pixel and sample index) meet the same occluders from frame to frame; the shadow rays of
// two samples aim at different points of the area light, so with one image per kind each sample started from the
// previous sample's hits (castle street, 256², 16 shadow spp, one view: the hint pass left 73 % of the rays against
// 2.3 % per sample; culling/README.md "Hit hints"). At most `sets` images per kind (ChcrtOptions::hintMemoryBytes):
// beyond, sample indices share them (hints never change hits).
uint64_t hintKey(const TraceRequest& request, uint32_t sets) {
    return (rayKind(request) << 32) | uint64_t(uint32_t(request.sampleIndex) % sets);
}

// The adaptive choice is kept per ray kind, not per ray set: the 20 AO (or diffuse) sample sets of a frame cost
// about the same, and per set each saw too few traces in a walkthrough to average out the noise of a shared
// machine (far AO on interior 1M: 20% of the traces culled although culling was 1.19x slower).
uint64_t adaptiveKey(const TraceRequest& request) { return rayKind(request); }

void validate(const ChcrtOptions& o) {
    if (o.batchSize < 1 || o.batchSize > CHCRT_CULLING_MAX_BATCH) {
        throw InputError("chcrt: batch size must be in [1, " + std::to_string(CHCRT_CULLING_MAX_BATCH) + "]");
    }
    if (o.pairs.minTileSize < 1) throw InputError("chcrt: minimum tile size must be positive");
    if (o.flushThreshold < 0) throw InputError("chcrt: flush threshold must not be negative");
    if (o.requeryInterval < 1 || o.requeryInterval > 255) throw InputError("chcrt: re-query interval must be in [1, 255]");
    if (!(o.pairs.tq > 0.0f)) throw InputError("chcrt: t_q must be positive");
    if (o.multiQueryPairs > CHCRT_CULLING_MAX_QUERY_BOXES / 2) {
        throw InputError("chcrt: at most " + std::to_string(CHCRT_CULLING_MAX_QUERY_BOXES / 2) + " pairs per multi-query");
    }
    if (o.adaptiveProbeInterval < 1) throw InputError("chcrt: adaptive probe interval must be at least 1");
    if (decidesByBounds(o.queries) && o.visibleThreshold > 0) {
        throw InputError("chcrt: the aggressive threshold counts rays per query; it needs --chcrt-queries gl");
    }
    if (decidesByBounds(o.queries) && o.subtreeDefines) {
        throw InputError("chcrt: cell lists traverse the pure BVH; another subtree traversal needs --chcrt-queries gl");
    }
}

const char* debugDefine(ChcrtDebugImage kind) {
    switch (kind) {
    case ChcrtDebugImage::Overdraw: return "CHCRT_CULLING_DEBUG_OVERDRAW";
    case ChcrtDebugImage::Subtrees: return "CHCRT_CULLING_DEBUG_SUBTREES";
    case ChcrtDebugImage::Batches: return "CHCRT_CULLING_DEBUG_BATCHES";
    case ChcrtDebugImage::Cost: return "CHCRT_CULLING_DEBUG_COST";
    default: return "CHCRT_CULLING_DEBUG_NONE";
    }
}

} // namespace

ChcrtOptions recommendedChcrtOptions(const RendererTraits& renderer) {
    ChcrtOptions options;
    options.partition.maxSubtreeHeight = 12;
    options.adaptiveHeights = {10, 14};
    options.cellListLimit = 64;
    options.hitHints = true;
    options.hintPass = true;
    options.shareShadowLists = true;
    options.hemisphereBounds = true; // where the lists are decided on the CPU (bounds-only)
    // The renderer's part (chcrt_tracer.h says why): lists decided on the GPU and traced in compute dispatches on
    // GPUs, decided on the CPU and traced in fragment passes on software rasterisers.
    options.queries = renderer.software ? ChcrtQueries::BoundsOnly : ChcrtQueries::BoundsGpu;
    options.computeCellPass = autoTraceStage(renderer) == TraceStage::Compute;
    // On every renderer: only the list decisions and the stage follow the renderer (app/method_tracers.cpp).
    options.bounds.cellSize = kRecommendedBoundsCellSize;
    return options;
}

ChcrtOptions recommendedChcrtOptions() { return recommendedChcrtOptions(RendererTraits{.software = true}); }

const char* toString(ChcrtQueries queries) {
    switch (queries) {
    case ChcrtQueries::Gl: return "gl";
    case ChcrtQueries::Batched: return "batched";
    case ChcrtQueries::BoundsOnly: return "bounds-only";
    default: return "bounds-gpu";
    }
}

ChcrtQueries parseChcrtQueries(const std::string& name) {
    if (name == "gl") return ChcrtQueries::Gl;
    if (name == "batched") return ChcrtQueries::Batched;
    if (name == "bounds-only") return ChcrtQueries::BoundsOnly;
    if (name == "bounds-gpu") return ChcrtQueries::BoundsGpu;
    throw InputError("unknown CHC+RT query mode '" + name + "' (available: gl, batched, bounds-only, bounds-gpu)");
}

bool decidesByBounds(ChcrtQueries queries) {
    return queries == ChcrtQueries::BoundsOnly || queries == ChcrtQueries::BoundsGpu;
}

ChcrtDebugImage parseChcrtDebugImage(const std::string& name) {
    if (name == "overdraw") return ChcrtDebugImage::Overdraw;
    if (name == "subtrees") return ChcrtDebugImage::Subtrees;
    if (name == "batches") return ChcrtDebugImage::Batches;
    if (name == "cost") return ChcrtDebugImage::Cost;
    if (name == "bounds") return ChcrtDebugImage::Bounds;
    throw InputError("unknown debug image '" + name + "' (available: overdraw, subtrees, batches, cost, bounds)");
}

namespace {

// The bounds image: t of bounded cells on a log ramp between the image's extremes, magenta for unbounded cells.
std::vector<float> colorizeBoundsImage(const std::vector<uint32_t>& values, int width, int height) {
    std::vector<float> rgb(size_t(width) * height * 3, 0.0f);
    float lo = 3.0e38f, hi = 0.0f;
    for (uint32_t v : values) {
        if (v == 0 || v == kUnboundedCell) continue;
        lo = std::min(lo, std::bit_cast<float>(v));
        hi = std::max(hi, std::bit_cast<float>(v));
    }
    const float range = hi > lo ? std::log(hi / lo) : 1.0f;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const uint32_t v = values[size_t(height - 1 - y) * width + x]; // GL rows are bottom to top
            float* out = &rgb[(size_t(y) * width + x) * 3];
            if (v == 0) continue;
            if (v == kUnboundedCell) {
                out[0] = out[2] = 1.0f;
                continue;
            }
            const float s = hi > lo ? std::log(std::bit_cast<float>(v) / lo) / range : 1.0f;
            out[0] = std::clamp(2.0f * s - 0.5f, 0.0f, 1.0f);
            out[1] = std::clamp(2.0f * s, 0.0f, 1.0f) * (s < 0.75f ? 1.0f : 4.0f * (1.0f - s));
            out[2] = std::clamp(1.0f - 2.0f * s, 0.0f, 1.0f);
        }
    }
    return rgb;
}

} // namespace

std::vector<float> colorizeChcrtDebugImage(ChcrtDebugImage kind, const std::vector<uint32_t>& values, int width,
                                           int height) {
    std::vector<float> rgb(size_t(width) * height * 3, 0.0f);
    if (kind == ChcrtDebugImage::Bounds) return colorizeBoundsImage(values, width, height);
    const bool cost = kind == ChcrtDebugImage::Cost;
    uint32_t maxValue = 0;
    for (uint32_t v : values) maxValue = std::max(maxValue, cost ? v & CHCRT_TRACE_STEPS_COUNT : v);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const uint32_t v = values[size_t(height - 1 - y) * width + x]; // GL rows are bottom to top
            float* out = &rgb[(size_t(y) * width + x) * 3];
            if (v == 0) continue;
            if (kind == ChcrtDebugImage::Subtrees) {
                uint32_t h = v * 0x9E3779B1u;
                h ^= h >> 15;
                h *= 0x85EBCA77u;
                h ^= h >> 13;
                for (int c = 0; c < 3; ++c) out[c] = 0.25f + 0.75f * float((h >> (8 * c)) & 255u) / 255.0f;
            } else if (cost && (v & CHCRT_TRACE_STEPS_CAPPED) != 0) {
                out[0] = 1.0f; // magenta: a pass reached the loop cap (the count is cut short), as the cost view
                out[2] = 1.0f;
            } else {
                // Heat ramp: blue -> green -> yellow -> red as the count approaches the image's maximum. Costs span
                // orders of magnitude (a sky ray tests one box, a grazing one thousands): log scale for them.
                const float s = cost ? std::log2(1.0f + float(v)) / std::log2(1.0f + float(std::max(maxValue, 1u)))
                                     : float(v) / float(std::max(maxValue, 1u));
                out[0] = std::clamp(2.0f * s - 0.5f, 0.0f, 1.0f);
                out[1] = std::clamp(2.0f * s, 0.0f, 1.0f) * (s < 0.75f ? 1.0f : 4.0f * (1.0f - s));
                out[2] = std::clamp(1.0f - 2.0f * s, 0.0f, 1.0f);
            }
        }
    }
    return rgb;
}

ChcrtStats& ChcrtStats::operator+=(const ChcrtStats& o) {
    traces += o.traces;
    fallbackTraces += o.fallbackTraces;
    heightSum += o.heightSum;
    queries += o.queries;
    queriesSingle += o.queriesSingle;
    queriesMulti += o.queriesMulti;
    queriesMultiFailed += o.queriesMultiFailed;
    queriesInvisible += o.queriesInvisible;
    queriesLazy += o.queriesLazy;
    queriesTraversal += o.queriesTraversal;
    queriesSkippedExtent += o.queriesSkippedExtent;
    leavesSkippedExtent += o.leavesSkippedExtent;
    subtreesPostponed += o.subtreesPostponed;
    pairsDecidedBounds += o.pairsDecidedBounds;
    pairsTestedBatched += o.pairsTestedBatched;
    batchedRounds += o.batchedRounds;
    boundsUpdates += o.boundsUpdates;
    boundsFromCamera += o.boundsFromCamera;
    boundsFromHemisphere += o.boundsFromHemisphere;
    cellsDrawn += o.cellsDrawn;
    cellEntries += o.cellEntries;
    cellsWholeTree += o.cellsWholeTree;
    hintPasses += o.hintPasses;
    hintRaysLeft += o.hintRaysLeft;
    sharedListsMade += o.sharedListsMade;
    sharedListsReused += o.sharedListsReused;
    boundsCulledPieces += o.boundsCulledPieces;
    boundsCulledFrustum += o.boundsCulledFrustum;
    boundsReached += o.boundsReached;
    boundsMs += o.boundsMs;
    decideMs += o.decideMs;
    cellListMs += o.cellListMs;
    subtreePassMs += o.subtreePassMs;
    hintPassMs += o.hintPassMs;
    passTimedTraces += o.passTimedTraces;
    pairsVisible += o.pairsVisible;
    pairsInvisible += o.pairsInvisible;
    pairsNewlyVisible += o.pairsNewlyVisible;
    pairsPulledUp += o.pairsPulledUp;
    subtreesScheduled += o.subtreesScheduled;
    shaderCalls += o.shaderCalls;
    barriers += o.barriers;
    residencyRounds += o.residencyRounds;
    raysTraced += o.raysTraced;
    phase1Ms += o.phase1Ms;
    phase2Ms += o.phase2Ms;
    phase3Ms += o.phase3Ms;
    fallbackMs += o.fallbackMs;
    return *this;
}

ChcrtTracer::ChcrtTracer(const Bvh& bvh, const ChcrtOptions& options, std::string name)
    : ChcrtTracer(bvh, options, std::move(name), std::make_shared<ProgramCache>()) {}

ChcrtTracer::ChcrtTracer(const Bvh& bvh, const ChcrtOptions& options, std::string name,
                         std::shared_ptr<ProgramCache> programs)
    : name_(std::move(name)), options_((validate(options), options)), bvh_(&bvh),
      hierarchy_(buildCullingHierarchy(bvh, options.partition)), programCache_(std::move(programs)) {
    heightArms_.resize(options_.adaptiveHeights.size());
    ownedSource_ = std::make_unique<BvhSubtreeSource>(hierarchy_);
    source_ = ownedSource_.get();
    if (options_.adaptive) {
        ownedFullTracer_ = std::make_unique<BvhTracer>();
        fullTracer_ = ownedFullTracer_.get();
        // The other heights' hierarchies and shaders now, not inside the first traces that probe them (a short
        // walkthrough would pay for them: city near, 4 frames, primary ran at 0.55x of pure BVH).
        for (uint32_t arm = 2; arm < 2 + heightArms_.size(); ++arm) armTracer(arm);
    }
    compilePrograms();
}

ChcrtTracer::ChcrtTracer(CullingHierarchy hierarchy, SubtreeSource& source, Tracer* fullTracer,
                         const ChcrtOptions& options, std::string name)
    : name_(std::move(name)), options_((validate(options), options)), hierarchy_(std::move(hierarchy)),
      source_(&source), fullTracer_(fullTracer) {
    if (hierarchy_.nodes.empty() || hierarchy_.subtrees.empty()) throw InputError("chcrt: empty culling hierarchy");
    if (options_.queries == ChcrtQueries::BoundsGpu) {
        throw InputError("chcrt: --chcrt-queries bounds-gpu needs the scene's BVH in core (its cells may traverse the "
                         "whole tree); out of core use gl or bounds-only");
    }
    compilePrograms();
}

std::vector<ShaderDefine> ChcrtTracer::subtreeDefines(bool anyHit) const {
    // A subtree of height h pushes at most h entries (one per level below its root).
    const uint32_t stack = std::min<uint32_t>(hierarchy_.maxSubtreeHeight + 1, CHCRT_MAX_BVH_DEPTH);
    // The leaf cache and merged batches have only a pure form: a traversal the options name instead (Line Space
    // traversal, subtreeDefines) takes one root at a time.
    const bool pureTraversal = !options_.subtreeDefines;
    std::vector<ShaderDefine> defines = {
        {"CHCRT_SUBTREE_STACK", std::to_string(stack)},
        {"CHCRT_CULLING_LEAF_CACHE", options_.leafCache && pureTraversal ? "1" : "0"},
        {"CHCRT_CULLING_MERGED_BATCH", options_.mergedBatch && pureTraversal ? "1" : "0"},
        {"CHCRT_COMPACT_SUBTREES", source_->compactLayout() ? "1" : "0"}};
    if (options_.subtreeDefines) {
        for (ShaderDefine& d : options_.subtreeDefines(anyHit)) defines.push_back(std::move(d));
    }
    return defines;
}

std::unique_ptr<CellTraversal> ChcrtTracer::makeCellTraversal() {
    // Cells over the list limit traverse the whole BVH: a stack as deep as the pure tracer's.
    // (The GPU's lists send a cell over CHCRT_CULLING_GPU_LIST_MAX subtrees there whatever the limit.)
    const bool wholeTree = bvh_ != nullptr && (options_.cellListLimit > 0 || options_.queries == ChcrtQueries::BoundsGpu);
    const bool hints = hintsAvailable();
    auto cells = std::make_unique<CellTraversal>([this, wholeTree, hints](bool anyHit) {
        std::vector<ShaderDefine> defines = subtreeDefines(anyHit);
        for (ShaderDefine& d : defines) {
            if (wholeTree && d.name == "CHCRT_SUBTREE_STACK") d.value = std::to_string(CHCRT_MAX_BVH_DEPTH);
        }
        defines.push_back({"CHCRT_CULLING_HINTS", hints && (anyHit || options_.closestHitHints) ? "1" : "0"});
        defines.push_back(hintSlotsDefine());
        return defines;
    }, options_.computeCellPass ? options_.bounds.cellSize : 0, programCache_);
    if (wholeTree) cells->setWholeTree(0u, options_.cellListLimit);
    return cells;
}

void ChcrtTracer::compilePrograms() {
    const bool bounded = decidesByBounds(options_.queries);
    if ((options_.rayExtentCulling || bounded || intersectsByCells()) && !rayExtent_) {
        rayExtent_ = std::make_unique<RayBoundsGrid>(options_.bounds, programCache_);
    }
    if ((bounded || intersectsByCells()) && !cells_) {
        const bool hints = hintsAvailable();
        cells_ = makeCellTraversal();
        const bool hintPass = hints && options_.hintPass;
        cells_->compile(hintPass);
        if (options_.shareShadowLists && bvh_ != nullptr && options_.queries == ChcrtQueries::BoundsOnly) {
            sharedCells_ = makeCellTraversal(); // the same programs (one cache)
        }
        if (hintPass) {
            hintPass_ = std::make_unique<HintPass>(options_.computeCellPass, options_.bounds.cellSize,
                                                   std::vector<ShaderDefine>{hintSlotsDefine(),
                                                                             {"CHCRT_COMPACT_SUBTREES",
                                                                              source_->compactLayout() ? "1" : "0"}},
                                                   programCache_);
        }
    }
    if (options_.queries == ChcrtQueries::Batched && !batched_) batched_ = std::make_unique<BatchedQueries>();
    if (options_.queries == ChcrtQueries::BoundsGpu && !gpuLists_) {
        gpuLists_ = std::make_unique<GpuCellLists>(hierarchy_, options_.bounds.pieces, programCache_);
        if (options_.shareShadowLists) {
            sharedGpuLists_ = std::make_unique<GpuCellLists>(hierarchy_, options_.bounds.pieces, programCache_);
        }
    }
    for (int anyHit = 0; anyHit < 2; ++anyHit) {
        const std::vector<ShaderDefine> defines = subtreeDefines(anyHit != 0);
        queryPrograms_[anyHit] = makeProgram("culling/chcrt_query.frag.glsl", anyHit != 0);
        subtreePrograms_[anyHit] = makeProgram("culling/chcrt_subtrees.frag.glsl", anyHit != 0, defines);
        std::vector<ShaderDefine> singleDefines = defines;
        singleDefines.push_back({"CHCRT_CULLING_SINGLE_SUBTREE", "1"});
        singleSubtreePrograms_[anyHit] = makeProgram("culling/chcrt_subtrees.frag.glsl", anyHit != 0, singleDefines);
    }
}

// The instrumented variants of one debug image, compiled on its first use and kept: the out-of-core viewer switches
// between two kinds every frame (its G-buffer records subtrees, its debug view another kind).
const ChcrtTracer::DebugPrograms& ChcrtTracer::debugPrograms(ChcrtDebugImage kind) {
    auto it = debugPrograms_.find(kind);
    if (it != debugPrograms_.end()) return it->second;
    DebugPrograms programs;
    const ShaderDefine debug{debugDefine(kind), "1"};
    for (int anyHit = 0; anyHit < 2; ++anyHit) {
        std::vector<ShaderDefine> defines = subtreeDefines(anyHit != 0);
        defines.push_back(debug);
        if (kind == ChcrtDebugImage::Subtrees) defines.push_back({"CHCRT_HIT_TRIANGLE_INDEX", "1"});
        programs.query[anyHit] = makeProgram("culling/chcrt_query.frag.glsl", anyHit != 0, {debug});
        programs.subtree[anyHit] = makeProgram("culling/chcrt_subtrees.frag.glsl", anyHit != 0, defines);
    }
    return debugPrograms_.emplace(kind, std::move(programs)).first->second;
}

ChcrtTracer::~ChcrtTracer() {
    if (!queryPool_.empty()) glDeleteQueries(GLsizei(queryPool_.size()), queryPool_.data());
}

void ChcrtTracer::setDebugImage(ChcrtDebugImage kind) {
    debugKind_ = kind;
    debugActive_ = kind != ChcrtDebugImage::None ? &debugPrograms(kind) : nullptr;
}

void ChcrtTracer::ensureDebugTexture(int width, int height) {
    if (debugTexture_.id() != 0 && debugWidth_ == width && debugHeight_ == height) return;
    debugTexture_ = createTexture2D(width, height, GL_R32UI);
    hitTriangleTexture_ = createTexture2D(width, height, GL_R32UI);
    debugWidth_ = width;
    debugHeight_ = height;
    clearDebugImage();
}

void ChcrtTracer::clearDebugImage() {
    if (debugTexture_.id() == 0) return;
    const GLuint zero = 0;
    glClearTexImage(debugTexture_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
}

// An R32UI image of the debug size (zeros before the first trace with a debug image).
std::vector<uint32_t> ChcrtTracer::readDebugSizedImage(const GlTexture& texture) const {
    std::vector<uint32_t> values(size_t(debugWidth_) * debugHeight_, 0u);
    if (texture.id() == 0) return values;
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    glGetTextureImage(texture.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(values.size() * 4), values.data());
    return values;
}

std::vector<uint32_t> ChcrtTracer::readHitTriangleImage() const { return readDebugSizedImage(hitTriangleTexture_); }

std::vector<uint32_t> ChcrtTracer::readDebugImage() const { return readDebugSizedImage(debugTexture_); }

const ShaderProgram& ChcrtTracer::queryProgram(bool anyHit) const {
    return debugActive_ ? debugActive_->query[anyHit] : queryPrograms_[anyHit];
}

const ShaderProgram& ChcrtTracer::subtreeProgram(bool anyHit) const {
    return debugActive_ ? debugActive_->subtree[anyHit] : subtreePrograms_[anyHit];
}

VisibilityState& ChcrtTracer::stateFor(const TraceRequest& request, int width, int height) {
    std::unique_ptr<VisibilityState>& state = states_[rayStateKey(request)];
    const bool temporal = options_.queries == ChcrtQueries::BoundsOnly ? options_.boundsPreviousFront
                                                                       : options_.temporalCoherence;
    if (!state || !temporal || state->width() != width || state->height() != height) {
        state = std::make_unique<VisibilityState>(width, height, options_.seed ^ uint32_t(rayStateKey(request)));
    }
    return *state;
}

GLuint ChcrtTracer::framebufferFor(const HitTargets& hits) {
    // The generalized queries need a depth-only target over the hit set's depth buffer; the hit buffer itself is
    // read and written as an image, never through the framebuffer (no feedback loop).
    return maskFramebufferFor(hits.depth.id());
}

bool ChcrtTracer::hintsAvailable() const {
    if (!options_.hitHints) return false;
    if (bvh_ != nullptr) return decidesByBounds(options_.queries);
    // Out of core a cache slot's nodes change as subtrees come and go: hints are visited only by the hint pass at a
    // trace's start, before this trace replaces any slot, which drops those whose slot was replaced since they were
    // validated (shaders/culling/hint_leaf.glsl), and recorded by the cell passes of batched rounds.
    return intersectsByCells() && source_->hintsSupported();
}

GLuint ChcrtTracer::hintTexture(const TraceRequest& request) const {
    const auto it = hintStore_->find(hintKey(request, hintSets_));
    return it == hintStore_->end() ? 0 : it->second.texture.id();
}

namespace {
// A copy of an R32UI hint image (made if `to` does not exist yet or has another size).
void copyHintImage(const GlTexture& from, GlTexture& to) {
    const TextureExtent extent = textureExtent(from.id());
    if (textureExtent(to.id()) != extent) to = createTexture2D(extent.width, extent.height, GL_R32UI);
    glCopyImageSubData(from.id(), GL_TEXTURE_2D, 0, 0, 0, 0, to.id(), GL_TEXTURE_2D, 0, 0, 0, 0, extent.width,
                       extent.height, 1);
}
} // namespace

ChcrtTracer::HintSnapshot ChcrtTracer::saveHints() const {
    HintSnapshot snapshot;
    snapshot.records = *hintPassRecords_;
    for (const auto& [key, image] : *hintStore_) {
        if (image.texture.id() == 0) continue;
        HintImage& copy = snapshot.images[key];
        copyHintImage(image.texture, copy.texture);
        copy.extent = image.extent;
        copy.epoch = image.epoch;
        copy.passed = image.passed;
        copy.droppedStale = image.droppedStale;
    }
    return snapshot;
}

void ChcrtTracer::restoreHints(const HintSnapshot& snapshot) {
    *hintPassRecords_ = snapshot.records;
    for (auto it = hintStore_->begin(); it != hintStore_->end();) {
        const auto saved = snapshot.images.find(it->first);
        if (saved == snapshot.images.end()) {
            it = hintStore_->erase(it);
            continue;
        }
        HintImage& image = it->second;
        copyHintImage(saved->second.texture, image.texture);
        image.extent = saved->second.extent;
        image.epoch = saved->second.epoch;
        image.passed = saved->second.passed;
        image.droppedStale = saved->second.droppedStale;
        ++it;
    }
    // The copies are texture updates; the next trace's image loads come after them.
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

uint32_t ChcrtTracer::hintSetsAt(int width, int height) const {
    const uint64_t bytesPerSet = 4 * uint64_t(width) * uint64_t(height) * kHintKinds;
    return uint32_t(std::clamp<uint64_t>(options_.hintMemoryBytes / bytesPerSet, 1, UINT32_MAX));
}

RaySetHints ChcrtTracer::setHints(const TraceRequest& request, int width, int height) const {
    RaySetHints hints;
    if (!usesHints(request)) return hints;
    const uint64_t kind = rayKind(request) << 32, own = hintKey(request, hintSetsAt(width, height));
    hints.set = false;
    for (auto it = hintStore_->lower_bound(kind); it != hintStore_->end() && (it->first >> 32) == (kind >> 32); ++it) {
        if (it->second.extent != TextureExtent{width, height}) continue;
        ++hints.ofKind;
        hints.set = hints.set || it->first == own;
    }
    return hints;
}

GLuint ChcrtTracer::hintImageFor(const TraceRequest& request, int width, int height, bool& fresh) {
    fresh = false;
    if (!usesHints(request)) return 0;
    hintSets_ = hintSetsAt(width, height);
    HintImage& image = (*hintStore_)[hintKey(request, hintSets_)];
    GlTexture& hint = image.texture;
    // Hints of slots replaced since are dropped by the hint pass (shaders/culling/hint_leaf.glsl), which compares
    // 32-bit epochs: an image that old is emptied.
    const uint64_t epoch = source_->contentEpoch();
    if (image.extent != TextureExtent{width, height}) {
        hint = createTexture2D(width, height, GL_R32UI);
        image.extent = {width, height};
    } else if (epoch - image.epoch < (uint64_t(1) << 31)) return hint.id();
    const GLuint none = CHCRT_NO_HIT_ID;
    glClearTexImage(hint.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    image.epoch = epoch;
    image.passed = false;
    fresh = true;
    return hint.id();
}

HintSlots ChcrtTracer::validateHints(const TraceRequest& request) {
    HintImage& image = (*hintStore_)[hintKey(request, hintSets_)];
    const uint64_t epoch = source_->contentEpoch();
    const HintSlots slots{source_->hintSlotNodes(), uint32_t(image.epoch), uint32_t(epoch - image.epoch)};
    image.droppedStale = epoch != image.epoch;
    image.epoch = epoch;
    return slots;
}

bool ChcrtTracer::hintPassDue(const TraceRequest& request) {
    HintPassRecord& record = (*hintPassRecords_)[adaptiveKey(request)];
    if (record.misses < kHintPassMisses) return true;
    const uint32_t doublings = std::min(record.misses - kHintPassMisses, kHintPassRetryDoublings);
    return ++record.skipped >= (uint64_t(options_.hintPassRetryInterval) << doublings);
}

void ChcrtTracer::finishHintPass(const TraceRequest& request, int width, int height) {
    last_.hintRaysLeft = hintPass_->raysLeft();
    HintPassRecord& record = (*hintPassRecords_)[adaptiveKey(request)];
    record.skipped = 0;
    // The first pass over a ray set's hints is no sample of what they leave: they come from the set's first trace,
    // which may have been a renderer's warm-up under a one-pixel scissor (Renderer::warmUp) or a cold trace. Nor is
    // a pass that dropped the hints of replaced cache slots (out of core, while the working set changes).
    HintImage& image = (*hintStore_)[hintKey(request, hintSets_)];
    if (!image.passed || image.droppedStale) {
        image.passed = true;
        return;
    }
    const bool tooMany = double(last_.hintRaysLeft) > options_.hintPassMaxLeft * double(width) * double(height);
    record.misses = tooMany ? record.misses + 1 : 0;
    hintPassLeftTooMany_ = tooMany;
}

GLuint ChcrtTracer::maskFramebufferFor(GLuint depthTexture) {
    auto it = framebuffers_.find(depthTexture);
    if (it == framebuffers_.end()) {
        it = framebuffers_.emplace(depthTexture, createFramebuffer(nullptr, 0, depthTexture)).first;
    }
    return it->second.id();
}

GLuint ChcrtTracer::acquireQuery() {
    if (queriesInUse_ == queryPool_.size()) {
        const size_t grow = std::max<size_t>(64, queryPool_.size());
        queryPool_.resize(queryPool_.size() + grow);
        glCreateQueries(GL_SAMPLES_PASSED, GLsizei(grow), queryPool_.data() + queriesInUse_);
    }
    return queryPool_[queriesInUse_++];
}

void ChcrtTracer::setMode(Mode mode, bool anyHit) {
    if (mode == mode_) return;
    mode_ = mode;
    if (mode == Mode::Query) {
        // §4.1: depth(entry) <= depth(nearest t so far) passes; queries never write depth.
        glDepthFunc(GL_LEQUAL);
        glDepthMask(GL_FALSE);
        queryProgram(anyHit).use();
    } else {
        // Subtree passes write depth(new nearest t), which only decreases.
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
        subtreeProgram(anyHit).use();
    }
}

int ChcrtTracer::setQueryBoxes(const ShaderProgram& program, const uint32_t* nodes, int count) const {
    // §5.1 tighter bounds: the children's boxes are inside the node's box, and traversal enters the node only to
    // test them, so a ray that can reach a hit under the node passes one of them: still conservative.
    std::array<glm::vec4, CHCRT_CULLING_MAX_QUERY_BOXES> mins{}, maxs{};
    int boxes = 0;
    for (int i = 0; i < count; ++i) {
        const CullingHierarchy::Node& node = hierarchy_.nodes[nodes[i]];
        if (options_.tighterBounds) {
            for (uint32_t c = 0; c < node.tightCount; ++c) {
                mins[size_t(boxes)] = glm::vec4(node.tightMin[c], 0.0f);
                maxs[size_t(boxes++)] = glm::vec4(node.tightMax[c], 0.0f);
            }
        } else {
            mins[size_t(boxes)] = glm::vec4(node.boxMin, 0.0f);
            maxs[size_t(boxes++)] = glm::vec4(node.boxMax, 0.0f);
        }
    }
    program.setArray("boxMin", mins.data(), boxes);
    program.setArray("boxMax", maxs.data(), boxes);
    program.set("boxCount", boxes);
    return boxes;
}

void ChcrtTracer::beginQueryDraw(const Tile& tile, bool anyHit) {
    setMode(Mode::Query, anyHit);
    if (anyHit) readPixelsOf(tile); // any-hit queries read the hit buffer (finished rays never pass)
    glViewport(tile.x, tile.y, tile.width, tile.height);
}

bool ChcrtTracer::mayHit(const QueryPair& pair) const {
    if (!rayExtent_) return true;
    // The boxes the query would test (setQueryBoxes): with tighter bounds the children's, inside the node's.
    const CullingHierarchy::Node& node = hierarchy_.nodes[pair.bvhNode];
    if (options_.tighterBounds && node.tightCount > 0) {
        return rayExtent_->mayReach(pair.tile, node.tightMin, node.tightMax, int(node.tightCount));
    }
    return rayExtent_->mayReach(pair.tile, &node.boxMin, &node.boxMax, 1);
}

bool ChcrtTracer::issueQuery(int32_t pairIndex, VisibilityState& state, bool lazy, bool anyHit) {
    QueryPair& pair = state.pair(pairIndex);
    if (!mayHit(pair)) {
        // No ray of the tile reaches the boxes: the query would count 0 (lazy or not, the pair is invisible).
        pair.visible = false;
        ++last_.queriesSkippedExtent;
        return false;
    }
    if (batched_) {
        batch_.push_back(PendingQuery{pairIndex, 0, lazy});
        return true;
    }
    beginQueryDraw(pair.tile, anyHit);
    const uint32_t node = pair.bvhNode;
    setQueryBoxes(queryProgram(anyHit), &node, 1);
    const GLuint query = acquireQuery();
    glBeginQuery(GL_SAMPLES_PASSED, query);
    drawFullscreenTriangle();
    glEndQuery(GL_SAMPLES_PASSED);
    queue_.push_back(PendingQuery{pairIndex, query, lazy});
    ++last_.queries;
    ++last_.queriesSingle;
    return true;
}

void ChcrtTracer::issueMultiQuery(const std::vector<int32_t>& pairs, const VisibilityState& state, bool anyHit) {
    // §5.1 multi-query: one pass over the tile tests the boxes of several previously invisible pairs; a ray
    // passes when it could hit any of them. No passing ray: all stay invisible in one pass.
    const Tile tile = state.pair(pairs.front()).tile;
    beginQueryDraw(tile, anyHit);
    std::array<uint32_t, CHCRT_CULLING_MAX_QUERY_BOXES> nodes{};
    for (size_t i = 0; i < pairs.size(); ++i) nodes[i] = state.pair(pairs[i]).bvhNode;
    setQueryBoxes(queryProgram(anyHit), nodes.data(), int(pairs.size()));
    const GLuint query = acquireQuery();
    glBeginQuery(GL_SAMPLES_PASSED, query);
    drawFullscreenTriangle();
    glEndQuery(GL_SAMPLES_PASSED);
    PendingQuery pending{-1, query, false, uint32_t(multiGroups_.size()), uint32_t(pairs.size())};
    multiGroups_.insert(multiGroups_.end(), pairs.begin(), pairs.end());
    queue_.push_back(pending);
    ++last_.queries;
    ++last_.queriesMulti;
}

void ChcrtTracer::schedule(const VisibilityState& state, int32_t pairIndex, std::vector<Scheduled>& out) const {
    const QueryPair& pair = state.pair(pairIndex);
    const CullingHierarchy::Node& node = hierarchy_.nodes[pair.bvhNode];
    out.push_back(Scheduled{pair.tile, node.subtree, squaredDistanceToBox(eye_, node.boxMin, node.boxMax),
                            SubtreeSource::kNotResident});
}

void ChcrtTracer::readPixelsOf(const Tile& tile) {
    // Image stores of earlier passes must be visible to a pass reading the same pixels. Passes over disjoint
    // tiles need no barrier, and skipping it matters: a barrier ends a batch of draws on some drivers
    // (llvmpipe finishes all work on it), which serialises the small per-tile draws on one core.
    for (const Tile& d : dirtyTiles_) {
        const bool disjoint = tile.x >= d.x + d.width || d.x >= tile.x + tile.width || tile.y >= d.y + d.height ||
                              d.y >= tile.y + tile.height;
        if (!disjoint) {
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            dirtyTiles_.clear();
            ++last_.barriers;
            return;
        }
    }
}

void ChcrtTracer::intersect(std::vector<Scheduled>& work, bool anyHit) {
    if (work.empty()) return;
    if (intersectsByCells()) {
        if (compactedRounds_) hintPass_->bindDispatch(); // the queries' dispatches may have bound another
        intersectCells(work, anyHit, *traceRays_, *traceHits_, !cellRoundRun_, compactedRounds_, traceWidth_,
                       traceHeight_);
        cellRoundRun_ = true;
        return;
    }
    // §5.2 by-tile sorting: subtrees of the same tile share shader calls, nearest first within the tile.
    std::sort(work.begin(), work.end(), [](const Scheduled& a, const Scheduled& b) {
        if (a.tile.y != b.tile.y) return a.tile.y < b.tile.y;
        if (a.tile.x != b.tile.x) return a.tile.x < b.tile.x;
        if (a.tile.width != b.tile.width) return a.tile.width < b.tile.width;
        if (a.tile.height != b.tile.height) return a.tile.height < b.tile.height;
        if (a.distance != b.distance) return a.distance < b.distance;
        return a.subtree < b.subtree;
    });
    residentRounds(work, [&](const std::vector<Scheduled>& resident) {
        beginPassTimer();
        drawBatches(resident, anyHit);
        endPassTimer();
    });
}

void ChcrtTracer::beginPassTimer(bool hintPass) {
    if (!timingPasses_) return;
    if (passTimersUsed_ == passTimers_.size()) passTimers_.push_back({std::make_unique<GpuTimer>()});
    PassTimer& pass = passTimers_[passTimersUsed_];
    pass.hintPass = hintPass;
    pass.timer->begin();
}

void ChcrtTracer::endPassTimer() {
    if (!timingPasses_) return;
    passTimers_[passTimersUsed_++].timer->end();
}

void ChcrtTracer::readPassTimers() {
    if (!timingPasses_) return;
    last_.passTimedTraces = 1;
    for (size_t i = 0; i < passTimersUsed_; ++i) {
        const double ms = passTimers_[i].timer->milliseconds();
        last_.subtreePassMs += ms;
        if (passTimers_[i].hintPass) last_.hintPassMs += ms;
    }
    passTimersUsed_ = 0;
}

void ChcrtTracer::residentRounds(std::vector<Scheduled>& work,
                                 const std::function<void(const std::vector<Scheduled>&)>& draw) {
    // §5.4: resident subtrees first (keeping the given order among them), then the rest in later rounds.
    // The hit rule makes the result independent of the order in which subtrees are intersected.
    std::vector<uint32_t> ids, roots;
    std::unordered_map<uint32_t, uint32_t> rootOf;   // subtree -> GPU root of this round
    std::vector<std::pair<float, uint32_t>> nearest; // (scheduled distance, subtree)
    std::vector<Scheduled> resident, rest;
    while (!work.empty()) {
        // Each subtree once, nearest to the camera first: a source that cannot take them all (slots, or an
        // upload budget) makes the near ones resident, which fill the depth buffer first.
        nearest.clear();
        for (const Scheduled& s : work) nearest.emplace_back(s.distance, s.subtree);
        std::sort(nearest.begin(), nearest.end());
        ids.clear();
        rootOf.clear();
        for (const auto& [distance, subtree] : nearest) {
            if (rootOf.emplace(subtree, SubtreeSource::kNotResident).second) ids.push_back(subtree);
        }
        roots.assign(ids.size(), SubtreeSource::kNotResident);
        source_->acquire(ids, roots);
        ++last_.residencyRounds;
        for (size_t i = 0; i < ids.size(); ++i) rootOf[ids[i]] = roots[i];
        resident.clear();
        rest.clear();
        for (Scheduled s : work) {
            s.gpuRoot = rootOf.at(s.subtree);
            (s.gpuRoot == SubtreeSource::kNotResident ? rest : resident).push_back(s);
        }
        if (resident.empty() && source_->uploadBudgetExhausted()) {
            last_.subtreesPostponed += rest.size(); // a later trace intersects them (Phase 1: still visible)
            break;
        }
        if (resident.empty()) {
            throw InputError("chcrt: the subtree source could not make any of " + std::to_string(ids.size()) +
                             " scheduled subtrees resident (GPU subtree budget too small for one subtree)");
        }
        draw(resident);
        work.swap(rest);
    }
    work.clear();
}

void ChcrtTracer::drawBatches(const std::vector<Scheduled>& work, bool anyHit) {
    // Tiles with more subtrees than a batch holds take several calls; issuing them round by round (the first
    // batch of every tile, then the second, ...) keeps consecutive draws on different tiles (no barrier).
    std::vector<std::pair<size_t, size_t>> tileRanges; // [begin, end) per tile
    for (size_t i = 0; i < work.size();) {
        size_t end = i;
        while (end < work.size() && work[end].tile == work[i].tile) ++end;
        tileRanges.emplace_back(i, end);
        i = end;
    }
    setMode(Mode::Intersect, anyHit);
    if (options_.bindSubtreeResources) options_.bindSubtreeResources();
    const ShaderProgram& batchProgram = subtreeProgram(anyHit);
    // Batches of one subtree use the variant without the batch loop (not with debug images).
    const ShaderProgram& singleProgram =
        debugKind_ == ChcrtDebugImage::None ? singleSubtreePrograms_[anyHit] : batchProgram;
    const ShaderProgram* current = &batchProgram;
    std::array<glm::uvec4, CHCRT_CULLING_MAX_BATCH / 4> roots{}, ids{};
    const size_t batch = size_t(options_.batchSize);
    for (size_t round = 0;; ++round) {
        bool any = false;
        for (const auto& [tileBegin, tileEnd] : tileRanges) {
            const size_t begin = tileBegin + round * batch;
            if (begin >= tileEnd) continue;
            any = true;
            const size_t end = std::min(tileEnd, begin + batch);
            roots.fill(glm::uvec4(0u));
            ids.fill(glm::uvec4(0u));
            for (size_t k = begin; k < end; ++k) {
                roots[(k - begin) / 4][int((k - begin) % 4)] = work[k].gpuRoot;
                ids[(k - begin) / 4][int((k - begin) % 4)] = work[k].subtree;
            }
            const Tile& tile = work[begin].tile;
            readPixelsOf(tile);
            const ShaderProgram& program = end - begin == 1 ? singleProgram : batchProgram;
            if (&program != current) {
                program.use();
                current = &program;
            }
            program.setArray("subtreeRoots", roots.data(), int(roots.size()));
            if (debugKind_ == ChcrtDebugImage::Subtrees) program.setArray("subtreeIds", ids.data(), int(ids.size()));
            program.set("subtreeCount", int(end - begin));
            glViewport(tile.x, tile.y, tile.width, tile.height);
            drawFullscreenTriangle();
            dirtyTiles_.push_back(tile);
            last_.subtreesScheduled += end - begin;
            ++last_.shaderCalls;
        }
        if (!any) break;
    }
    if (current != &batchProgram) batchProgram.use(); // setMode's program stays current
}

void ChcrtTracer::testBatch(VisibilityState& state, std::vector<Scheduled>& newlyVisible, bool anyHit) {
    std::vector<PendingQuery> round;
    round.swap(batch_);
    std::vector<BatchedQueries::Query> queries(round.size());
    for (size_t i = 0; i < round.size(); ++i) {
        const QueryPair& pair = state.pair(round[i].pair);
        const CullingHierarchy::Node& node = hierarchy_.nodes[pair.bvhNode];
        BatchedQueries::Query& q = queries[i];
        q.tile = pair.tile;
        // The boxes a GL query would test (setQueryBoxes).
        if (options_.tighterBounds && node.tightCount > 0) {
            q.boxCount = node.tightCount;
            for (uint32_t c = 0; c < node.tightCount; ++c) {
                q.boxMin[c] = node.tightMin[c];
                q.boxMax[c] = node.tightMax[c];
            }
        } else {
            q.boxMin[0] = node.boxMin;
            q.boxMax[0] = node.boxMax;
        }
    }
    std::vector<uint32_t> counts;
    batched_->test(queries, anyHit, options_.visibleThreshold, debugKind_ == ChcrtDebugImage::Overdraw, counts);
    dirtyTiles_.clear(); // the test's barrier ordered every earlier store before later passes too
    mode_ = Mode::None;  // the dispatch changed the current program
    ++last_.batchedRounds;
    last_.pairsTestedBatched += round.size();
    for (size_t i = 0; i < round.size(); ++i) {
        processResult(state, round[i], counts[i], newlyVisible, anyHit);
    }
    // The round's newly visible subtrees now: their hits bound the next round's tests.
    intersect(newlyVisible, anyHit);
}

void ChcrtTracer::processResult(VisibilityState& state, const PendingQuery& pending, GLuint samples,
                                std::vector<Scheduled>& newlyVisible, bool anyHit) {
    const bool visible = samples > options_.visibleThreshold;
    if (pending.pair < 0) {
        // A multi-query: every pair it covered stays invisible, or (some ray passed) each is queried on its own,
        // as we do not know which became visible (§5.1).
        if (!visible) return;
        ++last_.queriesMultiFailed;
        for (uint32_t i = 0; i < pending.groupCount; ++i) {
            issueQuery(multiGroups_[pending.groupBegin + i], state, false, anyHit);
        }
        return;
    }
    QueryPair& pair = state.pair(pending.pair);
    if (pending.lazy) {
        // Already intersected in Phase 1; an invisible result only moves the pair to the invisible front.
        pair.visible = visible;
        return;
    }
    if (!visible) {
        pair.visible = false;
        return;
    }
    const PairSplit split = decideSplit(pair.tile, pair.bvhNode, hierarchy_, state.width(), state.height(),
                                        options_.pairs);
    if (split == PairSplit::None) {
        // Termination reached (§5.2): the pair joins the visible front and its subtree is intersected.
        pair.visible = true;
        ++last_.pairsNewlyVisible;
        schedule(state, pending.pair, newlyVisible);
        if (int(newlyVisible.size()) > options_.flushThreshold) intersect(newlyVisible, anyHit);
        return;
    }
    std::array<int32_t, 4> children;
    const int count = subdividePair(state, pending.pair, split, children);
    for (int i = 0; i < count; ++i) {
        if (issueQuery(children[size_t(i)], state, false, anyHit)) ++last_.queriesTraversal;
    }
}

int ChcrtTracer::subdividePair(VisibilityState& state, int32_t pairIndex, PairSplit split,
                               std::array<int32_t, 4>& children) const {
    const QueryPair& pair = state.pair(pairIndex);
    std::array<Tile, 4> tiles;
    std::array<uint32_t, 4> nodes;
    int count = 0;
    if (split == PairSplit::Object) {
        const uint32_t left = hierarchy_.nodes[pair.bvhNode].firstChild;
        tiles = {pair.tile, pair.tile, Tile{}, Tile{}};
        nodes = {left, left + 1, 0, 0};
        count = 2;
    } else {
        count = splitTile(pair.tile, options_.pairs.minTileSize, tiles);
        nodes.fill(pair.bvhNode);
    }
    state.subdivide(pairIndex, tiles.data(), nodes.data(), count, children.data(), options_.requeryInterval);
    return count;
}

void ChcrtTracer::trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                        int height, TraceStats& stats) {
    last_ = ChcrtStats{};
    last_.traces = 1;
    last_.raysTraced = uint64_t(width) * uint64_t(height);
    // Adaptive choice (adaptive_choice.h): per ray kind, the cheapest measured arm — one pure pass, or culling at
    // the configured height or one of adaptiveHeights; losers are re-measured within the probe budget. A selected
    // debug image turns it off, so that the image shows the culling passes (for Cost: what culling costs per pixel,
    // also where the adaptive choice would trace with one pure pass).
    const bool canFallBack = options_.adaptive && fullTracer_ != nullptr && debugKind_ == ChcrtDebugImage::None;
    // A light sweep's shadow sets share lists made once per sweep, which a one-set probe of another height cannot
    // weigh (ChcrtOptions::adaptiveHeights): pure pass or the configured height.
    const uint32_t arms = 2 + uint32_t(bvh_ && !sweepListsFor(request) ? heightArms_.size() : 0);
    AdaptiveChoice& choice =
        adaptive_.try_emplace(adaptiveKey(request), arms, options_.adaptiveProbeInterval, options_.adaptiveProbeBudget)
            .first->second;
    const uint32_t arm = canFallBack ? choice.next(uint32_t(request.sampleIndex), setHints(request, width, height)) : 1;
    const auto timed = [this](uint32_t ran, double ms) {
        return options_.adaptiveTiming ? options_.adaptiveTiming(ran, ms) : ms;
    };
    const auto start = Clock::now();
    if (arm != AdaptiveChoice::kPureArm) {
        ChcrtTracer& tracer = armTracer(arm);
        const bool warm = tracer.traceOwn(request, rays, hits, width, height);
        if (&tracer != this) last_ = tracer.last_;
        last_.traces = 1;
        last_.raysTraced = uint64_t(width) * uint64_t(height);
        last_.heightSum = tracer.hierarchy_.maxSubtreeHeight;
        // The culling traces end with glFinish. A debug trace's time includes the instrumentation: not a sample
        // of culling's cost for the choice.
        if (canFallBack) choice.report(arm, timed(arm, millisecondsSince(start)), warm, uint32_t(request.sampleIndex));
        stats.passes += 1 + last_.shaderCalls + last_.queries;
    } else {
        fullTracer_->trace(request, rays, hits, width, height, stats);
        glFinish();
        const double ms = millisecondsSince(start);
        choice.report(arm, timed(arm, ms), true, uint32_t(request.sampleIndex));
        last_.fallbackTraces = 1;
        last_.fallbackMs = ms;
    }
    total_ += last_;
}

ChcrtTracer& ChcrtTracer::armTracer(uint32_t arm) {
    if (arm <= 1 || !bvh_) return *this;
    std::unique_ptr<ChcrtTracer>& tracer = heightArms_[arm - 2];
    if (!tracer) {
        ChcrtOptions options = options_;
        options.partition.maxSubtreeHeight = options_.adaptiveHeights[arm - 2];
        options.adaptive = false;
        options.adaptiveHeights.clear();
        tracer.reset(new ChcrtTracer(*bvh_, options, name_, programCache_)); // a private constructor
        tracer->hintStore_ = hintStore_;
        tracer->hintPassRecords_ = hintPassRecords_;
        tracer->surfaceFrames_ = surfaceFrames_;
    }
    return *tracer;
}

bool ChcrtTracer::traceOwn(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                           int height) {
    last_ = ChcrtStats{};
    hintPassLeftTooMany_ = false;
    ++tracesRun_;
    const uint32_t timerInterval = options_.passTimerInterval;
    timingPasses_ = timerInterval != 0 && (tracesRun_ - 1) % timerInterval == 0;
    if (rayExtent_) rayExtent_->resetDecisions();
    bool warm = false;
    switch (options_.queries) {
    case ChcrtQueries::BoundsOnly:
        warm = sharesLightSweep(request, width, height) ? traceSharedLists(request, rays, hits, width, height)
                                                        : traceBounded(request, rays, hits, width, height);
        break;
    case ChcrtQueries::BoundsGpu: warm = traceBoundedGpu(request, rays, hits, width, height); break;
    default: warm = traceCulled(request, rays, hits, width, height); break;
    }
    if (rayExtent_ && options_.queries != ChcrtQueries::BoundsGpu) { // bounds-gpu counts its tests on the GPU
        const RayBoundsGrid::ShapeDecisions& d = rayExtent_->decisions();
        last_.boundsCulledPieces = d.pieces;
        last_.boundsCulledFrustum = d.frustum;
        last_.boundsReached = d.reached;
    }
    // A trace whose hint pass left too many rays is no sample either: the rule stops that pass (hintPassDue), so it
    // is not what this configuration costs from then on, and counted it kept out a culling that wins (the plant's
    // near AO rays: two such traces at 1.45 / 1.09x of the pure pass, then ~170 pure traces; docs/benchmarks.md,
    // 2026-12-07).
    return warm && !hintPassLeftTooMany_;
}

bool ChcrtTracer::traceCulled(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                              int height) {
    // A trace that failed part way (an out-of-core read error) may have left pairs queued: they index fronts that
    // were dropped since (resetVisibility), so every trace starts with none.
    queriesInUse_ = 0;
    queue_.clear();
    multiGroups_.clear();
    batch_.clear();
    eye_ = request.camera.eye;
    const bool anyHit = request.anyHit;
    VisibilityState& state = stateFor(request, width, height);
    const bool warm = state.frame() > 0;
    auto start = Clock::now();
    traceRays_ = &rays, traceHits_ = &hits, traceWidth_ = width, traceHeight_ = height, cellRoundRun_ = false;
    compactedRounds_ = false;
    beginTrace(rays, hits, width, height, !intersectsByCells()); // batched tests read the hit image, not depth
    // Hit hints out of core (culling/README.md "Hit hints out of core"): the hint pass visits every ray's hinted leaf
    // before anything else, so the reduction below leaves out the any-hit rays it finished, and Phase 1 and the
    // queries skip what only they could reach. Visits happen there only, before this trace replaces any cache slot;
    // the cell passes record the leaves of new hits.
    bool hintPass = false;
    if (hintsAvailable()) {
        bool unusedWarm = false; // no adaptive choice out of core
        hintPass = startHints(request, rays, width, height, unusedWarm, anyHit);
        cells_->setHintsVisited(true);
    }
    // Where the rays can reach (culling/ray_bounds_grid.h), for skipping pairs out of reach in every phase. Primary
    // rays reach the whole view until they hit: before Phase 1 the renderer's are bounded from its camera (no
    // reduction), others are not bounded.
    if (rayExtent_) {
        if (request.rayType == RayType::Primary && !request.bounceShadow && !hintPass) {
            if (!boundFromCamera(request, width, height)) rayExtent_->forget();
        } else {
            updateBounds(rays, hintPass ? hits.hit.id() : 0, anyHit, width, height,
                         hintPass && anyHit ? hintPass_->cellMarks() : 0);
        }
    }
    // After the hint pass every round of any-hit rays traces only the rays it left, in one compacted dispatch (as in
    // core: a pass over all rays makes each SIMD group wait for its slowest ray in every loop).
    compactedRounds_ = hintPass && anyHit;

    // Phase 1 (Algorithm 1, lines 1-4): intersect the previously visible leaves, initialising depth.
    std::vector<int32_t> visibleLeaves, invisibleLeaves;
    state.collectLeaves(visibleLeaves, invisibleLeaves);
    std::vector<Scheduled> work;
    for (int32_t p : visibleLeaves) {
        if (mayHit(state.pair(p))) schedule(state, p, work);
        else ++last_.leavesSkippedExtent; // no hit possible; its lazy re-query (Phase 2) finds it invisible
    }
    intersect(work, anyHit);
    glFinish(); // phase timing (the queries of Phase 2 depend on this depth anyway)
    last_.phase1Ms = millisecondsSince(start);

    // Phase 2 (lines 5-11): query the invisible front (multi-queries over pairs of one tile, §5.1); re-query
    // visible leaves lazily every n frames. The grid now ends every ray at the hit Phase 1 found (any-hit rays
    // that hit drop out), so it leaves out more pairs without a query.
    start = Clock::now();
    if (rayExtent_) {
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        dirtyTiles_.clear();
        updateBounds(rays, hits.hit.id(), anyHit, width, height);
    }
    last_.queriesInvisible = invisibleLeaves.size();
    // Invisible pairs out of their rays' reach stay invisible without a query.
    std::erase_if(invisibleLeaves, [&](int32_t p) {
        if (mayHit(state.pair(p))) return false;
        ++last_.queriesSkippedExtent;
        return true;
    });
    if (options_.multiQueryPairs > 1 && !batched_) { // batched: every pair has its own count anyway
        std::stable_sort(invisibleLeaves.begin(), invisibleLeaves.end(), [&](int32_t a, int32_t b) {
            const Tile &ta = state.pair(a).tile, &tb = state.pair(b).tile;
            return std::tie(ta.y, ta.x, ta.width, ta.height) < std::tie(tb.y, tb.x, tb.width, tb.height);
        });
        std::vector<int32_t> group;
        for (size_t i = 0; i < invisibleLeaves.size();) {
            group.clear();
            const Tile tile = state.pair(invisibleLeaves[i]).tile;
            while (i < invisibleLeaves.size() && state.pair(invisibleLeaves[i]).tile == tile &&
                   int(group.size()) < options_.multiQueryPairs) {
                group.push_back(invisibleLeaves[i++]);
            }
            if (group.size() == 1) issueQuery(group.front(), state, false, anyHit);
            else issueMultiQuery(group, state, anyHit);
        }
    } else {
        for (int32_t p : invisibleLeaves) issueQuery(p, state, false, anyHit);
    }
    const uint64_t n = options_.requeryInterval;
    for (int32_t p : visibleLeaves) {
        if ((state.frame() + state.pair(p).requeryPhase) % n == 0) {
            issueQuery(p, state, true, anyHit);
            ++last_.queriesLazy;
        }
    }
    last_.phase2Ms = millisecondsSince(start);

    // Phase 3 (lines 12-34): fetch results in order; subdivide pairs that turned visible, intersect newly
    // visible terminal pairs in groups of more than m.
    start = Clock::now();
    std::vector<Scheduled> newlyVisible;
    while (!batch_.empty()) testBatch(state, newlyVisible, anyHit);
    while (!queue_.empty()) {
        const PendingQuery pending = queue_.front();
        queue_.pop_front();
        GLuint samples = 0;
        glGetQueryObjectuiv(pending.query, GL_QUERY_RESULT, &samples);
        processResult(state, pending, samples, newlyVisible, anyHit);
    }
    intersect(newlyVisible, anyHit);
    endTrace(state, width, height);
    if (hintPass) finishHintPass(request, width, height);
    last_.phase3Ms = millisecondsSince(start);
    return warm;
}

void ChcrtTracer::beginTrace(const RayTextures& rays, HitTargets& hits, int width, int height, bool hitDepth,
                             bool clearHits) {
    // The framebuffers over the frame targets' depth textures are kept by texture name; the renderer makes its
    // targets again when its size changes, and a deleted texture's name may be given to a new one.
    if (width != framebufferWidth_ || height != framebufferHeight_) {
        framebuffers_.clear();
        framebufferWidth_ = width;
        framebufferHeight_ = height;
    }
    if (debugKind_ != ChcrtDebugImage::None) {
        ensureDebugTexture(width, height);
        glBindImageTexture(CHCRT_CULLING_IMAGE_DEBUG, debugTexture_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
        glBindImageTexture(CHCRT_CULLING_IMAGE_HIT_TRIANGLE, hitTriangleTexture_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                           GL_R32UI);
    }
    // Initialise: all misses and, where the passes use it, depth 1 (= no hit yet; queries test a ray's own tmax in the
    // shader; skipping the depth where it is unused saves ~4 % of a culled shadow trace). Clears, not a full-screen
    // pass: on llvmpipe an initialising pass cost ~25% of a whole trace (culling/README.md).
    const GLuint framebuffer = framebufferFor(hits);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width, height);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    if (clearHits) clearHitsToMisses(hits);
    cellPassWritesAll_ = !clearHits;
    const GLfloat farDepth = 1.0f;
    if (hitDepth) glClearNamedFramebufferfv(framebuffer, GL_DEPTH, 0, &farDepth);
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, rays.origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, rays.direction.id());
    glBindImageTexture(CHCRT_CULLING_IMAGE_HIT, hits.hit.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
    mode_ = Mode::None;
    // The clear is a texture update; shader image loads after it need this barrier (once per trace).
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    dirtyTiles_.clear();
}

void ChcrtTracer::endTrace(VisibilityState& state, int width, int height) {
    last_.pairsPulledUp = uint64_t(state.pullUpInvisibility());
    state.advanceFrame();
    std::vector<int32_t> visibleLeaves, invisibleLeaves;
    state.collectLeaves(visibleLeaves, invisibleLeaves);
    last_.pairsVisible = visibleLeaves.size();
    last_.pairsInvisible = invisibleLeaves.size();
    finishTrace(width, height);
}

void ChcrtTracer::writeBoundsImage(int width, int height) {
    std::vector<uint32_t> image(size_t(width) * size_t(height), 0u);
    if (rayExtent_ && rayExtent_->known()) {
        const int cell = rayExtent_->options().cellSize;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                const RayBoundsGrid::CellBoxes& c = rayExtent_->cell(x / cell, y / cell);
                image[size_t(y) * size_t(width) + size_t(x)] =
                    c.state == 0 ? 0u
                    : c.state == 2 || !std::isfinite(c.segmentEnd)
                        ? kUnboundedCell
                        : std::bit_cast<uint32_t>(std::max(c.segmentEnd, 1.0e-30f));
            }
        }
    }
    glTextureSubImage2D(debugTexture_.id(), 0, 0, 0, width, height, GL_RED_INTEGER, GL_UNSIGNED_INT, image.data());
}

void ChcrtTracer::finishTrace(int width, int height) {
    // Hand the hits to texture fetches and read-backs of the renderer; leave GL state as the pure tracer does.
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    dirtyTiles_.clear();
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
    glViewport(0, 0, width, height);
    glFinish();
    readPassTimers();
    if (debugKind_ == ChcrtDebugImage::Bounds) writeBoundsImage(width, height);
    mode_ = Mode::None;
}

} // namespace chcrt
