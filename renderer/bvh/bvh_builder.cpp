// Binned SAH BVH builder (Wald 2007, "On fast construction of SAH-based bounding volume hierarchies"; the
// Acceleration Structures lecture: SAH split cost, centroid bounds, 32-byte nodes; CHC+RT §5.2 builds its BVH
// with SAH on the CPU).
//
// Threading (std::jthread via detail::parallelFor, no TBB): the build runs in two phases.
//   1. Top phase, level by level: the nodes of one level are split in parallel (disjoint triangle ranges);
//      while a level has fewer nodes than threads, its nodes are split one after another with their binning
//      spread over all threads by triangle blocks (exact min/max and integer counts, so the merged bins do
//      not depend on how blocks were assigned). Child pairs are allocated after each level, in level order.
//      Nodes with at most `subtreeTriangles` triangles are set aside as subtree roots.
//   2. Subtree phase: every subtree is built sequentially (depth-first) into its own node vector, the
//      subtrees in parallel (largest first), then appended in top-phase order.
// Every decision depends only on the input, and the phase boundary only on the triangle count, so the node
// and triangle arrays are bit-identical for any thread count. Only the root's partition runs on one thread.
//
// Memory: besides the output, one 32-byte PrimRef per triangle (bounds + original id; the centroid is derived
// from the bounds) and, transiently, the subtrees' nodes before they are appended.
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/bvh_internal.h"
#include "renderer/core/error.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

namespace chcrt {

namespace {

constexpr uint32_t kMaxLeafDepth = CHCRT_MAX_BVH_DEPTH - 1; // root = depth 0; the traversal stack holds 64
constexpr uint32_t kForcedSplitTriangles = 16;             // above this, split even if SAH prefers a leaf
constexpr uint32_t kParallelBinTriangles = 1u << 16;       // below this, binning on one thread is faster
constexpr uint32_t kBlockTriangles = 1u << 14;             // work item of the parallel loops
constexpr uint32_t kSubtreesPerBuild = 64;                 // phase 2 granularity: ~N/64 triangles per subtree
constexpr uint32_t kMinSubtreeTriangles = 1u << 12;
constexpr uint64_t kProgressStep = 1u << 15; // triangles placed in leaves between progress updates
constexpr size_t kMaxTriangles = (size_t(1) << 31) - 1; // node indices (2N - 1) must fit in 32 bits

// One triangle during the build: its exact bounds and its original id. 32 bytes, partitioned in place.
struct PrimRef {
    glm::vec3 lower;
    uint32_t id;
    glm::vec3 upper;
    uint32_t pad;
};
static_assert(sizeof(PrimRef) == 32);

// Twice the bounds' centre: the factor 2 changes no decision and saves a multiply per use.
glm::vec3 centroid2(const PrimRef& ref) { return ref.lower + ref.upper; }

// Forced inline: called per triangle and bin from several loops, where GCC otherwise keeps the call.
[[gnu::always_inline]] inline void growBy(Aabb& box, const PrimRef& ref) {
    box.lower = glm::min(box.lower, ref.lower);
    box.upper = glm::max(box.upper, ref.upper);
}

// Surface area in double (see bvh_stats.cpp): SAH costs of huge boxes would overflow in float.
double surfaceArea(const Aabb& box) {
    const double x = double(box.upper.x) - double(box.lower.x);
    const double y = double(box.upper.y) - double(box.lower.y);
    const double z = double(box.upper.z) - double(box.lower.z);
    if (!(x >= 0.0 && y >= 0.0 && z >= 0.0)) {
        return 0.0;
    }
    return 2.0 * (x * y + y * z + z * x);
}

// A node waiting to be built: refs [begin, end), its exact bounds and the bounds of its (doubled) centroids.
struct BuildTask {
    uint32_t node = 0; // index in the node vector being filled
    uint32_t begin = 0;
    uint32_t end = 0;
    uint32_t depth = 0;
    Aabb bounds;
    Aabb centroidBounds;
    uint32_t count() const { return end - begin; }
};

// Maps a doubled centroid to one of binCount bins per axis over the node's centroid bounds. Axes with no
// (or a non-finite) extent have no bins. The same function assigns bins during binning and partitioning, so
// the counts the SAH saw are exactly the sizes the partition produces.
struct BinMapping {
    glm::vec3 origin{0.0f};
    glm::vec3 scale{0.0f};
    bool valid[3] = {false, false, false};
    float maxBin = 0.0f;

