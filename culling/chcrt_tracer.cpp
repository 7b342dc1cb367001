#include "culling/chcrt_tracer.h"

#include "renderer/core/error.h"
#include "shaders/culling/culling_layout.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <array>
#include <chrono>

namespace chcrt {
namespace {

using Clock = std::chrono::steady_clock;
double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

ShaderProgram makeProgram(const char* fragment, bool anyHit, std::vector<ShaderDefine> defines = {}) {
    defines.push_back({"TRACE_ANY_HIT", anyHit ? "1" : "0"});
    return ShaderProgram({{GL_VERTEX_SHADER, "common/fullscreen.vert.glsl"}, {GL_FRAGMENT_SHADER, fragment}},
                         defines);
}

// §5.3: one visibility state for all primary rays, one for all shadow rays, one for the bounce shadow rays,
// and one per sample index for AO and diffuse rays (their directions differ per pass).
uint64_t rayStateKey(const TraceRequest& request) {
    const bool perSample = !request.bounceShadow && (request.rayType == RayType::Ao || request.rayType == RayType::Diffuse);
    const uint64_t kind = request.bounceShadow ? 4u : uint64_t(request.rayType);
    return (kind << 32) | uint64_t(perSample ? uint32_t(request.sampleIndex) : 0u);
}

void validate(const ChcrtOptions& o) {
    if (o.batchSize < 1 || o.batchSize > CHCRT_CULLING_MAX_BATCH) {
        throw InputError("chcrt: batch size must be in [1, " + std::to_string(CHCRT_CULLING_MAX_BATCH) + "]");
    }
    if (o.pairs.minTileSize < 1) throw InputError("chcrt: minimum tile size must be positive");
    if (o.flushThreshold < 0) throw InputError("chcrt: flush threshold must not be negative");
    if (o.requeryInterval < 1 || o.requeryInterval > 255) throw InputError("chcrt: re-query interval must be in [1, 255]");
    if (!(o.pairs.tq > 0.0f)) throw InputError("chcrt: t_q must be positive");
}

} // namespace

ChcrtStats& ChcrtStats::operator+=(const ChcrtStats& o) {
    traces += o.traces;
    queries += o.queries;
    queriesInvisible += o.queriesInvisible;
    queriesLazy += o.queriesLazy;
    queriesTraversal += o.queriesTraversal;
    pairsVisible += o.pairsVisible;
    pairsInvisible += o.pairsInvisible;
    pairsNewlyVisible += o.pairsNewlyVisible;
    pairsPulledUp += o.pairsPulledUp;
    subtreesScheduled += o.subtreesScheduled;
    shaderCalls += o.shaderCalls;
    phase1Ms += o.phase1Ms;
    phase2Ms += o.phase2Ms;
    phase3Ms += o.phase3Ms;
    barriers += o.barriers;
    return *this;
}

ChcrtTracer::ChcrtTracer(const Bvh& bvh, const ChcrtOptions& options, std::string name)
    : name_(std::move(name)), options_((validate(options), options)), partition_(bvh, options.partition) {
    boxMin_.resize(bvh.nodes.size());
    boxMax_.resize(bvh.nodes.size());
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        boxMin_[i] = bvh.nodes[i].boundsMin;
        boxMax_[i] = bvh.nodes[i].boundsMax;
    }
    initProgram_ = makeProgram("culling/chcrt_init.frag.glsl", false);
    for (int anyHit = 0; anyHit < 2; ++anyHit) {
        queryPrograms_[anyHit] = makeProgram("culling/chcrt_query.frag.glsl", anyHit != 0);
        // A subtree of height h pushes at most h entries (one per level below its root).
        const uint32_t stack = std::min<uint32_t>(partition_.maxRootHeight() + 1, CHCRT_MAX_BVH_DEPTH);
        const std::vector<ShaderDefine> defines = {{"CHCRT_SUBTREE_STACK", std::to_string(stack)}};
        subtreePrograms_[anyHit] = makeProgram("culling/chcrt_subtrees.frag.glsl", anyHit != 0, defines);
    }
}

ChcrtTracer::~ChcrtTracer() {
    if (!queryPool_.empty()) glDeleteQueries(GLsizei(queryPool_.size()), queryPool_.data());
}

