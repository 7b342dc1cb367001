#pragma once
// CHC+RT (coherent hierarchical culling for ray tracing) as a Tracer: generalized occlusion queries over
// query pairs (screen tile × BVH node, §4.1-4.4) decide which termination subtrees (§5.2) each tile's rays
// must traverse; visibility fronts kept per ray set across frames (§4.5, §5.1, Algorithm 1) hide most of the
// query latency. The conservative variant returns exactly the hits of pure BVH tracing (same subtree
// traversal code and hit rule; queries never cull a box a ray could hit at its current nearest t), up to the
// rule's own order dependence when a hit lies one ulp outside its boxes (culling/README.md, known edge case).
// Not implemented yet: multi-queries and tighter bounds (§5.1), the leaf cache (§5.2), out-of-core caching
// (§5.4), debug images. See culling/README.md.
#include "culling/query_pair_hierarchy.h"
#include "culling/subtree_partition.h"
#include "culling/visibility_state.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"
#include "renderer/render/tracer.h"

#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace chcrt {

struct ChcrtOptions {
    SubtreePartitionOptions partition;
    QueryPairOptions pairs;
    int batchSize = 24;              // §5.2: subtrees per shader call (<= CHCRT_CULLING_MAX_BATCH)
    int flushThreshold = 16;         // §5.1 m: intersect newly visible leaves once more than m have collected
    uint32_t requeryInterval = 3;    // §5.1 n: lazy re-query of visible leaves every n frames
    bool temporalCoherence = true;   // false: every trace starts from the root pair (§4.3-4.4 only)
    uint32_t visibleThreshold = 0;   // §7 aggressive culling: visible only when more rays pass (0 = exact)
    uint32_t seed = 1;               // of the randomized re-query phases
};

// Counters of one trace (lastStats) or summed over traces (totalStats).
struct ChcrtStats {
    uint64_t traces = 0;
    uint64_t queries = 0;            // occlusion queries issued (all phases)
    uint64_t queriesInvisible = 0;   // Phase 2: previously invisible pairs
    uint64_t queriesLazy = 0;        // Phase 2: lazy re-queries of previously visible leaves
    uint64_t queriesTraversal = 0;   // Phase 3: children of pairs that turned visible
    uint64_t pairsVisible = 0;       // visible front after the trace
    uint64_t pairsInvisible = 0;     // invisible front after the trace
    uint64_t pairsNewlyVisible = 0;  // terminal pairs found visible in Phase 3
    uint64_t pairsPulledUp = 0;      // interior pairs merged into invisible leaves
    uint64_t subtreesScheduled = 0;  // (tile, subtree) intersections
    uint64_t shaderCalls = 0;        // subtree-intersection draws (by-tile batches)
    uint64_t barriers = 0;           // image memory barriers between passes over the same pixels
    double phase1Ms = 0;             // intersect previously visible leaves (incl. the init pass)
    double phase2Ms = 0;             // issue queries of the previous fronts
    double phase3Ms = 0;             // fetch results, traverse, intersect newly visible, pull-up
    ChcrtStats& operator+=(const ChcrtStats& o);
};

class ChcrtTracer final : public Tracer {
public:
    // Requires a current GL context. Copies what it needs of the BVH (node boxes, the termination cut).
    // Throws InputError for invalid options.
    ChcrtTracer(const Bvh& bvh, const ChcrtOptions& options = {}, std::string name = "chcrt");
    ~ChcrtTracer() override;

    std::string name() const override { return name_; }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override;

    const ChcrtOptions& options() const { return options_; }
    const SubtreePartition& partition() const { return partition_; }
    const ChcrtStats& lastStats() const { return last_; }
    const ChcrtStats& totalStats() const { return total_; }
    void resetStats() { total_ = ChcrtStats{}; }
    // Forgets every ray set's visibility fronts (next traces start from the root pair).
    void resetVisibility() { states_.clear(); }
    size_t rayStateCount() const { return states_.size(); }

private:
    struct PendingQuery {
        int32_t pair;
        GLuint query;
        bool lazy; // re-query of a visible leaf (already intersected this frame)
    };
    struct Scheduled {
        Tile tile;
        uint32_t node;
        float distance; // to the camera, for approximate front-to-back order in a batch
    };
    enum class Mode { None, Query, Intersect };

    VisibilityState& stateFor(const TraceRequest& request, int width, int height);
    GLuint framebufferFor(const HitTargets& hits);
    void setMode(Mode mode, bool anyHit);
    void issueQuery(int32_t pair, const VisibilityState& state, bool lazy, bool anyHit);
    GLuint acquireQuery();
    void schedule(const VisibilityState& state, int32_t pair, std::vector<Scheduled>& out) const;
    void intersect(std::vector<Scheduled>& work, bool anyHit);
    void readPixelsOf(const Tile& tile); // barrier when `tile` overlaps pixels stored since the last one
    void processResult(VisibilityState& state, const PendingQuery& pending, GLuint samples,
                       std::vector<Scheduled>& newlyVisible, bool anyHit);

    std::string name_;
    ChcrtOptions options_;
    SubtreePartition partition_;
    std::vector<glm::vec3> boxMin_, boxMax_;
    ShaderProgram initProgram_;
    ShaderProgram queryPrograms_[2];   // [anyHit]
    ShaderProgram subtreePrograms_[2]; // [anyHit]
    std::map<GLuint, GlFramebuffer> framebuffers_; // by depth texture id
    std::map<uint64_t, std::unique_ptr<VisibilityState>> states_;
    std::vector<GLuint> queryPool_;
    size_t queriesInUse_ = 0;
    std::deque<PendingQuery> queue_;
    std::vector<Tile> dirtyTiles_; // tiles whose hit-image stores no barrier has published yet
    Mode mode_ = Mode::None;
    glm::vec3 eye_{0.0f};
    ChcrtStats last_, total_;
};

} // namespace chcrt