    BinMapping(const Aabb& centroidBounds, uint32_t binCount)
        : origin(centroidBounds.lower), maxBin(float(binCount - 1)) {
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = centroidBounds.upper[axis] - centroidBounds.lower[axis];
            valid[axis] = extent > 0.0f && std::isfinite(extent);
            scale[axis] = valid[axis] ? float(binCount) / extent : 0.0f;
        }
    }
    [[gnu::always_inline]] uint32_t binOf(const glm::vec3& c2, int axis) const {
        // max(0, NaN) is 0 and min(inf, maxBin) is maxBin: NaN or rounding never leaves [0, binCount).
        const float f = (c2[axis] - origin[axis]) * scale[axis];
        return uint32_t(std::min(std::max(0.0f, f), maxBin));
    }
};

struct Bin {
    Aabb bounds;
    uint32_t count = 0;
};

// binCount bins for each of the three axes.
struct BinGrid {
    uint32_t binCount = 0;
    std::vector<Bin> bins;

    void reset(uint32_t count) {
        binCount = count;
        bins.assign(3 * size_t(count), Bin{});
    }
    Bin& at(int axis, uint32_t bin) { return bins[size_t(axis) * binCount + bin]; }
    const Bin& at(int axis, uint32_t bin) const { return bins[size_t(axis) * binCount + bin]; }
    void merge(const BinGrid& other) {
        for (size_t i = 0; i < bins.size(); ++i) {
            bins[i].bounds.grow(other.bins[i].bounds);
            bins[i].count += other.bins[i].count;
        }
    }
};

struct SplitPlan {
    enum class Kind { Leaf, Sah, Median };
    Kind kind = Kind::Leaf;
    int axis = 0;
    uint32_t bin = 0;      // SAH: bins [0, bin] go left
    uint32_t binCount = 0; // SAH: bins per axis used for this node
};

// Bounds of both children, accumulated while partitioning (exact unions of the triangles' bounds).
struct ChildBounds {
    Aabb bounds[2];
    Aabb centroidBounds[2];
    [[gnu::always_inline]] void add(int side, const PrimRef& ref) {
        growBy(bounds[side], ref);
        centroidBounds[side].grow(centroid2(ref));
    }
};

struct BuildContext {
    const BvhBuildOptions& options;
    PrimRef* refs = nullptr;
    uint32_t threads = 1;
    uint32_t leafCap = kForcedSplitTriangles; // no leaf holds more
    Progress& progress;
    std::atomic<uint64_t> trianglesPlaced{0};
};

// The outcome of splitting one node: a leaf, or the partition point and both children's bounds.
struct SplitResult {
    bool leaf = true;
    uint32_t mid = 0;
    ChildBounds children;
};

// Splits nodes (SAH, median fallback, leaf decision, in-place partition) and builds subtrees depth-first.
// One per thread: it owns the scratch bins.
class NodeBuilder {
public:
    explicit NodeBuilder(BuildContext& context) : ctx_(context) {
        bins_.reset(ctx_.options.binCount);
        rightArea_.resize(ctx_.options.binCount);
        rightCount_.resize(ctx_.options.binCount);
    }

    // Decides how to split `task` and partitions its refs accordingly. parallelBinning spreads the binning
    // over all threads (only for large nodes, and only from the calling thread).
    SplitResult splitNode(const BuildTask& task, bool parallelBinning) {
        SplitResult result;
        const SplitPlan plan = planSplit(task, parallelBinning);
        if (plan.kind == SplitPlan::Kind::Leaf) {
            reportLeaf(task.count());
            return result;
        }
        result.leaf = false;
        result.mid = plan.kind == SplitPlan::Kind::Sah ? partitionSah(task, plan, result.children) : task.begin;
        if (result.mid == task.begin || result.mid == task.end) {
            // Median split requested, or (never expected) an SAH partition that left one side empty: the
            // median always makes progress, so the build terminates even on NaN input.
            result.children = ChildBounds{};
            result.mid = partitionMedian(task, result.children);
        }
        return result;
    }

    // Builds the whole subtree of `root`, whose node slot exists in `nodes`, depth-first from an explicit
    // stack (left child first, so every subtree's nodes are contiguous).
    void build(const BuildTask& root, std::vector<BvhNodeGpu>& nodes) {
        std::vector<BuildTask> stack{root};
        while (!stack.empty()) {
            const BuildTask task = stack.back();
            stack.pop_back();
            const SplitResult split = splitNode(task, false);
            if (split.leaf) {
                nodes[task.node] = BvhNodeGpu{task.bounds.lower, task.begin, task.bounds.upper, task.count()};
                continue;
            }
            const auto child = uint32_t(nodes.size());
            nodes.resize(nodes.size() + 2);
            nodes[task.node] = BvhNodeGpu{task.bounds.lower, child, task.bounds.upper, 0u};
            stack.push_back(childTask(task, split, 1, child + 1));
            stack.push_back(childTask(task, split, 0, child));
        }
    }