VisibilityState& ChcrtTracer::stateFor(const TraceRequest& request, int width, int height) {
    std::unique_ptr<VisibilityState>& state = states_[rayStateKey(request)];
    if (!state || !options_.temporalCoherence || state->width() != width || state->height() != height) {
        state = std::make_unique<VisibilityState>(width, height, options_.seed ^ uint32_t(rayStateKey(request)));
    }
    return *state;
}

GLuint ChcrtTracer::framebufferFor(const HitTargets& hits) {
    // The generalized queries need a depth-only target over the hit set's depth buffer; the hit buffer itself is
    // read and written as an image, never through the framebuffer (no feedback loop).
    auto it = framebuffers_.find(hits.depth.id());
    if (it == framebuffers_.end()) {
        it = framebuffers_.emplace(hits.depth.id(), createFramebuffer(nullptr, 0, hits.depth.id())).first;
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
        queryPrograms_[anyHit].use();
    } else {
        // Subtree passes write depth(new nearest t), which only decreases.
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
        subtreePrograms_[anyHit].use();
    }
}

void ChcrtTracer::issueQuery(int32_t pairIndex, const VisibilityState& state, bool lazy, bool anyHit) {
    const QueryPair& pair = state.pair(pairIndex);
    setMode(Mode::Query, anyHit);
    if (anyHit) readPixelsOf(pair.tile); // any-hit queries read the hit buffer (finished rays never pass)
    const ShaderProgram& program = queryPrograms_[anyHit];
    program.set("boxMin", boxMin_[pair.bvhNode]);
    program.set("boxMax", boxMax_[pair.bvhNode]);
    glViewport(pair.tile.x, pair.tile.y, pair.tile.width, pair.tile.height);
    const GLuint query = acquireQuery();
    glBeginQuery(GL_SAMPLES_PASSED, query);
    drawFullscreenTriangle();
    glEndQuery(GL_SAMPLES_PASSED);
    queue_.push_back(PendingQuery{pairIndex, query, lazy});
    ++last_.queries;
}

void ChcrtTracer::schedule(const VisibilityState& state, int32_t pairIndex, std::vector<Scheduled>& out) const {
    const QueryPair& pair = state.pair(pairIndex);
    const glm::vec3 nearest = glm::clamp(eye_, boxMin_[pair.bvhNode], boxMax_[pair.bvhNode]);
    const glm::vec3 d = nearest - eye_;
    out.push_back(Scheduled{pair.tile, pair.bvhNode, d.x * d.x + d.y * d.y + d.z * d.z});
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
    // §5.2 by-tile sorting: subtrees of the same tile share shader calls, nearest first within the tile.
    std::sort(work.begin(), work.end(), [](const Scheduled& a, const Scheduled& b) {
        if (a.tile.y != b.tile.y) return a.tile.y < b.tile.y;
        if (a.tile.x != b.tile.x) return a.tile.x < b.tile.x;
        if (a.tile.width != b.tile.width) return a.tile.width < b.tile.width;
        if (a.tile.height != b.tile.height) return a.tile.height < b.tile.height;
        if (a.distance != b.distance) return a.distance < b.distance;
        return a.node < b.node;
    });
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
    const ShaderProgram& program = subtreePrograms_[anyHit];
    std::array<glm::uvec4, CHCRT_CULLING_MAX_BATCH / 4> roots{};
    const size_t batch = size_t(options_.batchSize);
    for (size_t round = 0;; ++round) {
        bool any = false;
        for (const auto& [tileBegin, tileEnd] : tileRanges) {
            const size_t begin = tileBegin + round * batch;
            if (begin >= tileEnd) continue;
            any = true;
            const size_t end = std::min(tileEnd, begin + batch);
            roots.fill(glm::uvec4(0u));
            for (size_t k = begin; k < end; ++k) roots[(k - begin) / 4][int((k - begin) % 4)] = work[k].node;
            const Tile& tile = work[begin].tile;
            readPixelsOf(tile);
            program.setArray("subtreeRoots", roots.data(), int(roots.size()));
            program.set("subtreeCount", int(end - begin));
            glViewport(tile.x, tile.y, tile.width, tile.height);
            drawFullscreenTriangle();
            dirtyTiles_.push_back(tile);
            last_.subtreesScheduled += end - begin;
            ++last_.shaderCalls;
        }
        if (!any) break;
    }
    work.clear();
}

