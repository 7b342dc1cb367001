#include "linespace/ntree.h"

#include "linespace/binary_linespace.h"
#include "linespace/shaft_geometry.h"
#include "linespace/shaft_index.h"
#include "renderer/core/error.h"
#include "renderer/core/memory_budget.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <thread>

namespace chcrt::ls {

std::string NTreeParams::toString() const {
    return "NTree(N=" + std::to_string(n) + ", d=" + std::to_string(depth) + ")";
}

std::string NTreeStats::summary() const {
    char line[320];
    std::snprintf(line, sizeof(line),
                  "%u nodes (%u with a Line Space), build %.2f s: binary %.1f%% filled, Line Spaces %.2f MB, nodes %.2f MB",
                  nodeCount, subdividedCount, buildSeconds,
                  binaryShafts ? 100.0 * double(binaryFilled) / double(binaryShafts) : 0.0,
                  double(lineSpaceBytes) / 1e6, double(nodeBytes) / 1e6);
    return line;
}

bool NTree::binaryFilled(uint32_t space, uint32_t symmetricShaft) const {
    const uint32_t word = binaryWords[size_t(space) * lsWordCount(params.n, true) + symmetricShaft / 32u];
    return ((word >> (symmetricShaft & 31u)) & 1u) != 0u;
}

namespace {

// Splits `parent` into N^3 children and distributes its triangles (exact triangle/cube overlap).
void subdivide(NTree& tree, const Bvh& bvh, uint32_t parent) {
    const uint32_t n = tree.params.n;
    const NTreeNode p = tree.nodes[parent];
    const float childSize = p.size / static_cast<float>(n);
    const uint32_t first = static_cast<uint32_t>(tree.nodes.size());
    tree.nodes[parent].firstChild = first;
    std::vector<std::vector<uint32_t>> lists(size_t(n) * n * n);
    auto cellOf = [&](float x, int axis) {
        const float c = std::floor((x - p.lower[axis]) / childSize);
        return static_cast<uint32_t>(std::clamp(c, 0.0f, static_cast<float>(n - 1)));
    };
    for (uint32_t r = 0; r < p.triangleCount; ++r) {
        const uint32_t triangle = tree.triangleRefs[p.firstTriangle + r];
        const TriangleGpu& t = bvh.triangles[triangle];
        const glm::vec3 lo = glm::min(glm::min(t.v0, t.v1), t.v2), hi = glm::max(glm::max(t.v0, t.v1), t.v2);
        for (uint32_t z = cellOf(lo.z, 2); z <= cellOf(hi.z, 2); ++z) {
            for (uint32_t y = cellOf(lo.y, 1); y <= cellOf(hi.y, 1); ++y) {
                for (uint32_t x = cellOf(lo.x, 0); x <= cellOf(hi.x, 0); ++x) {
                    const glm::vec3 cellLower = p.lower + childSize * glm::vec3(float(x), float(y), float(z));
                    const BoxD cell{glm::dvec3(cellLower), glm::dvec3(cellLower + glm::vec3(childSize))};
                    // A shaft from a box to itself is the box: the exact triangle/box test.
                    if (shaftOverlapsTriangle(ShaftVolume(cell, cell), t.v0, t.v1, t.v2)) {
                        lists[(size_t(z) * n + y) * n + x].push_back(triangle);
                    }
                }
            }
        }
    }
    for (uint32_t z = 0; z < n; ++z) {
        for (uint32_t y = 0; y < n; ++y) {
            for (uint32_t x = 0; x < n; ++x) {
                const std::vector<uint32_t>& list = lists[(size_t(z) * n + y) * n + x];
                NTreeNode child;
                child.lower = p.lower + childSize * glm::vec3(float(x), float(y), float(z));
                child.size = childSize;
                child.level = p.level + 1;
                child.firstTriangle = static_cast<uint32_t>(tree.triangleRefs.size());
                child.triangleCount = static_cast<uint32_t>(list.size());
                tree.triangleRefs.insert(tree.triangleRefs.end(), list.begin(), list.end());
                tree.nodes.push_back(child);
            }
        }
    }
}

struct ChildBox {
    glm::dvec3 lower, upper;
};

// Block recursion as in binary_linespace.cpp, over the non-empty child boxes still overlapping the block. The
// boxes of a block are pool[begin, end); a block appends its own subset to the pool and truncates it on return
// (one allocation per node instead of one per block).
void fillBlock(const Aabb& box, uint32_t n, double dilation, PatchRect a, PatchRect b, std::vector<ChildBox>& pool,
               size_t begin, size_t end, std::vector<uint8_t>& filled) {
    const ShaftVolume volume(patchRegion(box, n, a, dilation), patchRegion(box, n, b, dilation));
    const size_t mark = pool.size();
    for (size_t i = begin; i < end; ++i) {
        if (shaftOverlapsBox(volume, pool[i].lower, pool[i].upper)) {
            const ChildBox c = pool[i]; // copy first: push_back may reallocate
            pool.push_back(c);
        }
    }
    const size_t count = pool.size() - mark;
    if (count == 0) {
        return;
    }
    if (a.count() == 1 && b.count() == 1) {
        filled[lsShaftIndexFromPatches(a.face, a.v0 * n + a.u0, b.face, b.v0 * n + b.u0, n, true)] = 1;
        pool.resize(mark);
        return;
    }
    PatchRect& larger = a.count() >= b.count() ? a : b;
    PatchRect first = larger, second = larger;
    if (larger.u1 - larger.u0 >= larger.v1 - larger.v0) {
        first.u1 = second.u0 = (larger.u0 + larger.u1) / 2;
    } else {
        first.v1 = second.v0 = (larger.v0 + larger.v1) / 2;
    }
    const bool splitA = &larger == &a;
    fillBlock(box, n, dilation, splitA ? first : a, splitA ? b : first, pool, mark, mark + count, filled);
    fillBlock(box, n, dilation, splitA ? second : a, splitA ? b : second, pool, mark, mark + count, filled);
    pool.resize(mark);
}

} // namespace

NTreeNode nTreeRoot(const Bvh& bvh) {
    // Cubic root over the scene bounds (§3.2: cubic nodes simplify building and traversal).
    const Aabb sceneBounds = bvh.rootBounds();
    const glm::vec3 extent = sceneBounds.extent();
    NTreeNode root;
    root.size = std::max({extent.x, extent.y, extent.z, 1e-6f});
    root.lower = sceneBounds.center() - glm::vec3(0.5f * root.size);
    root.triangleCount = static_cast<uint32_t>(bvh.triangles.size());
    return root;
}

void computeNTreeStats(NTree& tree) {
    const uint32_t n = tree.params.n;
    uint32_t subdivided = 0;
    for (const NTreeNode& node : tree.nodes) {
        subdivided += node.space != kNoChild ? 1u : 0u;
    }
    NTreeStats& stats = tree.stats;
    stats.nodeCount = static_cast<uint32_t>(tree.nodes.size());
    stats.subdividedCount = subdivided;
    stats.triangleRefs = tree.triangleRefs.size();
    stats.binaryShafts = uint64_t(subdivided) * lsShaftCount(n, true);
    stats.binaryFilled = 0;
    for (const uint32_t w : tree.binaryWords) {
        stats.binaryFilled += static_cast<uint64_t>(std::popcount(w));
    }
    stats.lineSpaceBytes = 4ull * tree.binaryWords.size();
    stats.nodeBytes = 32ull * subdivided + 4ull * subdivided * n * n * n;
}

NTree buildNTree(const Bvh& bvh, const NTreeParams& params, Progress& progress) {
    if (params.n < 2 || params.n > CHCRT_LS_MAX_N || params.depth == 0) {
        throw InputError("N-tree needs N in 2.." + std::to_string(CHCRT_LS_MAX_N) + " and depth >= 1");
    }
    const auto start = std::chrono::steady_clock::now();
    NTree tree;
    tree.params = params;
    const Aabb sceneBounds = bvh.rootBounds();
    const NTreeNode root = nTreeRoot(bvh);
    for (uint32_t i = 0; i < root.triangleCount; ++i) {
        tree.triangleRefs.push_back(i);
    }
    tree.nodes.push_back(root);
    const uint32_t n = params.n, words = lsWordCount(n, true);
    // How large the tree grows depends on where the triangles lie, so no estimate up front can bound it without
    // refusing the papers' parameters (N = 10, depth 4 allows 10^12 nodes; a city fills a small fraction): the
    // memory budget (--max-memory-mb) is checked before each subdivision instead, with what the tree holds so far,
    // the node's children and the Line Spaces of the nodes subdivided so far, twice (the host's copy and the GPU's).
    const uint64_t lineSpaceBytes = 4ull * words;
    const uint64_t childrenBytes = uint64_t(n) * n * n * sizeof(NTreeNode);
    const std::string what = "the N-tree " + params.toString() + " (built so far, host and GPU)";
    // Level by level: every non-empty node above the leaf level is subdivided.
    std::vector<uint32_t> subdivided;
    for (uint32_t node = 0; node < tree.nodes.size(); ++node) {
        if (tree.nodes[node].level < params.depth && tree.nodes[node].triangleCount > 0) {
            checkMemoryBudget(2 * (tree.nodes.size() * sizeof(NTreeNode) + childrenBytes +
                                   tree.triangleRefs.size() * sizeof(uint32_t) +
                                   (subdivided.size() + 1) * lineSpaceBytes),
                              what);
            tree.nodes[node].space = static_cast<uint32_t>(subdivided.size());
            subdivided.push_back(node);
            subdivide(tree, bvh, node);
        }
    }
    // Binary Line Spaces of the subdivided nodes, in parallel over nodes.
    const double dilation = shaftDilationForScene(sceneBounds);
    tree.binaryWords.assign(subdivided.size() * size_t(words), 0u);
    std::atomic<size_t> next{0}, done{0};
    progress.begin("Line Space " + params.toString(), subdivided.size());
    auto worker = [&] {
        std::vector<uint8_t> filled;
        for (size_t space = next++; space < subdivided.size(); space = next++) {
            const NTreeNode& node = tree.nodes[subdivided[space]];
            std::vector<ChildBox> children;
            for (uint32_t c = 0; c < n * n * n; ++c) {
                const NTreeNode& child = tree.nodes[node.firstChild + c];
                if (child.triangleCount > 0) {
                    children.push_back({glm::dvec3(child.lower), glm::dvec3(child.lower + glm::vec3(child.size))});
                }
            }
            filled.assign(lsShaftCount(n, true), 0);
            for (uint32_t pair = 0; pair < kFacePairCount; ++pair) {
                uint32_t f1 = 0, f2 = 0;
                facePairFaces(pair, f1, f2);
                fillBlock(node.bounds(), n, dilation, PatchRect{f1, 0, n, 0, n}, PatchRect{f2, 0, n, 0, n}, children, 0,
                          children.size(), filled);
            }
            const std::vector<uint32_t> packed = packBits(filled);
            std::copy(packed.begin(), packed.end(), tree.binaryWords.begin() + std::ptrdiff_t(space * words));
            progress.update(++done);
        }
    };
    const uint32_t threadCount = std::max(1u, params.threads != 0 ? params.threads : std::thread::hardware_concurrency());
    std::vector<std::thread> threads;
    for (uint32_t t = 1; t < threadCount; ++t) {
        threads.emplace_back(worker);
    }
    worker();
    for (std::thread& t : threads) {
        t.join();
    }
    progress.end();

    computeNTreeStats(tree);
    tree.stats.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return tree;
}

} // namespace chcrt::ls