    static BuildTask childTask(const BuildTask& parent, const SplitResult& split, int side, uint32_t node) {
        return BuildTask{node,
                         side == 0 ? parent.begin : split.mid,
                         side == 0 ? split.mid : parent.end,
                         parent.depth + 1,
                         split.children.bounds[side],
                         split.children.centroidBounds[side]};
    }

    void flushProgress() {
        if (unreported_ != 0) {
            const uint64_t placed = ctx_.trianglesPlaced.fetch_add(unreported_) + unreported_;
            unreported_ = 0;
            ctx_.progress.update(placed);
        }
    }

private:
    SplitPlan planSplit(const BuildTask& task, bool parallelBinning) {
        const BvhBuildOptions& options = ctx_.options;
        const uint32_t n = task.count();
        if (n <= options.maxLeafTriangles) {
            return {SplitPlan::Kind::Leaf};
        }
        // Depth guarantee: median splits from here reach single triangles after ceil(log2 n) levels. Keep
        // depth + 1 + ceil(log2 n) <= kMaxLeafDepth while using SAH; switch this branch to medians otherwise.
        const auto medianLevels = uint32_t(std::bit_width(n - 1));
        if (options.medianSplit || task.depth + 1 + medianLevels > kMaxLeafDepth) {
            return {SplitPlan::Kind::Median};
        }
        // Nodes with fewer triangles than bins get one bin per triangle: more bins could not separate more
        // candidates than there are triangles, and the per-node cost (clearing and sweeping the bins) would
        // dominate the small nodes that make up most of the tree.
        const uint32_t binCount = std::min(options.binCount, n);
        const BinMapping mapping(task.centroidBounds, binCount);
        if (!mapping.valid[0] && !mapping.valid[1] && !mapping.valid[2]) {
            // All centroids coincide: no plane separates them.
            return {n <= ctx_.leafCap ? SplitPlan::Kind::Leaf : SplitPlan::Kind::Median};
        }
        fillBins(task, mapping, binCount, parallelBinning);
        return chooseSahSplit(task, mapping, binCount);
    }

    void binRange(BinGrid& grid, const BinMapping& mapping, uint32_t begin, uint32_t end) const {
        for (uint32_t i = begin; i < end; ++i) {
            const PrimRef& ref = ctx_.refs[i];
            const glm::vec3 c2 = centroid2(ref);
            for (int axis = 0; axis < 3; ++axis) {
                if (mapping.valid[axis]) {
                    Bin& bin = grid.at(axis, mapping.binOf(c2, axis));
                    growBy(bin.bounds, ref);
                    ++bin.count;
                }
            }
        }
    }

    void fillBins(const BuildTask& task, const BinMapping& mapping, uint32_t binCount, bool parallelBinning) {
        bins_.reset(binCount);
        if (!parallelBinning) {
            binRange(bins_, mapping, task.begin, task.end);
            return;
        }
        // Per-worker grids merged afterwards; min/max and integer sums are exact in any order.
        workerBins_.resize(ctx_.threads);
        for (BinGrid& grid : workerBins_) {
            grid.reset(binCount);
        }
        const uint32_t blocks = (task.count() + kBlockTriangles - 1) / kBlockTriangles;
        detail::parallelFor(ctx_.threads, blocks, [&](uint32_t worker, uint32_t block) {
            const uint32_t begin = task.begin + block * kBlockTriangles;
            binRange(workerBins_[worker], mapping, begin, std::min(task.end, begin + kBlockTriangles));
        });
        for (const BinGrid& grid : workerBins_) {
            bins_.merge(grid);
        }
    }