void ChcrtTracer::processResult(VisibilityState& state, const PendingQuery& pending, GLuint samples,
                                std::vector<Scheduled>& newlyVisible, bool anyHit) {
    const bool visible = samples > options_.visibleThreshold;
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
    const PairSplit split = decideSplit(pair.tile, pair.bvhNode, partition_, state.width(), state.height(),
                                        options_.pairs);
    if (split == PairSplit::None) {
        // Termination reached (§5.2): the pair joins the visible front and its subtree is intersected.
        pair.visible = true;
        ++last_.pairsNewlyVisible;
        schedule(state, pending.pair, newlyVisible);
        if (int(newlyVisible.size()) > options_.flushThreshold) intersect(newlyVisible, anyHit);
        return;
    }
    std::array<Tile, 4> tiles;
    std::array<uint32_t, 4> nodes;
    int count = 0;
    if (split == PairSplit::Object) {
        const uint32_t left = partition_.childOf(pair.bvhNode);
        tiles = {pair.tile, pair.tile, Tile{}, Tile{}};
        nodes = {left, left + 1, 0, 0};
        count = 2;
    } else {
        count = splitTile(pair.tile, options_.pairs.minTileSize, tiles);
        nodes.fill(pair.bvhNode);
    }
    std::array<int32_t, 4> children;
    state.subdivide(pending.pair, tiles.data(), nodes.data(), count, children.data(), options_.requeryInterval);
    for (int i = 0; i < count; ++i) {
        issueQuery(children[size_t(i)], state, false, anyHit);
        ++last_.queriesTraversal;
    }
}

void ChcrtTracer::trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                        int height, TraceStats& stats) {
    last_ = ChcrtStats{};
    last_.traces = 1;
    queriesInUse_ = 0;
    queue_.clear();
    eye_ = request.camera.eye;
    const bool anyHit = request.anyHit;
    VisibilityState& state = stateFor(request, width, height);

    // Initialise: all misses, depth = depth(tmax).
    auto start = Clock::now();
    glBindFramebuffer(GL_FRAMEBUFFER, framebufferFor(hits));
    glViewport(0, 0, width, height);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, rays.origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, rays.direction.id());
    glBindImageTexture(CHCRT_CULLING_IMAGE_HIT, hits.hit.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
    initProgram_.use();
    mode_ = Mode::None;
    drawFullscreenTriangle();
    dirtyTiles_.assign(1, Tile{0, 0, width, height});

    // Phase 1 (Algorithm 1, lines 1-4): intersect the previously visible leaves, initialising depth.
    std::vector<int32_t> visibleLeaves, invisibleLeaves;
    state.collectLeaves(visibleLeaves, invisibleLeaves);
    std::vector<Scheduled> work;
    for (int32_t p : visibleLeaves) schedule(state, p, work);
    intersect(work, anyHit);
    glFinish(); // phase timing (the queries of Phase 2 depend on this depth anyway)
    last_.phase1Ms = millisecondsSince(start);

    // Phase 2 (lines 5-11): query the invisible front; re-query visible leaves lazily every n frames.
    start = Clock::now();
    for (int32_t p : invisibleLeaves) {
        issueQuery(p, state, false, anyHit);
        ++last_.queriesInvisible;
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
    while (!queue_.empty()) {
        const PendingQuery pending = queue_.front();
        queue_.pop_front();
        GLuint samples = 0;
        glGetQueryObjectuiv(pending.query, GL_QUERY_RESULT, &samples);
        processResult(state, pending, samples, newlyVisible, anyHit);
    }
    intersect(newlyVisible, anyHit);
    last_.pairsPulledUp = uint64_t(state.pullUpInvisibility());
    state.advanceFrame();
    state.collectLeaves(visibleLeaves, invisibleLeaves);
    last_.pairsVisible = visibleLeaves.size();
    last_.pairsInvisible = invisibleLeaves.size();

    // Hand the hits to texture fetches and read-backs of the renderer; leave GL state as the pure tracer does.
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    dirtyTiles_.clear();
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
    glViewport(0, 0, width, height);
    glFinish();
    last_.phase3Ms = millisecondsSince(start);
    mode_ = Mode::None;
    stats.passes += 1 + last_.shaderCalls + last_.queries;
    total_ += last_;
}

} // namespace chcrt
