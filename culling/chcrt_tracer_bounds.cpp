// CHC+RT with the ray bounds grid deciding every query pair (ChcrtQueries::BoundsOnly; culling/README.md "Deciding
// pairs"). Algorithm 1's structure stays — Phase 1 intersects the previous visible front, the invisible front is
// tested against the hits Phase 1 found, pairs that turned visible are traversed down to terminal pairs, newly
// visible subtrees are intersected, invisibility is pulled up — but a "query" is a test of the pair's boxes
// against the grid's cell boxes (ray_bounds_grid.h), answered on the CPU at once: no GL query, no blocking read,
// no per-pixel work. The per-ray test the query made is left to the subtree traversal, whose first step tests the
// subtree's box against the ray's current hit (what a query's fragment does), and each subtree is listed only for
// the screen cells whose boxes it may meet. Intersection rounds are one draw each over the cells with work
// (cell_traversal.h).
#include "culling/chcrt_tracer.h"

#include "renderer/core/error.h"
#include "renderer/core/timing.h"
#include "renderer/render/trace_pass.h"
#include "shaders/shared/culling_layout.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <chrono>

namespace chcrt {
namespace {
using Clock = std::chrono::steady_clock;
} // namespace

void ChcrtTracer::updateBounds(const RayTextures& rays, GLuint hitImage, bool anyHit, int width, int height,
                               GLuint cellMarks) {
    const auto start = Clock::now();
    const CullingHierarchy::Node& root = hierarchy_.nodes[0];
    rayExtent_->update(rays.origin.id(), rays.direction.id(), hitImage, anyHit, width, height, root.boxMin,
                       root.boxMax, cellMarks);
    // The reduction bound the hit image read-only, its own program and, over marked cells, their dispatch command:
    // restore what the passes expect.
    if (hitImage != 0) glBindImageTexture(CHCRT_CULLING_IMAGE_HIT, hitImage, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
    if (cellMarks != 0) hintPass_->bindDispatch();
    mode_ = Mode::None;
    ++last_.boundsUpdates;
    last_.boundsMs += millisecondsSince(start);
}

bool ChcrtTracer::cameraBoundable(const TraceRequest& request, int width, int height) const {
    return request.cameraRays && rayExtent_->options().cameraRays && request.cameraRays->width == width &&
           request.cameraRays->height == height;
}

bool ChcrtTracer::boundFromCamera(const TraceRequest& request, int width, int height) {
    if (!cameraBoundable(request, width, height)) return false;
    const auto start = Clock::now();
    const CullingHierarchy::Node& root = hierarchy_.nodes[0];
    rayExtent_->setCameraCells(*request.cameraRays, root.boxMin, root.boxMax);
    ++last_.boundsFromCamera;
    last_.boundsMs += millisecondsSince(start);
    return true;
}

bool ChcrtTracer::boundFromHemisphere(const TraceRequest& request, const RayTextures& rays, int width, int height) {
    if (!options_.hemisphereBounds || !request.hemisphereRays || !request.anyHit) return false;
    const auto start = Clock::now();
    const TraceRequest::HemisphereRays& set = *request.hemisphereRays;
    const SurfaceFramesKey key{set.generation, request.camera.eye, width, height};
    KeyedSurfaceFrames& frames = *surfaceFrames_;
    if (frames.key != key) {
        frames.frames =
            rayExtent_->reduceSurfaceFrames(rays.origin.id(), rays.direction.id(), set.shadingNormals, width, height);
        mode_ = Mode::None; // the reduction's program and bindings replaced the passes'
        frames.key = key;
        ++last_.boundsUpdates;
    }
    const CullingHierarchy::Node& root = hierarchy_.nodes[0];
    rayExtent_->setHemisphereCells(frames.frames, HemisphereSample{set.sample, set.maxRotation, set.length},
                                   root.boxMin, root.boxMax);
    ++last_.boundsFromHemisphere;
    last_.boundsMs += millisecondsSince(start);
    return true;
}

bool ChcrtTracer::decideByBounds(int32_t first, VisibilityState& state, std::vector<Scheduled>& out) {
    // Pairs that turn visible are traversed down at once (Phase 3 without waiting for query results): the grid
    // answers immediately.
    bool firstVisible = false;
    std::vector<int32_t> stack{first};
    std::array<int32_t, 4> children;
    while (!stack.empty()) {
        const int32_t index = stack.back();
        stack.pop_back();
        ++last_.pairsDecidedBounds;
        QueryPair& pair = state.pair(index);
        const bool visible = mayHit(pair);
        if (index == first) firstVisible = visible;
        if (!visible) {
            pair.visible = false;
            continue;
        }
        const PairSplit split = decideSplit(pair.tile, pair.bvhNode, hierarchy_, state.width(), state.height(),
                                            options_.pairs);
        if (split == PairSplit::None) {
            pair.visible = true; // termination reached (§5.2): the visible front
            ++last_.pairsNewlyVisible;
            schedule(state, index, out);
            continue;
        }
        const int count = subdividePair(state, index, split, children);
        for (int i = 0; i < count; ++i) stack.push_back(children[size_t(i)]);
    }
    return firstVisible;
}

bool ChcrtTracer::traceBoundedGpu(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                                  int height) {
    const bool anyHit = request.anyHit;
    bool warm = tracesRun_ > 1; // every trace is alike; the first compiles and fills caches
    auto start = Clock::now();
    beginTrace(rays, hits, width, height, false);
    // A shadow ray set of a light sweep traces the sweep's lists, made by its first set that shares them
    // (chcrt_tracer.h, shareShadowLists; sharesLightSweep keeps the request's key in sweepSets_); every other set
    // reduces its own rays after the hint pass, over the cells it marked.
    const bool shared = sharesLightSweep(request, width, height);
    const bool hintPass = startHints(request, rays, width, height, warm, anyHit && !shared);
    // The reduction and the lists are queued one after the other; the CPU waits for neither (the times below are
    // the CPU's, submitting them; the cell pass's GPU time is subtreePassMs).
    const auto boundsStart = Clock::now();
    const CullingHierarchy::Node& root = hierarchy_.nodes[0];
    // After the hint pass the reduction reads its hits; only any-hit rays can leave cells empty (their marks).
    const bool compacted = hintPass && anyHit;
    const int cell = rayExtent_->options().cellSize;
    const int cellsX = (width + cell - 1) / cell, cellsY = (height + cell - 1) / cell;
    GpuCellLists& lists = shared ? *sharedGpuLists_ : *gpuLists_;
    if (shared && sharedKey_ == sweepSets_.key) {
        lists.bind();
        ++last_.sharedListsReused;
    } else {
        if (shared) {
            sharedKey_.reset();
            rayExtent_->reduceLightSweep(rays.origin.id(), rays.direction.id(), width, height, root.boxMin,
                                         root.boxMax, request.lightSweep->lightMin, request.lightSweep->lightMax);
        } else {
            const GLuint hitImage = hintPass ? hits.hit.id() : 0, marks = compacted ? hintPass_->cellMarks() : 0;
            if (debugKind_ == ChcrtDebugImage::Bounds) { // the bounds image needs the grid on the CPU
                rayExtent_->update(rays.origin.id(), rays.direction.id(), hitImage, anyHit, width, height,
                                   root.boxMin, root.boxMax, marks);
            } else {
                rayExtent_->reduce(rays.origin.id(), rays.direction.id(), hitImage, anyHit, width, height,
                                   root.boxMin, root.boxMax, marks);
            }
            if (hitImage != 0) {
                glBindImageTexture(CHCRT_CULLING_IMAGE_HIT, hitImage, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
            }
        }
        ++last_.boundsUpdates;
        last_.boundsMs += millisecondsSince(boundsStart);
        const auto listStart = Clock::now();
        lists.build(rayExtent_->buffer(), cellsX, cellsY, options_.cellListLimit, options_.bounds.relativePad,
                    options_.bounds.frustum);
        last_.cellListMs += millisecondsSince(listStart);
        if (shared) {
            sharedKey_ = sweepSets_.key;
            ++last_.sharedListsMade;
        }
    }
    last_.phase1Ms = millisecondsSince(start);

    start = Clock::now();
    mode_ = Mode::None;
    beginPassTimer();
    cells_->setHintsVisited(hintPass);
    if (compacted) {
        hintPass_->bindDispatch(); // the reduction and the lists' build bound their own indirect commands
        cells_->dispatchCompacted(anyHit, debugDefineOfKind(), cellsX, cell);
    } else {
        cells_->drawIndirect(anyHit, debugDefineOfKind(), width, height, cellsX, cell,
                             maskFramebufferFor(rays.active.id()), false);
    }
    endPassTimer();
    ++last_.shaderCalls;
    finishTrace(width, height);
    const GpuCellLists::Counters counters = lists.counters();
    last_.cellsDrawn = counters.cellsDrawn;
    last_.cellEntries = counters.entries;
    last_.cellsWholeTree = counters.wholeTreeCells;
    last_.pairsDecidedBounds = counters.nodesTested;
    last_.boundsCulledPieces = counters.culledPieces;
    last_.boundsCulledFrustum = counters.culledFrustum;
    last_.boundsReached = counters.reached;
    last_.subtreesScheduled = counters.entries;
    if (hintPass) finishHintPass(request, width, height);
    last_.phase3Ms = millisecondsSince(start);
    return warm;
}

bool ChcrtTracer::startHints(const TraceRequest& request, const RayTextures& rays, int width, int height, bool& warm,
                             bool markCells) {
    bool fresh = false;
    const GLuint hintImage = hintImageFor(request, width, height, fresh);
    if (hintImage == 0) return false;
    glBindImageTexture(CHCRT_CULLING_IMAGE_HINT, hintImage, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    warm = warm && !fresh;
    // The hint pass (hint_pass.h): hinted leaves first, for every ray, in a pass of their own; the rays they finish
    // leave the reduction, and the rest are traced in one compacted dispatch. Not without hints yet (every ray would
    // be left). It records no subtree ids or list lengths, so those debug images keep the visits in the cell pass.
    // Needs one round (no previous front).
    const bool hintPass = hintPass_ && options_.hintPass && !fresh && !options_.boundsPreviousFront &&
                          debugKind_ != ChcrtDebugImage::Subtrees && debugKind_ != ChcrtDebugImage::Batches &&
                          hintPassDue(request);
    if (!hintPass) return false;
    warm = warm && hintPassRan_;
    hintPassRan_ = true;
    beginPassTimer(true);
    source_->bind(); // out of core: the cache's buffers (the renderer bound the in-core scene's, if any)
    hintPass_->run(request.anyHit, width, height, maskFramebufferFor(rays.active.id()),
                   debugKind_ == ChcrtDebugImage::Cost, markCells, validateHints(request));
    endPassTimer();
    ++last_.shaderCalls;
    ++last_.hintPasses;
    return true;
}

std::string ChcrtTracer::debugDefineOfKind() const {
    switch (debugKind_) {
    case ChcrtDebugImage::Subtrees: return "CHCRT_CULLING_DEBUG_SUBTREES";
    case ChcrtDebugImage::Batches: return "CHCRT_CULLING_DEBUG_BATCHES";
    case ChcrtDebugImage::Cost: return "CHCRT_CULLING_DEBUG_COST";
    default: return ""; // query overdraw: no queries here
    }
}

void ChcrtTracer::intersectCells(std::vector<Scheduled>& work, bool anyHit, const RayTextures& rays,
                                 HitTargets& hits, bool firstRound, bool compacted, int width, int height) {
    if (work.empty()) return;
    // Nearest to the camera first (residency rounds make the near ones resident first); duplicates adjacent.
    std::sort(work.begin(), work.end(), [](const Scheduled& a, const Scheduled& b) {
        return a.distance != b.distance ? a.distance < b.distance : a.subtree < b.subtree;
    });
    mode_ = Mode::None;
    // The first round traces every active ray (the ray set's mask); later rounds of any-hit rays only those without
    // a hit (a mask written into the hit set's depth), closest-hit rays all again.
    const bool writeMask = anyHit && !firstRound;
    const GLuint maskFramebuffer = writeMask ? framebufferFor(hits) : maskFramebufferFor(rays.active.id());
    const int cell = rayExtent_->options().cellSize;
    const int cellsX = (width + cell - 1) / cell, cellsY = (height + cell - 1) / cell;
    std::vector<uint32_t> lastSubtree;
    const std::string debugDefine = debugDefineOfKind();
    residentRounds(work, [&](const std::vector<Scheduled>& resident) {
        const auto listStart = Clock::now();
        cells_->begin(cellsX, cellsY, cell);
        addToCellLists(*cells_, cellsX, cellsY, resident, lastSubtree);
        const double addMs = millisecondsSince(listStart);
        last_.cellEntries += cells_->entryCount();
        last_.subtreesScheduled += resident.size();
        beginPassTimer();
        last_.cellsDrawn += compacted ? cells_->drawCompacted(anyHit, debugDefine)
                                      : cells_->draw(anyHit, debugDefine, width, height, maskFramebuffer, writeMask,
                                                     cellPassWritesAll_);
        cellPassWritesAll_ = false;
        endPassTimer();
        last_.cellsWholeTree += cells_->wholeTreeCells();
        // CPU: lists, sorting, uploads; not the pass issued, which llvmpipe runs inside the call for a compute
        // dispatch (the compacted one, compute cell passes).
        last_.cellListMs += addMs + cells_->listUploadMs();
        ++last_.shaderCalls;
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // the next round continues from these hits
    });
}

void ChcrtTracer::addToCellLists(CellTraversal& cells, int cellsX, int cellsY, const std::vector<Scheduled>& resident,
                                 std::vector<uint32_t>& lastSubtree) const {
    const int cell = rayExtent_->options().cellSize;
    lastSubtree.assign(size_t(cellsX) * size_t(cellsY), CullingHierarchy::kNone);
    for (const Scheduled& s : resident) {
        // The boxes the traversal tests first: the subtree root's children (§5.1 tighter bounds).
        const CullingHierarchy::Node& node = hierarchy_.nodes[hierarchy_.subtrees[s.subtree].node];
        const int boxes = int(node.tightCount);
        const int x0 = std::clamp(s.tile.x / cell, 0, cellsX), y0 = std::clamp(s.tile.y / cell, 0, cellsY);
        const int x1 = std::clamp((s.tile.x + s.tile.width + cell - 1) / cell, 0, cellsX);
        const int y1 = std::clamp((s.tile.y + s.tile.height + cell - 1) / cell, 0, cellsY);
        for (int cy = y0; cy < y1; ++cy) {
            for (int cx = x0; cx < x1; ++cx) {
                const size_t c = size_t(cy) * size_t(cellsX) + size_t(cx);
                if (lastSubtree[c] == s.subtree) continue; // two tiles of one subtree sharing a cell
                if (!rayExtent_->cellMayReach(cx, cy, node.tightMin, node.tightMax, boxes)) continue;
                lastSubtree[c] = s.subtree;
                cells.add(uint32_t(c), s.gpuRoot, s.subtree,
                          rayExtent_->entryLowerBound(cx, cy, node.boxMin, node.boxMax));
            }
        }
    }
}

bool ChcrtTracer::sharesLightSweep(const TraceRequest& request, int width, int height) {
    if (!sweepListsFor(request) || !request.anyHit || options_.boundsPreviousFront ||
        debugKind_ != ChcrtDebugImage::None) {
        return false;
    }
    const TraceRequest::LightSweep& sweep = *request.lightSweep;
    const SharedListsKey key{sweep.generation, sweep.lightMin, sweep.lightMax, request.camera.eye, width, height};
    if (sweepSets_.key != key) {
        lastSweepSets_ = sweepSets_.sets;
        sweepSets_ = {key, 0};
    }
    ++sweepSets_.sets;
    // Shared lists pay from a sweep's second set on: its first set makes them where the last sweep had several sets
    // (a frame of several samples), else its second does, so that one shadow set per G-buffer (the viewer at 1 spp)
    // keeps the per-set lists, which the hint pass's marks make smaller.
    return sweepSets_.sets >= 2 || lastSweepSets_ >= 2;
}

bool ChcrtTracer::traceSharedLists(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                                   int height) {
    // One grid, one set of decisions and one set of cell lists for every shadow ray set of the light sweep: its rays
    // run from the same surface points to the light, so cells around each cell's points swept to the light's box hold
    // every set's segments (ray_bounds.comp.glsl, CHCRT_BOUNDS_LIGHT_SWEEP), and the lists they decide hold every
    // subtree any of those rays may hit. Exact as the per-set lists are; they are longer (they do not know which rays
    // a set's hits finished, nor which rays are inactive in it), and what they save is a reduction and its read-back,
    // the decisions and the lists' sorting and upload per set (culling/README.md "Shared shadow lists").
    bool warm = tracesRun_ > 1;
    auto start = Clock::now();
    beginTrace(rays, hits, width, height, false);
    const bool hintPass = startHints(request, rays, width, height, warm, false); // the lists come from the sweep
    const TraceRequest::LightSweep& sweep = *request.lightSweep;
    const SharedListsKey& key = sweepSets_.key; // sharesLightSweep's, for this request
    // Where the hint pass finished every ray (views whose shadow rays all end at their previous occluders, e.g. the
    // interior's far path) there is nothing to list or trace: a read of its count (waiting for it, as the per-set
    // reduction's read-back would) saves making the lists for no ray (interior far, 256², 16 spp, `chcrt-noadapt`:
    // 0.69× of pure BVH with the lists made, 1.09× without; culling/README.md "Shared shadow lists").
    const bool nothingLeft = hintPass && hintPass_->raysLeft() == 0;
    if (nothingLeft) {
        finishTrace(width, height);
        finishHintPass(request, width, height);
        last_.phase1Ms = millisecondsSince(start);
        return warm;
    }
    if (sharedKey_ != key) {
        sharedKey_.reset();
        const auto boundsStart = Clock::now();
        const CullingHierarchy::Node& root = hierarchy_.nodes[0];
        rayExtent_->updateLightSweep(rays.origin.id(), rays.direction.id(), width, height, root.boxMin, root.boxMax,
                                     sweep.lightMin, sweep.lightMax);
        mode_ = Mode::None;
        ++last_.boundsUpdates;
        last_.boundsMs += millisecondsSince(boundsStart);
        // Every pair from the root pair (no previous front: boundsPreviousFront is off).
        const auto decideStart = Clock::now();
        VisibilityState& state = stateFor(request, width, height);
        std::vector<int32_t> visibleLeaves, invisibleLeaves;
        state.collectLeaves(visibleLeaves, invisibleLeaves);
        std::vector<Scheduled> work;
        for (int32_t p : invisibleLeaves) decideByBounds(p, state, work);
        last_.decideMs += millisecondsSince(decideStart);
        const auto listStart = Clock::now();
        std::sort(work.begin(), work.end(), [](const Scheduled& a, const Scheduled& b) {
            return a.distance != b.distance ? a.distance < b.distance : a.subtree < b.subtree;
        });
        sharedCells_->begin(rayExtent_->cellsX(), rayExtent_->cellsY(), rayExtent_->options().cellSize);
        std::vector<uint32_t> lastSubtree;
        residentRounds(work, [&](const std::vector<Scheduled>& resident) { // in core: one round, all resident
            addToCellLists(*sharedCells_, rayExtent_->cellsX(), rayExtent_->cellsY(), resident, lastSubtree);
            last_.subtreesScheduled += resident.size();
        });
        sharedEntries_ = sharedCells_->entryCount();
        sharedCells_->keep();
        last_.cellListMs += millisecondsSince(listStart);
        last_.pairsPulledUp = uint64_t(state.pullUpInvisibility());
        sharedKey_ = key;
        ++last_.sharedListsMade;
    } else {
        ++last_.sharedListsReused;
    }
    last_.phase1Ms = millisecondsSince(start);

    start = Clock::now();
    mode_ = Mode::None;
    sharedCells_->setHintsVisited(hintPass);
    beginPassTimer();
    if (hintPass) {
        hintPass_->bindDispatch(); // the rays it left, compacted
        last_.cellsDrawn += sharedCells_->drawKeptCompacted(true);
    } else {
        last_.cellsDrawn += sharedCells_->drawKept(true, width, height, maskFramebufferFor(rays.active.id()));
    }
    endPassTimer();
    ++last_.shaderCalls;
    last_.cellEntries += sharedEntries_;
    last_.cellsWholeTree += sharedCells_->wholeTreeCells();
    finishTrace(width, height);
    if (hintPass) finishHintPass(request, width, height);
    last_.phase3Ms = millisecondsSince(start);
    return warm;
}

bool ChcrtTracer::traceBounded(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                               int height) {
    eye_ = request.camera.eye;
    const bool anyHit = request.anyHit;
    VisibilityState& state = stateFor(request, width, height);
    // Without the previous front every trace is alike; only the first (compiling, filling caches) is not typical.
    bool warm = options_.boundsPreviousFront ? state.frame() > 0 : tracesRun_ > 1;
    auto start = Clock::now();
    // The renderer's primary rays are all active and, without closest-hit hints, nothing is stored before the one
    // cell pass: that pass draws every cell and stores every ray's hit, so the hit image is not cleared first (a
    // clear cost 3 % of a culled primary trace at 256², and each ray's load of the miss it wrote).
    const bool cellPassWritesAll = !anyHit && !options_.closestHitHints && !options_.boundsPreviousFront &&
                                   debugKind_ == ChcrtDebugImage::None && cameraBoundable(request, width, height);
    beginTrace(rays, hits, width, height, false, !cellPassWritesAll);
    // Hit hints (any-hit ray sets): the cell passes first visit each ray's hinted leaf and record the leaves of new
    // hits there.
    const bool hintPass = startHints(request, rays, width, height, warm, anyHit);
    // Before any hit, a ray reaches its whole segment (clipped to the scene): bounded rays (shadow, AO) already
    // leave most of the scene out, and every cell's lists get their entry bounds. After the hint pass, any-hit rays
    // it finished are left out.
    // Closest-hit rays it bounded end their segments at those hits (every cell keeps its rays: no marks).
    const bool compacted = hintPass && anyHit;
    // The renderer's primary rays before any hit are bounded from its camera, with no reduction and no read-back,
    // its AO rays from their G-buffer's surface frames, with one reduction per G-buffer.
    if (hintPass || (!boundFromCamera(request, width, height) && !boundFromHemisphere(request, rays, width, height))) {
        updateBounds(rays, hintPass ? hits.hit.id() : 0, anyHit, width, height, compacted ? hintPass_->cellMarks() : 0);
    }
    cells_->setHintsVisited(hintPass);

    // Phase 1 (Algorithm 1, lines 1-4): intersect the previously visible leaves that the rays can reach.
    std::vector<int32_t> visibleLeaves, invisibleLeaves;
    state.collectLeaves(visibleLeaves, invisibleLeaves);
    const bool phase1 = !visibleLeaves.empty();
    if (phase1) {
        std::vector<Scheduled> work;
        for (int32_t p : visibleLeaves) {
            if (mayHit(state.pair(p))) schedule(state, p, work);
            else ++last_.leavesSkippedExtent;
        }
        intersectCells(work, anyHit, rays, hits, true, false, width, height);
        glFinish();
    }
    last_.phase1Ms = millisecondsSince(start);

    // Phases 2 and 3 (lines 5-34), decided on the CPU against the hits Phase 1 found: visible leaves out of reach
    // join the invisible front (the lazy re-query, every frame and free); invisible pairs in reach are traversed
    // down to terminal pairs, whose subtrees are intersected in one more round. Without a visible front (a cold
    // trace, or no temporal coherence) the bounds before any hit decide, and one round intersects everything.
    start = Clock::now();
    if (phase1) updateBounds(rays, hits.hit.id(), anyHit, width, height);
    for (int32_t p : visibleLeaves) {
        ++last_.pairsDecidedBounds;
        if (!mayHit(state.pair(p))) state.pair(p).visible = false;
    }
    last_.queriesInvisible = invisibleLeaves.size();
    const auto decideStart = Clock::now();
    std::vector<Scheduled> newlyVisible;
    for (int32_t p : invisibleLeaves) decideByBounds(p, state, newlyVisible);
    last_.decideMs += millisecondsSince(decideStart);
    last_.phase2Ms = millisecondsSince(start);

    start = Clock::now();
    intersectCells(newlyVisible, anyHit, rays, hits, !phase1, compacted, width, height);
    if (cellPassWritesAll_) { // nothing was intersected: every ray missed
        clearHitsToMisses(hits);
        cellPassWritesAll_ = false;
    }
    endTrace(state, width, height);
    if (hintPass) finishHintPass(request, width, height);
    last_.phase3Ms = millisecondsSince(start);
    return warm;
}

} // namespace chcrt