    // SAH over the bin boundaries of all axes, in units of the node's area (no division, so zero-area nodes
    // are fine): C_t A + C_i (A_l N_l + A_r N_r) against the leaf cost C_i N A. Ties keep the first candidate
    // (lowest axis, then lowest bin), which keeps the build deterministic.
    SplitPlan chooseSahSplit(const BuildTask& task, const BinMapping& mapping, uint32_t binCount) {
        const BvhBuildOptions& options = ctx_.options;
        const double nodeArea = surfaceArea(task.bounds);
        double bestCost = std::numeric_limits<double>::infinity();
        SplitPlan best{SplitPlan::Kind::Leaf};
        for (int axis = 0; axis < 3; ++axis) {
            if (!mapping.valid[axis]) {
                continue;
            }
            // Sweep right to left: rightArea_[i], rightCount_[i] describe bins [i, binCount).
            Aabb sweep;
            uint32_t count = 0;
            for (uint32_t i = binCount - 1; i > 0; --i) {
                sweep.grow(bins_.at(axis, i).bounds);
                count += bins_.at(axis, i).count;
                rightArea_[i] = surfaceArea(sweep);
                rightCount_[i] = count;
            }
            // Sweep left to right: candidate `i` puts bins [0, i] left.
            sweep = Aabb{};
            count = 0;
            for (uint32_t i = 0; i + 1 < binCount; ++i) {
                sweep.grow(bins_.at(axis, i).bounds);
                count += bins_.at(axis, i).count;
                if (count == 0 || rightCount_[i + 1] == 0) {
                    continue;
                }
                const double cost = options.traversalCost * nodeArea +
                                    options.intersectionCost * (surfaceArea(sweep) * count + rightArea_[i + 1] * rightCount_[i + 1]);
                if (cost < bestCost) {
                    bestCost = cost;
                    best = {SplitPlan::Kind::Sah, axis, i, binCount};
                }
            }
        }
        const uint32_t n = task.count();
        if (best.kind != SplitPlan::Kind::Sah) {
            return {n <= ctx_.leafCap ? SplitPlan::Kind::Leaf : SplitPlan::Kind::Median};
        }
        const double leafCost = double(options.intersectionCost) * n * nodeArea;
        if (!(bestCost < leafCost) && n <= ctx_.leafCap) {
            return {SplitPlan::Kind::Leaf};
        }
        return best;
    }

    // Hoare partition by bin, accumulating both children's bounds on the way. Returns the first right ref.
    uint32_t partitionSah(const BuildTask& task, const SplitPlan& plan, ChildBounds& children) const {
        const BinMapping mapping(task.centroidBounds, plan.binCount);
        auto isLeft = [&](const PrimRef& ref) { return mapping.binOf(centroid2(ref), plan.axis) <= plan.bin; };
        PrimRef* refs = ctx_.refs;
        uint32_t i = task.begin;
        uint32_t j = task.end;
        while (true) {
            while (i < j && isLeft(refs[i])) {
                children.add(0, refs[i++]);
            }
            while (i < j && !isLeft(refs[j - 1])) {
                children.add(1, refs[--j]);
            }
            if (i >= j) {
                break;
            }
            std::swap(refs[i], refs[j - 1]);
            children.add(0, refs[i++]);
            children.add(1, refs[--j]);
        }
        assert(i != task.begin && i != task.end && "SAH bins and partition disagree");
        return i;
    }

    // Object median along the widest centroid axis. Ties (and NaN, mapped to -inf so the order stays strict
    // and weak) are broken by original id, so the split does not depend on the refs' current order.
    uint32_t partitionMedian(const BuildTask& task, ChildBounds& children) const {
        const glm::vec3 extent = task.centroidBounds.upper - task.centroidBounds.lower;
        int axis = 0;
        if (extent.y > extent[axis]) {
            axis = 1;
        }
        if (extent.z > extent[axis]) {
            axis = 2;
        }
        auto key = [axis](const PrimRef& ref) {
            const float c = centroid2(ref)[axis];
            return std::isnan(c) ? -std::numeric_limits<float>::infinity() : c;
        };
        PrimRef* refs = ctx_.refs;
        const uint32_t mid = task.begin + task.count() / 2;
        std::nth_element(refs + task.begin, refs + mid, refs + task.end, [&](const PrimRef& a, const PrimRef& b) {
            const float ka = key(a);
            const float kb = key(b);
            return ka < kb || (ka == kb && a.id < b.id);
        });
        for (uint32_t i = task.begin; i < task.end; ++i) {
            children.add(i < mid ? 0 : 1, refs[i]);
        }
        return mid;
    }

    void reportLeaf(uint32_t triangles) {
        unreported_ += triangles;
        if (unreported_ >= kProgressStep) {
            flushProgress();
        }
    }

