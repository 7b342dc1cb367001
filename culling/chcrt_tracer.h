#pragma once
// CHC+RT (coherent hierarchical culling for ray tracing) as a Tracer: generalized occlusion queries over
// query pairs (screen tile × BVH node, §4.1-4.4) decide which termination subtrees (§5.2) each tile's rays
// must traverse; visibility fronts kept per ray set across frames (§4.5, §5.1, Algorithm 1) hide most of the
// query latency. Multi-queries and tighter bounds (§5.1) reduce query overdraw. The tracer sees the scene only
// through a CullingHierarchy (upper BVH, culling_hierarchy.h) and a SubtreeSource (where subtrees live on the
// GPU, §5.4), so an out-of-core cache can plug in. The conservative variant returns exactly the hits of pure
// BVH tracing (same subtree traversal code and hit rule; queries never cull a box a ray could hit at its
// current nearest t). An adaptive fallback traces a ray set with one pure full-screen pass when culling did
// not pay in recent frames (culling/README.md).
#include "culling/adaptive_choice.h"
#include "culling/culling_hierarchy.h"
#include "culling/query_pair_hierarchy.h"
#include "culling/cell_traversal.h"
#include "culling/gpu_cell_lists.h"
#include "culling/batched_queries.h"
#include "culling/hint_pass.h"
#include "culling/ray_bounds_grid.h"
#include "culling/subtree_source.h"
#include "culling/visibility_state.h"
#include "renderer/gl/context.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"
#include "renderer/render/tracer.h"

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace chcrt {

// How query pairs are decided (culling/README.md "Deciding pairs"). Both are exact.
enum class ChcrtQueries : uint8_t {
    Gl,         // §4.1 as in the paper: one GL occlusion query per pair (or §5.1 multi-query), per-tile subtree draws
    Batched,    // the same test, a round's pairs in one compute dispatch read back once (batched_queries.h); as Gl else
    BoundsOnly, // the ray bounds grid decides every pair (no queries) on the CPU; cell lists, one draw per round
    BoundsGpu,  // the same grid decides every cell's list on the GPU (gpu_cell_lists.h): no read-back; in core only
};
const char* toString(ChcrtQueries queries);
ChcrtQueries parseChcrtQueries(const std::string& name); // "gl" | "batched" | "bounds-only" | "bounds-gpu"; InputError otherwise
bool decidesByBounds(ChcrtQueries queries);              // BoundsOnly or BoundsGpu: cell lists, no GL queries

struct ChcrtOptions {
    // Defaults: the paper's configuration (GL queries, termination height 24); recommendedChcrtOptions() below is
    // the fastest measured one, which the `chcrt` methods start from.
    SubtreePartitionOptions partition;
    ChcrtQueries queries = ChcrtQueries::Gl;
    // Cells and pieces of the ray bounds grid (ray_bounds_grid.h): the only culling of BoundsOnly, the query
    // skipping of Gl with rayExtentCulling.
    RayBoundsOptions bounds;
    QueryPairOptions pairs;
    int batchSize = 24;              // §5.2: subtrees per shader call (<= CHCRT_CULLING_MAX_BATCH)
    int flushThreshold = 16;         // §5.1 m: intersect newly visible leaves once more than m have collected
    uint32_t requeryInterval = 3;    // §5.1 n: lazy re-query of visible leaves every n frames
    bool temporalCoherence = true;   // Gl, false: every trace starts from the root pair (§4.3-4.4 only)
    // BoundsOnly: intersect the previous trace's visible front first (Algorithm 1's Phase 1), then decide the rest
    // against its hits: two intersection rounds and two reductions. Off: the bounds before any hit decide every
    // pair from the root pair and one round intersects them; cell lists sorted by entry distance let a ray stop
    // at its first hit anyway. Off measured faster for every ray type (city near 256², culling/README.md).
    bool boundsPreviousFront = false;
    // BoundsOnly in core: a cell with more scheduled subtrees than this traverses the whole BVH from its root
    // instead (cell_traversal.h; 0 = never). Long lists come from rays of diverse directions (diffuse) whose
    // cell bounds meet much of the scene: each listed root costs a box test the pure traversal would mostly skip.
    uint32_t cellListLimit = 0;
    // BoundsOnly in core, and out of core with cellIntersect: hit hints for any-hit rays (culling/README.md "Hit
    // hints"; out of core: "Hit hints out of core"). Every shadow and AO ray set
    // keeps, per ray, the BVH leaf in which its previous trace found a hit; a ray visits that leaf before its cell's
    // list and is done when it hits there. Algorithm 1's Phase 1 (the previous visible front first) at the finest
    // granularity: one leaf per pixel.
    bool hitHints = false;
    // With hit hints: closest-hit ray sets (primary, diffuse) keep hints too — the leaf of each ray's nearest hit.
    // A hit in it does not finish the ray, but bounds it from the start: its traversal prunes against that hit, and
    // after the hint pass the ray bounds reduction ends the ray's segment there, so the cell lists hold only the
    // subtrees that could hold a nearer hit (culling/README.md "Hit hints").
    bool closestHitHints = false;
    // With hit hints: visit every ray's hinted leaf in a pass of its own before the ray bounds reduction, and
    // traverse the cell lists only for the rays left, compacted into one dispatch (hint_pass.h; culling/README.md
    // "The hint pass"). Off: the cell pass visits the hint first, in the same pass as the list. Same hits.
    bool hintPass = false;
    // The hint pass pays for itself where most rays end at their hints (city near, 256²: shadow rays, 5-10 % left,
    // traced 1.2x faster with it); where many rays have no hint (AO rays that escape: 52-64 % of the pixels left on
    // the near paths) the pass over all rays costs more than the compaction saves (Table 2's settings, 20 spp, frames
    // 0-7: chcrt-noadapt city AO 1.20x with it against 1.38x without, interior 1.18x either way, plant 0.77x against
    // 1.09x). A ray kind whose hint passes left more than this share of the pixels twice in a row visits its hints in
    // the cell pass instead, and tries the hint pass again after hintPassRetryInterval traces, twice as many after
    // each retry that left too many again (at most kHintPassRetryDoublings times: a retry of a losing pass costs
    // the trace 15-40 % on the near AO rays, 1-3 % of all traces at one retry in 16). Out of core the cell
    // passes visit no hints (a slot may change within a trace), so stopping the pass stops the hints; there the
    // recommended share is a half (app/methods.cpp).
    float hintPassMaxLeft = 0.25f;
    uint32_t hintPassRetryInterval = 16;
    // The GL timer queries of the statistics' pass times (ChcrtStats::subtreePassMs, hintPassMs) run on one trace in
    // this many (the first, then every passTimerInterval-th; ChcrtStats::estimatedPassMs scales them up): on
    // llvmpipe a timer query around a pass costs about 0.06 ms, 5-7 % of a culled shadow trace (city near, 256², 16
    // spp: 2.67-2.79x of pure BVH timed on every trace, 2.85-2.94x on none; culling/README.md "Statistics"), which
    // pure BVH's passes do not pay. Prime, so that the timed traces rotate through the sample indices of a frame of
    // 2^k samples. 1: every trace (exact sums); 0: none (the pass times stay 0).
    uint32_t passTimerInterval = 7;
    // Hit hints: the GPU memory their images may take (4 bytes per ray, per sample index and ray kind; a quarter each for
    // shadow, AO, bounce shadow and closest-hit rays). Sample indices beyond what it holds share images (ray kind,
    // sample index modulo the sets that fit): 1 GiB keeps every set apart up to 32 samples at 1920×1080, 8 at 3840×2160.
    uint64_t hintMemoryBytes = uint64_t(1) << 30;
    // BoundsOnly and BoundsGpu in core: shadow ray sets from one G-buffer to the light (TraceRequest::lightSweep: the
    // renderer's shadow rays) share one ray bounds grid — every cell's surface points swept to the light's box —, its
    // decisions and its cell lists, made by the first such set and traced by the rest (culling/README.md "Shared
    // shadow lists"). Same hits; off: every set reduces, decides and lists its own rays.
    bool shareShadowLists = false;
    // BoundsOnly in core: AO ray sets of one G-buffer (TraceRequest::hemisphereRays: the renderer's AO rays) are
    // bounded before any hit from one reduction of their surface points and tangent frames per G-buffer and each
    // set's sample, on the CPU (hemisphere_ray_bounds.h), instead of a reduction and its read-back per set
    // (culling/README.md "AO cells from the surface frames"). Not where the hint pass runs (its hits end segments).
    // Same hits; off: every set reduces its own rays.
    bool hemisphereBounds = false;
    // BoundsOnly and BoundsGpu: trace the cell lists in compute dispatches (a work group per cell) instead of fragment
    // passes; for GPUs whose fragment work runs on few units (docs/architecture.md). Same hits.
    bool computeCellPass = false;
    uint32_t visibleThreshold = 0;   // §7 aggressive culling: visible only when more rays pass (0 = exact)
    uint32_t seed = 1;               // of the randomized re-query phases
    bool tighterBounds = true;       // §5.1: query the node's two children's boxes instead of its own box
    int multiQueryPairs = 4;         // §5.1: previously invisible pairs of one tile per query (<= 1: off)
    // §5.2: 2-entry leaf cache in the subtree traversal (delayed leaf tests). Off by default: on llvmpipe it made
    // CHC+RT traces 1.17-1.30x slower than without (city 1M, culling/README.md); the paper's GPU gained ~30%.
    bool leafCache = false;
    // §5.2 batches traversed as one: the roots of a batch's subtrees share one traversal stack and loop instead of a
    // loop per subtree (our change for llvmpipe, culling/README.md "Merged batch traversal"; same hits). Not with the
    // leaf cache or Line Space traversal, which keep the loop per subtree.
    bool mergedBatch = true;
    // Batched queries: each intersection round's (tile, subtree) pairs are traced in one cell pass (the lists of
    // BoundsOnly, culling/cell_traversal.h: every cell of a pair's tile that its rays may reach lists the subtree)
    // instead of per-tile subtree passes of batchSize subtrees. Same pairs, same hits; one draw per round and
    // residency round instead of one per tile and batch (out of core, the 140M city's near path: ~200 AO passes).
    bool cellIntersect = false;
    // Gl queries: pairs out of reach of every ray of their tile are invisible without a query, and such visible
    // leaves are not intersected (our addition; culling/ray_bounds_grid.h). Exact. BoundsOnly always uses the grid.
    bool rayExtentCulling = true;
    // Adaptive choice (culling/README.md, adaptive_choice.h): per ray kind (primary, shadow, AO, diffuse, bounce
    // shadow), the arm with the lowest measured cost relative to the pure pass (median of its last five) — one pure
    // full-screen pass, or culling at the configured height or one of adaptiveHeights; losing arms are re-measured
    // after at least `adaptiveProbeInterval` traces, spaced so that their expected cost stays under
    // `adaptiveProbeBudget` of the trace time, and the probe ledger keeps the measured excess of all probes within it.
    // Needs a full-tree tracer (in core: the BVH); ignored without one.
    bool adaptive = true;
    uint32_t adaptiveProbeInterval = 8;
    // Half the 3 % that probing may cost: estimates come from different ray sets of the kind, and measured losses
    // ran at about twice the budget (city far shadow, 16 spp: 5 % with a 3 % budget; culling/README.md).
    double adaptiveProbeBudget = AdaptiveChoice::kAllowedProbeCost / 2;
    // More culling arms of the adaptive choice (in core only): the same options at these termination heights,
    // each with its own culling hierarchy, built on first use. Empty: the configured height only. Not for the shadow
    // rays of a light sweep with shareShadowLists: a probe of another height traces one ray set of a sweep, so it
    // either makes that height's lists for the sweep alone or uses per-set lists, and measures neither what the
    // height costs over a sweep nor what the running height costs (culling/README.md "Adaptive choice").
    std::vector<uint32_t> adaptiveHeights;
    // What the adaptive choice is told a trace of `arm` took (0 = the pure pass, 1 = this configuration, 2.. =
    // adaptiveHeights), given its measured wall time; empty = the wall time. Tests fix the times so that the
    // choices do not depend on the machine.
    std::function<double(uint32_t arm, double wallMs)> adaptiveTiming;
    // Extra defines of the subtree-intersection shader per any-hit (e.g. Line Space traversal, methods
    // chcrt+ls*: linespace/README.md) and the binding of what they read, called before subtree draws. Empty =
    // pure subtree traversal; a traversal named there (CHCRT_BVH_TRAVERSAL) turns the leaf cache and merged batches off.
    std::function<std::vector<ShaderDefine>(bool anyHit)> subtreeDefines;
    std::function<void()> bindSubtreeResources;
};

// The fastest exact configuration measured on the city, interior and plant near paths (culling/README.md): the ray
// bounds grid decides every pair, termination height 12, cells with more than 64 subtrees traverse the whole BVH,
// any-hit rays start from hit hints, and the adaptive choice also tries heights 10 and 14 per ray kind besides the
// pure pass. Where the grid decides and in which shader stage the cell lists are traced depends on the GL renderer
// (culling/README.md, "Stage and list decisions per renderer"), and this is the one place that chooses it:
//  - software rasterisers (renderer.software: llvmpipe): bounds-only, fragment cell passes. llvmpipe runs fragment
//    and compute work on the same CPU threads; there bounds-only measured faster than bounds-gpu for primary, shadow
//    and AO rays, and compute cell passes about as fast as fragment ones, pure BVH's compute pass slower than its
//    fragment pass (docs/benchmarks.md);
//  - every other renderer (GPUs): bounds-gpu with compute cell passes. Data-centre GPUs run fragment work on few
//    graphics-capable units (docs/architecture.md, "GPUs"), and the GPU deciding the lists leaves nothing to read
//    back until the trace ends. Not measured on a GPU yet.
// Same hits either way. The overload without traits is the software choice (what a caller without a GL context
// gets, e.g. the methods' defaults, before the renderer is known: app/method_tracers.cpp applies the renderer's).
ChcrtOptions recommendedChcrtOptions(const RendererTraits& renderer);
ChcrtOptions recommendedChcrtOptions();

// Pixels per ray bounds cell edge of the recommended configuration, in core and out of core: a quarter of the cells
// of 8-pixel ones to reduce, decide and list. On llvmpipe faster on every near row measured (city near at 256²,
// 2026-12-05: primary 1.21–1.26× → 1.41–1.51×, AO 1.37× → 1.47–1.48×, shadow unchanged; out of core, the compact
// 140M city's near path, 640×360: 179–182 → 153–167 ms per frame; culling/README.md "Parameters"). Not yet measured
// on a GPU.
inline constexpr int kRecommendedBoundsCellSize = 16;

// Counters of one trace (lastStats) or summed over traces (totalStats).
struct ChcrtStats {
    uint64_t traces = 0;
    uint64_t fallbackTraces = 0;     // traces done by the adaptive fallback (one pure pass, no culling)
    uint64_t heightSum = 0;          // termination heights of the culling traces (mean = heightSum / culled traces)
    uint64_t queries = 0;            // occlusion queries issued (all phases) = single + multi
    uint64_t queriesSingle = 0;      // queries of one pair
    uint64_t queriesMulti = 0;       // §5.1 multi-queries (several invisible pairs of one tile)
    uint64_t queriesMultiFailed = 0; // multi-queries that found rays (their pairs are re-queried singly)
    uint64_t queriesInvisible = 0;   // Phase 2: previously invisible pairs (single or inside multi-queries)
    uint64_t queriesLazy = 0;        // Phase 2: lazy re-queries of previously visible leaves
    uint64_t queriesTraversal = 0;   // Phase 3: children of pairs that turned visible
    uint64_t queriesSkippedExtent = 0; // pairs found invisible without a query: out of their rays' reach
    uint64_t leavesSkippedExtent = 0;  // Phase 1: visible leaves not intersected, out of their rays' reach
    uint64_t subtreesPostponed = 0;    // scheduled but left for a later trace by the source's upload budget
    uint64_t pairsDecidedBounds = 0;   // BoundsOnly: pairs decided by the ray bounds grid (no query)
    uint64_t pairsTestedBatched = 0;   // Batched: pairs tested by the batched dispatches (no GL query)
    uint64_t batchedRounds = 0;        // Batched: dispatches with their read-back (rounds of Phase 3)
    uint64_t boundsUpdates = 0;        // ray bounds reductions (a compute pass and a read-back each)
    uint64_t boundsFromCamera = 0;     // ray bounds of primary rays made from the camera instead (no reduction)
    uint64_t boundsFromHemisphere = 0; // hemisphereBounds: AO ray sets bounded from their surface frames instead
    uint64_t cellsDrawn = 0;           // BoundsOnly: cells drawn by the intersection rounds
    uint64_t cellEntries = 0;          // BoundsOnly: (cell, subtree) list entries traversed
    uint64_t cellsWholeTree = 0;       // BoundsOnly: cells over cellListLimit that traversed the whole BVH
    uint64_t hintPasses = 0;           // hintPass: traces that ran the hint pass
    uint64_t hintRaysLeft = 0;         // hintPass: active rays their hint did not finish (the compacted dispatches)
    uint64_t sharedListsMade = 0;      // shareShadowLists: traces that made their light sweep's grid and lists
    uint64_t sharedListsReused = 0;    // shareShadowLists: traces that traced lists an earlier ray set made
    // The ray bounds grid's tests of cells against boxes (on the CPU in BoundsOnly and Gl with ray extent culling, in
    // the cell-list compute pass in BoundsGpu): culled by the pieces (tested first), culled by the frustum where
    // pieces reached, reached.
    uint64_t boundsCulledPieces = 0, boundsCulledFrustum = 0, boundsReached = 0;
    double boundsMs = 0;               // time of the ray bounds reductions (inside the phases' times)
    double decideMs = 0;               // BoundsOnly: CPU time deciding pairs against the grid (inside the phases)
    double cellListMs = 0;             // BoundsOnly: CPU time building, sorting and uploading cell lists (not the passes)
    // GPU time of the subtree passes (per-tile batches or cell-list draws, with their masks) and of the hint pass (GL
    // timer queries), for the cost of a traversal step in a subtree pass against one in a pure pass (chcrt bench
    // --steps, which counts the hint visits' steps too). Summed over the passTimedTraces traces whose passes were
    // timed (ChcrtOptions::passTimerInterval): estimatedPassMs gives them for every culled trace.
    double subtreePassMs = 0;
    // Of subtreePassMs, the hint passes' (hintPass): what is left is the traversal of the cell lists, so a reader sees
    // what the lists cost apart from the hint visits (culling/README.md, "The ceiling of the passes").
    double hintPassMs = 0;
    uint64_t passTimedTraces = 0;
    uint64_t pairsVisible = 0;       // visible front after the trace
    uint64_t pairsInvisible = 0;     // invisible front after the trace
    uint64_t pairsNewlyVisible = 0;  // terminal pairs found visible in Phase 3
    uint64_t pairsPulledUp = 0;      // interior pairs merged into invisible leaves
    uint64_t subtreesScheduled = 0;  // (tile, subtree) intersections
    uint64_t shaderCalls = 0;        // subtree-intersection draws (by-tile batches)
    uint64_t barriers = 0;           // image memory barriers between passes over the same pixels
    uint64_t residencyRounds = 0;    // SubtreeSource::acquire calls (more than batches when subtrees did not fit)
    uint64_t raysTraced = 0;         // ray texels of the traced ray sets (width × height per trace)
    double phase1Ms = 0;             // intersect previously visible leaves (incl. the init pass)
    double phase2Ms = 0;             // issue queries of the previous fronts
    double phase3Ms = 0;             // fetch results, traverse, intersect newly visible, pull-up
    double fallbackMs = 0;           // adaptive fallback traces
    double totalMs() const { return phase1Ms + phase2Ms + phase3Ms + fallbackMs; }
    uint64_t culledTraces() const { return traces - fallbackTraces; }
    // Share of the traces that culled (0 without traces) and their mean termination height (0 without any).
    double culledShare() const { return traces ? double(culledTraces()) / double(traces) : 0.0; }
    double meanHeight() const { return culledTraces() ? double(heightSum) / double(culledTraces()) : 0.0; }
    // A pass time summed over the timed traces (subtreePassMs, hintPassMs), for all culled traces: their mean times
    // the culled traces (0 where none was timed).
    double estimatedPassMs(double timedMs) const {
        return passTimedTraces ? timedMs * double(culledTraces()) / double(passTimedTraces) : 0.0;
    }
    ChcrtStats& operator+=(const ChcrtStats& o);
};

// Debug images (Figures 4 and 5 of the paper), accumulated over traces until clearDebugImage().
enum class ChcrtDebugImage : uint8_t {
    None,
    Overdraw, // query fragments per pixel (Figure 4 left)
    Subtrees, // 1 + id of the termination subtree that produced the pixel's latest hit change, 0 = none (Figure 5 left)
    Batches,  // subtrees traversed per pixel: the sum of the sizes of the batches that covered it (Figure 5 right)
    // BVH traversal steps per pixel (inner nodes + leaves + triangles, as the pure tracer's cost target counts
    // them) summed over every subtree pass of the trace, in the steps word of shaders/shared/render_layout.h:
    // CHCRT_TRACE_STEPS_CAPPED = a pass reached the loop cap, the count (CHCRT_TRACE_STEPS_COUNT) saturates.
    Cost,
    // The ray bounds grid of the last trace, per cell (every pixel of a cell holds its value): the bits of the largest
    // segment end t of the cell's rays after the trace's last reduction — their t_best extent once hits bound them —,
    // 0 for a cell without a ray to trace, 0xFFFFFFFF for an unbounded one (culling/README.md, "The ray bounds grid").
    // Each trace overwrites it. Not drawn by a shader: written from the grid the tracer read back.
    Bounds,
};
// "overdraw" | "subtrees" | "batches" | "cost" | "bounds" (InputError otherwise).
ChcrtDebugImage parseChcrtDebugImage(const std::string& name);
// Colours a debug image (R32UI values, rows bottom to top as GL stores them) as display RGB in [0, 1], rows top to
// bottom: counts as a heat ramp scaled to the maximum, subtree ids as hashed colours; 0 is black. Cost: a log heat
// ramp of the steps (costs span orders of magnitude) scaled to the image's maximum, magenta where a pass was capped.
// Bounds: a log heat ramp of t between the image's smallest and largest cell extent, magenta for unbounded cells.
std::vector<float> colorizeChcrtDebugImage(ChcrtDebugImage kind, const std::vector<uint32_t>& values, int width,
                                           int height);

class ChcrtTracer final : public Tracer {
public:
    // In core: builds the culling hierarchy of `bvh` and uses the BVH itself as the subtree source and as the
    // adaptive fallback's full tree. Requires a current GL context. Throws InputError for invalid options.
    ChcrtTracer(const Bvh& bvh, const ChcrtOptions& options = {}, std::string name = "chcrt");
    // Any source (e.g. out of core, §5.4). `fullTracer` (may be null: no adaptive fallback) traces a whole ray
    // set without culling; it is not owned. `options.partition` is ignored (the hierarchy carries its cut).
    ChcrtTracer(CullingHierarchy hierarchy, SubtreeSource& source, Tracer* fullTracer, const ChcrtOptions& options,
                std::string name = "chcrt");
    ~ChcrtTracer() override;

    std::string name() const override { return name_; }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override;

    const ChcrtOptions& options() const { return options_; }
    const CullingHierarchy& hierarchy() const { return hierarchy_; }
    const ChcrtStats& lastStats() const { return last_; }
    const ChcrtStats& totalStats() const { return total_; }
    void resetStats() { total_ = ChcrtStats{}; }
    // Forgets every ray set's visibility fronts and adaptive measurements.
    void resetVisibility() {
        states_.clear();
        sharedKey_.reset();
        surfaceFrames_->key.reset();
        sweepSets_ = {};
        lastSweepSets_ = 0;
        adaptive_.clear();
        for (auto& arm : heightArms_) if (arm) arm->resetVisibility();
    }
    size_t rayStateCount() const { return states_.size(); }
    // Every ray set's invisible front next to its visible pairs (VisibilityState::collectInvisibleNextToVisible):
    // nodes of hierarchy(), appended, possibly repeated. Out of core: what to prefetch (subtree_prefetch.h).
    void collectInvisibleFrontNextToVisible(std::vector<uint32_t>& nodes) const {
        for (const auto& [key, state] : states_) state->collectInvisibleNextToVisible(nodes);
    }
    // The hit hints of the request's ray set (R32UI texture, GL orientation; culling/README.md "Hit hints"), 0 when
    // it has none yet. Tests write arbitrary nodes into it: hints never change hits.
    GLuint hintTexture(const TraceRequest& request) const;
    // Hint images kept (all ray sets of all kinds; within ChcrtOptions::hintMemoryBytes).
    size_t hintImageCount() const { return hintStore_->size(); }

    // A ray set's hints (hintKey: ray kind and sample index) and a ray kind's hint pass record (see hintPassRecords_).
    struct HintImage {
        GlTexture texture;
        TextureExtent extent;  // the texture's, kept so that choosing a trace's arm asks GL nothing (setHints)
        uint64_t epoch = 0;  // the source's contentEpoch when its hints were last validated (by a hint pass)
        bool passed = false;       // a hint pass has run over them (the first does not count in HintPassRecord)
        bool droppedStale = false; // the last pass dropped hints of cache slots replaced since (validateHints)
    };
    struct HintPassRecord {
        uint32_t misses = 0, skipped = 0;
    };
    // Every ray set's hints and every kind's hint pass record, copied. `chcrt bench --steps` counts a pass's steps in
    // an extra, untimed trace: restored to the hints the timed trace started from, it does the timed trace's work;
    // without, its rays would find their hits in the hints the timed trace had just recorded from these very rays
    // (city near, 256², 16 shadow spp, chcrt-noadapt: 2.9 steps per ray counted so, 4.2 with the snapshot; pure BVH 33).
    struct HintSnapshot {
        std::map<uint64_t, HintImage> images;
        std::map<uint64_t, HintPassRecord> records;
    };
    HintSnapshot saveHints() const;
    // Makes the hints and records those of `snapshot`; ray sets that had no hints then have none again.
    void restoreHints(const HintSnapshot& snapshot);

    // Debug images: selecting one compiles the instrumented shader variants on first use; traces then add to
    // an R32UI texture of the traced size (GL window orientation) until clearDebugImage() (the viewer and
    // `chcrt render --debug-image` clear it per frame). Traces the adaptive choice gives to another arm add nothing.
    void setDebugImage(ChcrtDebugImage kind);
    ChcrtDebugImage debugImageKind() const { return debugKind_; }
    void clearDebugImage();
    GLuint debugTexture() const { return debugTexture_.id(); } // 0 before the first trace with a debug image
    int debugWidth() const { return debugWidth_; }
    int debugHeight() const { return debugHeight_; }
    std::vector<uint32_t> readDebugImage() const;
    // With the Subtrees debug image: per pixel, the buffer index of the triangle that produced the latest hit change
    // (written with the subtree id, by the tile subtree passes; cell passes leave it as it was). For the out-of-core
    // primary resolve, which checks each index against the hit's triangle id before using it.
    std::vector<uint32_t> readHitTriangleImage() const;

private:
    // A tracer of one of the adaptive choice's further heights (armTracer): its passes' programs come from `programs`,
    // the cache of the tracer that made it, so that its first trace does not compile the same passes again.
    ChcrtTracer(const Bvh& bvh, const ChcrtOptions& options, std::string name, std::shared_ptr<ProgramCache> programs);

    struct PendingQuery {
        int32_t pair;       // single query: the pair; multi-query: -1
        GLuint query;
        bool lazy;          // re-query of a visible leaf (already intersected this frame)
        uint32_t groupBegin = 0, groupCount = 0; // multi-query: pairs in multiGroups_
    };
    struct Scheduled {
        Tile tile;
        uint32_t subtree;
        float distance;   // to the camera, for approximate front-to-back order in a batch
        uint32_t gpuRoot; // from the SubtreeSource, per residency round
    };
    enum class Mode { None, Query, Intersect };

    struct DebugPrograms {
        ShaderProgram query[2];   // [anyHit]
        ShaderProgram subtree[2]; // [anyHit]
    };
    std::vector<ShaderDefine> subtreeDefines(bool anyHit) const;
    void compilePrograms();
    const DebugPrograms& debugPrograms(ChcrtDebugImage kind);
    const ShaderProgram& queryProgram(bool anyHit) const;
    const ShaderProgram& subtreeProgram(bool anyHit) const;
    VisibilityState& stateFor(const TraceRequest& request, int width, int height);
    GLuint framebufferFor(const HitTargets& hits);
    void setMode(Mode mode, bool anyHit);
    int setQueryBoxes(const ShaderProgram& program, const uint32_t* nodes, int count) const;
    // False when the pair was found invisible without a query (out of its rays' reach).
    bool issueQuery(int32_t pair, VisibilityState& state, bool lazy, bool anyHit);
    bool mayHit(const QueryPair& pair) const; // some ray of the pair's tile may reach its query boxes
    void issueMultiQuery(const std::vector<int32_t>& pairs, const VisibilityState& state, bool anyHit);
    void beginQueryDraw(const Tile& tile, bool anyHit);
    GLuint acquireQuery();
    void schedule(const VisibilityState& state, int32_t pair, std::vector<Scheduled>& out) const;
    void intersect(std::vector<Scheduled>& work, bool anyHit);
    bool intersectsByCells() const { return options_.cellIntersect && options_.queries == ChcrtQueries::Batched; }
    void drawBatches(const std::vector<Scheduled>& work, bool anyHit);
    void readPixelsOf(const Tile& tile); // barrier when `tile` overlaps pixels stored since the last one
    void processResult(VisibilityState& state, const PendingQuery& pending, GLuint samples,
                       std::vector<Scheduled>& newlyVisible, bool anyHit);
    // Batched: tests the round's pairs (batch_) in one dispatch and processes their results, which queue the next
    // round's pairs (children of pairs that turned visible).
    void testBatch(VisibilityState& state, std::vector<Scheduled>& newlyVisible, bool anyHit);
    // Returns false when the ray set had no fronts yet (a cold trace, not representative of culling's cost).
    bool traceCulled(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height);
    // §5.4 residency rounds: makes the scheduled subtrees resident, as many as fit, nearest first, and hands each
    // round's resident ones (with their GPU roots) to `draw`, until all are done or the upload budget ran out.
    void residentRounds(std::vector<Scheduled>& work, const std::function<void(const std::vector<Scheduled>&)>& draw);
    // BoundsGpu (chcrt_tracer_bounds.cpp): the reduction, the GPU's cell lists and one cell pass, no read-back.
    bool traceBoundedGpu(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height);
    // BoundsOnly (chcrt_tracer_bounds.cpp): Algorithm 1 with the ray bounds grid deciding every pair.
    bool traceBounded(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height);
    // Clears the hits to misses (unless `clearHits` is false: the trace's first cell pass writes them all, see
    // cellPassWritesAll_) and binds them; `hitDepth`: also the hit set's depth to "no hit yet", for traces whose
    // passes test against it or write it (GL queries, subtree passes). Cell passes only use it as the later rounds'
    // mask, which they clear themselves (CellTraversal::draw).
    void beginTrace(const RayTextures& rays, HitTargets& hits, int width, int height, bool hitDepth,
                    bool clearHits = true);
    void endTrace(VisibilityState& state, int width, int height); // pull-up, fronts' statistics, then finishTrace
    void finishTrace(int width, int height);                      // GL state, glFinish, the passes' GPU times
    // Subdivides a pair that turned visible (§4.3, `split` its domain) into new invisible leaves; returns how many.
    int subdividePair(VisibilityState& state, int32_t pair, PairSplit split, std::array<int32_t, 4>& children) const;
    // The ray bounds grid from the rays and the hits so far (`hitImage`, 0 = none); `cellMarks`: the hint pass's.
    void updateBounds(const RayTextures& rays, GLuint hitImage, bool anyHit, int width, int height,
                      GLuint cellMarks = 0);
    // Decides the pair with the grid and, when visible, descends the pair hierarchy to terminal pairs, which are
    // scheduled into `out`. Returns whether the pair is visible.
    // Sets the ray bounds grid of the renderer's primary rays from its camera (TraceRequest::cameraRays,
    // camera_ray_bounds.h) when the request has it and the option allows; false: nothing done.
    bool boundFromCamera(const TraceRequest& request, int width, int height);
    // Whether boundFromCamera applies to the request: the renderer's primary rays of the traced size.
    bool cameraBoundable(const TraceRequest& request, int width, int height) const;
    // Sets the ray bounds grid of the renderer's AO rays before any hit from the surface frames of their G-buffer
    // (TraceRequest::hemisphereRays, hemisphere_ray_bounds.h; reduced by the first such set of the G-buffer) when the
    // request has them and options_.hemisphereBounds allows; false: nothing done.
    bool boundFromHemisphere(const TraceRequest& request, const RayTextures& rays, int width, int height);
    bool decideByBounds(int32_t pair, VisibilityState& state, std::vector<Scheduled>& out);
    // Whether the request's rays belong to a light sweep and this tracer makes shared lists for sweeps (the first
    // test of sharesLightSweep, which also needs any-hit rays and no debug image or previous front).
    bool sweepListsFor(const TraceRequest& request) const {
        return request.lightSweep && (sharedCells_ || sharedGpuLists_);
    }
    // Whether the request's ray set traces the shared lists of its light sweep (options_.shareShadowLists; counts the
    // sweep's sets and keeps the request's key in sweepSets_, call once per trace), and the trace that does so: the
    // shared lists, made first when the sweep is new (chcrt_tracer_bounds.cpp).
    bool sharesLightSweep(const TraceRequest& request, int width, int height);
    bool traceSharedLists(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                          int height);
    // Appends the resident scheduled subtrees to the lists of the cellsX × cellsY cells whose rays may reach them
    // (by the grid's cells; every cell of their tiles without any); `lastSubtree`: scratch.
    void addToCellLists(CellTraversal& cells, int cellsX, int cellsY, const std::vector<Scheduled>& resident,
                        std::vector<uint32_t>& lastSubtree) const;
    std::unique_ptr<CellTraversal> makeCellTraversal();
    // Intersects scheduled subtrees from cell lists (cell_traversal.h), one draw per residency round; `compacted`:
    // a dispatch over the rays the hint pass left (hint_pass.h) instead of a pass over every cell with work.
    void intersectCells(std::vector<Scheduled>& work, bool anyHit, const RayTextures& rays, HitTargets& hits,
                        bool firstRound, bool compacted, int width, int height);
    GLuint maskFramebufferFor(GLuint depthTexture);
    // GL timer queries around the subtree passes of a trace (beginPassTimer/endPassTimer), read once it has finished;
    // `hintPass`: the timer also counts as the hint pass's (ChcrtStats::hintPassMs).
    void beginPassTimer(bool hintPass = false);
    void endPassTimer();
    void readPassTimers();
    // Whether traces use hit hints: hitHints with bounds-decided cell lists on the in-core BVH, or out of core with
    // rounds intersected by cells from a source whose nodes hints may name (closest-hit ray sets also closestHitHints).
    bool hintsAvailable() const;
    // Whether the request's ray set has a hint image: hints available, and any-hit rays or closestHitHints.
    bool usesHints(const TraceRequest& request) const {
        return hintsAvailable() && (request.anyHit || options_.closestHitHints);
    }
    // CHCRT_CULLING_HINT_SLOTS: 1 where hints name nodes of cache slots (out of core; shaders/culling/hint_leaf.glsl).
    ShaderDefine hintSlotsDefine() const { return {"CHCRT_CULLING_HINT_SLOTS", source_->hintSlotNodes() != 0 ? "1" : "0"}; }
    // The hint image of the request's ray set (R32UI of the traced size, CHCRT_CULLING_IMAGE_HINT), made on first
    // use with no hints (`fresh` = true then). Out of core the hint pass drops the hints whose cache slot was replaced
    // since the image's epoch; an image 2^31 replacements old is emptied here instead (fresh again). 0 when the ray
    // set has none (hints off, or closest-hit rays without closestHitHints).
    GLuint hintImageFor(const TraceRequest& request, int width, int height, bool& fresh);
    // Hint images per ray kind at the traced size (within ChcrtOptions::hintMemoryBytes; sample indices beyond share).
    uint32_t hintSetsAt(int width, int height) const;
    // For the adaptive choice: whether the request's ray set has hints of the traced size (true where its kind uses
    // none), and how many sets of its kind have.
    RaySetHints setHints(const TraceRequest& request, int width, int height) const;
    // The start of a BoundsOnly / BoundsGpu trace's hints (out of core: of a trace intersected by cells): binds the
    // ray set's hint image and runs the hint pass when it is due (options_.hintPass, hints from an earlier trace, the debug image allows it, and hintPassDue). Clears
    // `warm` for a trace that is no sample of culling's cost: its ray set had no hints yet, or it is this tracer's
    // first hint pass (llvmpipe compiles a program's variants at their first use). `markCells`: the pass marks the
    // cells of the rays it leaves, for a reduction over those cells (HintPass::run). Returns whether the pass ran.
    bool startHints(const TraceRequest& request, const RayTextures& rays, int width, int height, bool& warm,
                    bool markCells);
    // Out of core, for the hint pass about to run: what it checks each hint's cache slot against (the slots replaced
    // since the image's hints were last validated); the pass validates them all, so the image's epoch moves on.
    HintSlots validateHints(const TraceRequest& request);
    // Whether its ray kind's recent hint passes left at most hintPassMaxLeft of the pixels, or a retry is due.
    bool hintPassDue(const TraceRequest& request);
    // After a trace that ran the hint pass (its GPU work finished): the rays it left, into the statistics and the
    // ray kind's record.
    void finishHintPass(const TraceRequest& request, int width, int height);
    std::string debugDefineOfKind() const;
    void ensureDebugTexture(int width, int height);
    std::vector<uint32_t> readDebugSizedImage(const GlTexture& texture) const;
    // ChcrtDebugImage::Bounds: the grid's cells of the last reduction into the debug texture.
    void writeBoundsImage(int width, int height);
    // The culling tracer of adaptive arm `arm` (>= 1): this one for arm 1, else one at adaptiveHeights[arm - 2].
    ChcrtTracer& armTracer(uint32_t arm);
    // Traces with this tracer's own options; returns whether the trace is a sample of what they cost, for the
    // adaptive choice (not from cold fronts or hints, not with a hint pass that left too many rays).
    bool traceOwn(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height);

    std::string name_;
    ChcrtOptions options_;
    const Bvh* bvh_ = nullptr; // in core: for the culling hierarchies of adaptiveHeights
    std::vector<std::unique_ptr<ChcrtTracer>> heightArms_; // by adaptiveHeights index, built on first use
    uint64_t tracesRun_ = 0; // culling traces of this configuration
    CullingHierarchy hierarchy_;
    std::unique_ptr<SubtreeSource> ownedSource_;
    SubtreeSource* source_ = nullptr;
    std::unique_ptr<Tracer> ownedFullTracer_;
    Tracer* fullTracer_ = nullptr;
    ShaderProgram queryPrograms_[2];   // [anyHit]
    ShaderProgram subtreePrograms_[2]; // [anyHit]
    ShaderProgram singleSubtreePrograms_[2]; // [anyHit], for batches of one subtree (no batch loop)
    std::map<ChcrtDebugImage, DebugPrograms> debugPrograms_; // instrumented variants per debug image, kept
    const DebugPrograms* debugActive_ = nullptr;              // those of debugKind_; nullptr = none
    ChcrtDebugImage debugKind_ = ChcrtDebugImage::None;
    GlTexture debugTexture_;
    GlTexture hitTriangleTexture_; // R32UI, sized with debugTexture_ (readHitTriangleImage)
    int debugWidth_ = 0, debugHeight_ = 0;
    std::map<GLuint, GlFramebuffer> framebuffers_; // by depth texture id
    int framebufferWidth_ = 0, framebufferHeight_ = 0; // the size of the targets framebuffers_ were made over
    std::map<uint64_t, std::unique_ptr<VisibilityState>> states_;
    static constexpr uint64_t kHintKinds = 4; // shares of hintMemoryBytes: shadow, AO, bounce shadow, closest-hit
    uint32_t hintSets_ = UINT32_MAX;          // hint images per ray kind at the traced size (hintImageFor)
    std::map<uint64_t, HintImage> hints_; // hit hints per ray kind and sample index (hintKey), hitHints only
    // The hints this tracer reads and writes: its own, or for the tracers of adaptiveHeights those of the tracer that
    // owns them. Hints name leaves of the one in-core BVH, whatever the termination height, so every arm continues
    // from the hints of the last culled trace of the ray set; a probe of another height is then measured as it would
    // run, not from cold hints.
    std::map<uint64_t, HintImage>* hintStore_ = &hints_;
    // Per ray kind (adaptiveKey: whether hints finish most rays depends on the kind of ray in the scene, not on the
    // sample or the height; shared with the adaptiveHeights tracers as the hints are): its hint passes in a row that
    // left too many rays, and its traces since the last one. From kHintPassMisses such passes on (one may come from
    // hints of an unrepresentative trace) the kind visits its hints in the cell pass, retrying after
    // hintPassRetryInterval traces, doubled per further miss up to kHintPassRetryDoublings times.
    static constexpr uint32_t kHintPassMisses = 2;
    static constexpr uint32_t kHintPassRetryDoublings = 4;
    std::map<uint64_t, HintPassRecord> ownHintPassRecords_;
    std::map<uint64_t, HintPassRecord>* hintPassRecords_ = &ownHintPassRecords_;
    bool hintPassRan_ = false; // this tracer ran the hint pass before
    bool hintPassLeftTooMany_ = false; // the last trace's hint pass counted as a miss (finishHintPass)
    // bounds-only primary rays (every ray of the set active, nothing stored before the cell pass): the trace's next
    // cell pass draws every cell and stores every ray's hit, a miss too, so the hit image was not cleared; a trace
    // that ends with it still set (nothing to intersect) clears it then.
    bool cellPassWritesAll_ = false;
    std::map<uint64_t, AdaptiveChoice> adaptive_; // per ray kind
    // The programs of the grid, the cell passes and the hint pass; one cache for the tracers of all heights.
    std::shared_ptr<ProgramCache> programCache_ = std::make_shared<ProgramCache>();
    std::unique_ptr<RayBoundsGrid> rayExtent_;    // with options_.rayExtentCulling or BoundsOnly, updated per trace
    std::unique_ptr<CellTraversal> cells_;        // BoundsOnly's and BoundsGpu's intersection rounds
    // shareShadowLists: the lists of the light sweep last decided (kept for the ray sets that share them; BoundsOnly),
    // and what they are for: the sweep, the eye (the origins' offsets), the traced size; their entries (statistics).
    std::unique_ptr<CellTraversal> sharedCells_;
    struct SharedListsKey {
        uint64_t generation = 0;
        glm::vec3 lightMin{0.0f}, lightMax{0.0f}, eye{0.0f};
        int width = 0, height = 0;
        bool operator==(const SharedListsKey&) const = default;
    };
    std::optional<SharedListsKey> sharedKey_;
    // hemisphereBounds: the G-buffer whose surface frames the grid holds.
    struct SurfaceFramesKey {
        uint64_t generation = 0;
        glm::vec3 eye{0.0f};
        int width = 0, height = 0;
        bool operator==(const SurfaceFramesKey&) const = default;
    };
    struct KeyedSurfaceFrames {
        std::optional<SurfaceFramesKey> key; // none: nothing reduced since the last resetVisibility
        SurfaceFrames frames;
    };
    // The surface frames of the G-buffer whose AO sets were bounded last (boundFromHemisphere). Shared with the
    // tracers of adaptiveHeights, whose grids have this one's cells, as the hints are: a G-buffer's frames are reduced
    // once, whichever heights trace its sets (interior near AO, 20 sets a frame: the further heights' probes reduced
    // them again, 3–4 ms a frame; docs/benchmarks.md, 2026-12-08).
    std::shared_ptr<KeyedSurfaceFrames> surfaceFrames_ = std::make_shared<KeyedSurfaceFrames>();
    struct SweepSets {
        SharedListsKey key;
        uint32_t sets = 0;
    };
    SweepSets sweepSets_;         // the light sweep traced last and its sets so far
    uint32_t lastSweepSets_ = 0;  // the sets of the sweep before it
    std::unique_ptr<GpuCellLists> sharedGpuLists_; // BoundsGpu: the shared lists, decided on the GPU
    uint64_t sharedEntries_ = 0;
    std::unique_ptr<GpuCellLists> gpuLists_;      // BoundsGpu's cell lists
    std::unique_ptr<HintPass> hintPass_;          // options_.hintPass with hints available
    std::vector<GLuint> queryPool_;
    struct PassTimer {
        std::unique_ptr<GpuTimer> timer;
        bool hintPass = false; // it timed a hint pass
    };
    std::vector<PassTimer> passTimers_; // the first passTimersUsed_ hold this trace's passes
    size_t passTimersUsed_ = 0;
    bool timingPasses_ = true; // this trace's passes are timed (ChcrtOptions::passTimerInterval)
    size_t queriesInUse_ = 0;
    std::deque<PendingQuery> queue_;
    std::vector<int32_t> multiGroups_;
    std::unique_ptr<BatchedQueries> batched_; // options_.queries == Batched
    std::vector<PendingQuery> batch_;         // Batched: the pairs of the next round (no query objects)
    std::vector<Tile> dirtyTiles_; // tiles whose hit-image stores no barrier has published yet
    // The trace in progress, for intersection rounds by cells (intersectsByCells): its rays, hits, size, and whether
    // a round has run (later rounds of any-hit rays trace only the rays still without a hit).
    const RayTextures* traceRays_ = nullptr;
    HitTargets* traceHits_ = nullptr;
    int traceWidth_ = 0, traceHeight_ = 0;
    bool cellRoundRun_ = false;
    bool compactedRounds_ = false; // out of core after a hint pass: rounds trace the rays it left (drawCompacted)
    Mode mode_ = Mode::None;
    glm::vec3 eye_{0.0f};
    ChcrtStats last_, total_;
};

} // namespace chcrt