    BuildContext& ctx_;
    BinGrid bins_;
    std::vector<BinGrid> workerBins_;
    std::vector<double> rightArea_;
    std::vector<uint32_t> rightCount_;
    uint64_t unreported_ = 0;
};

void checkInput(const Scene& scene, const BvhBuildOptions& options) {
    if (scene.triangles.empty()) {
        throw InputError("scene has no triangles");
    }
    if (scene.triangles.size() > kMaxTriangles) {
        throw InputError("scene has too many triangles for one BVH (" + std::to_string(scene.triangles.size()) + ")");
    }
    if (scene.triangleMaterials.size() != scene.triangles.size()) {
        throw InputError("scene has " + std::to_string(scene.triangleMaterials.size()) + " triangle materials for " +
                         std::to_string(scene.triangles.size()) + " triangles");
    }
    if (options.binCount < 2 || options.maxLeafTriangles == 0) {
        throw InputError("BVH options need binCount >= 2 and maxLeafTriangles >= 1");
    }
}

// One PrimRef per triangle (in parallel) and the root task's bounds. Throws InputError on an out-of-range
// vertex index, so a malformed scene cannot make the builder read out of bounds.
BuildTask makePrimRefs(const Scene& scene, uint32_t threads, std::vector<PrimRef>& refs) {
    const auto n = uint32_t(scene.triangles.size());
    refs.resize(n);
    const size_t vertexCount = scene.positions.size();
    std::vector<BuildTask> partial(threads);
    std::vector<uint8_t> badIndex(threads, 0);
    const uint32_t blocks = (n + kBlockTriangles - 1) / kBlockTriangles;
    detail::parallelFor(threads, blocks, [&](uint32_t worker, uint32_t block) {
        const uint32_t end = std::min(n, (block + 1) * kBlockTriangles);
        for (uint32_t i = block * kBlockTriangles; i < end; ++i) {
            const glm::uvec3 t = scene.triangles[i];
            if (t.x >= vertexCount || t.y >= vertexCount || t.z >= vertexCount) {
                badIndex[worker] = 1;
                continue;
            }
            const glm::vec3& a = scene.positions[t.x];
            const glm::vec3& b = scene.positions[t.y];
            const glm::vec3& c = scene.positions[t.z];
            PrimRef& ref = refs[i];
            ref = PrimRef{glm::min(a, glm::min(b, c)), i, glm::max(a, glm::max(b, c)), 0u};
            growBy(partial[worker].bounds, ref);
            partial[worker].centroidBounds.grow(centroid2(ref));
        }
    });
    if (std::find(badIndex.begin(), badIndex.end(), 1) != badIndex.end()) {
        throw InputError("scene has a triangle with a vertex index out of range");
    }
    BuildTask root;
    root.end = n;
    for (const BuildTask& p : partial) {
        root.bounds.grow(p.bounds);
        root.centroidBounds.grow(p.centroidBounds);
    }
    return root;
}

// Phase 1: splits the nodes above subtreeTriangles level by level into bvh.nodes (breadth-first numbering)
// and returns the subtree roots below, in a deterministic order.
std::vector<BuildTask> buildTopLevels(const BuildTask& root, std::vector<NodeBuilder>& builders, uint32_t threads,
                                      uint32_t subtreeTriangles, std::vector<BvhNodeGpu>& nodes) {
    std::vector<BuildTask> subtrees;
    std::vector<BuildTask> level;
    (root.count() <= subtreeTriangles ? subtrees : level).push_back(root);
    while (!level.empty()) {
        std::vector<SplitResult> splits(level.size());
        if (level.size() < threads) {
            for (size_t i = 0; i < level.size(); ++i) {
                splits[i] = builders[0].splitNode(level[i], threads > 1 && level[i].count() >= kParallelBinTriangles);
            }
        } else {
            detail::parallelFor(threads, uint32_t(level.size()), [&](uint32_t worker, uint32_t i) {
                splits[i] = builders[worker].splitNode(level[i], false);
            });
        }
        std::vector<BuildTask> next;
        for (size_t i = 0; i < level.size(); ++i) {
            const BuildTask& task = level[i];
            if (splits[i].leaf) {
                nodes[task.node] = BvhNodeGpu{task.bounds.lower, task.begin, task.bounds.upper, task.count()};
                continue;
            }
            const auto child = uint32_t(nodes.size());
            nodes.resize(nodes.size() + 2);
            nodes[task.node] = BvhNodeGpu{task.bounds.lower, child, task.bounds.upper, 0u};
            for (int side = 0; side < 2; ++side) {
                const BuildTask childTask = NodeBuilder::childTask(task, splits[i], side, child + uint32_t(side));
                (childTask.count() <= subtreeTriangles ? subtrees : next).push_back(childTask);
            }
        }
        level = std::move(next);
    }
    return subtrees;
}

// Phase 2: builds the set-aside subtrees in parallel and appends them to bvh.nodes in their original order.
void buildSubtrees(const std::vector<BuildTask>& subtrees, std::vector<NodeBuilder>& builders, uint32_t threads,
                   std::vector<BvhNodeGpu>& nodes) {
    // Largest first, so that one big subtree does not start last.
    std::vector<uint32_t> order(subtrees.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return subtrees[a].count() > subtrees[b].count(); });
    std::vector<std::vector<BvhNodeGpu>> local(subtrees.size());
    detail::parallelFor(threads, uint32_t(subtrees.size()), [&](uint32_t worker, uint32_t k) {
        const uint32_t s = order[k];
        BuildTask task = subtrees[s];
        task.node = 0; // local[s][0] stands for the subtree root, whose slot is nodes[subtrees[s].node]
        local[s].resize(1);
        builders[worker].build(task, local[s]);
    });
    // local[s][i] (i >= 1) goes to nodes[base[s] + i - 1]; local child indices are >= 1.
    std::vector<uint32_t> base(subtrees.size());
    auto size = uint32_t(nodes.size());
    for (size_t s = 0; s < subtrees.size(); ++s) {
        base[s] = size;
        size += uint32_t(local[s].size() - 1);
    }
    nodes.resize(size);
    detail::parallelFor(threads, uint32_t(subtrees.size()), [&](uint32_t, uint32_t s) {
        auto relocate = [&](BvhNodeGpu node) {
            if (node.triCount == 0) {
                node.leftFirst = node.leftFirst - 1 + base[s];
            }
            return node;
        };
        nodes[subtrees[s].node] = relocate(local[s][0]);
        for (size_t i = 1; i < local[s].size(); ++i) {
            nodes[base[s] + i - 1] = relocate(local[s][i]);
        }
        std::vector<BvhNodeGpu>().swap(local[s]);
    });
}

// Output triangles in leaf order (refs are in leaf order now), with original and material ids.
void writeTriangles(const Scene& scene, const std::vector<PrimRef>& refs, uint32_t threads, std::vector<TriangleGpu>& out) {
    const auto n = uint32_t(refs.size());
    out.resize(n);
    const uint32_t blocks = (n + kBlockTriangles - 1) / kBlockTriangles;
    detail::parallelFor(threads, blocks, [&](uint32_t, uint32_t block) {
        const uint32_t end = std::min(n, (block + 1) * kBlockTriangles);
        for (uint32_t i = block * kBlockTriangles; i < end; ++i) {
            const uint32_t id = refs[i].id;
            const glm::uvec3 t = scene.triangles[id];
            out[i] = TriangleGpu{scene.positions[t.x], id, scene.positions[t.y], scene.triangleMaterials[id],
                                 scene.positions[t.z], 0u};
        }
    });
}

} // namespace

Bvh buildBvh(const Scene& scene, const BvhBuildOptions& options, Progress& progress) {
    const auto start = std::chrono::steady_clock::now();
    checkInput(scene, options);
    const uint32_t threads = detail::resolveThreadCount(options.threads);
    const auto n = uint32_t(scene.triangles.size());
    progress.begin("Building BVH", n);

    std::vector<PrimRef> refs;
    const BuildTask root = makePrimRefs(scene, threads, refs);
    BuildContext context{options, refs.data(), threads, std::max(options.maxLeafTriangles, kForcedSplitTriangles), progress};
    std::vector<NodeBuilder> builders;
    builders.reserve(threads);
    for (uint32_t i = 0; i < threads; ++i) {
        builders.emplace_back(context);
    }

    Bvh bvh;
    bvh.nodes.resize(1);
    const uint32_t subtreeTriangles = std::max(kMinSubtreeTriangles, n / kSubtreesPerBuild);
    const std::vector<BuildTask> subtrees = buildTopLevels(root, builders, threads, subtreeTriangles, bvh.nodes);
    buildSubtrees(subtrees, builders, threads, bvh.nodes);
    for (NodeBuilder& builder : builders) {
        builder.flushProgress();
    }
    writeTriangles(scene, refs, threads, bvh.triangles);
    std::vector<PrimRef>().swap(refs);

    detail::measureBvh(bvh, options.traversalCost, options.intersectionCost);
    bvh.stats.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.end();
    return bvh;
}

} // namespace chcrt
