#include "linespace/ntree_cache.h"

#include "linespace/shaft_index.h"

#include <cmath>
#include <cstdio>
#include <type_traits>

namespace chcrt::ls {

namespace {

// Bump when the payload layout or anything buildNTree computes changes (cell assignment, dilation, bit order).
constexpr uint32_t kVersion = 1;

static_assert(std::is_trivially_copyable_v<NTreeNode> && sizeof(NTreeNode) == 36,
              "NTreeNode is stored as raw bytes: bump kVersion when it changes");

CacheFileHeader makeHeader(const NTreeParams& params, uint64_t inputHash) {
    return makeCacheFileHeader("CHCRTNT1", kVersion, {params.n, params.depth, 0u, 0u, 0u}, inputHash);
}

// Positions are recomputed with the builder's expressions; a tolerance keeps files valid across builds whose
// compilers contract these expressions differently (fused multiply-add), while any real damage is far larger.
bool closeTo(const glm::vec3& a, const glm::vec3& b, float scale) {
    const glm::vec3 d = glm::abs(a - b);
    const float tolerance = 1e-5f * scale;
    return d.x <= tolerance && d.y <= tolerance && d.z <= tolerance; // false for NaN
}

// The tree is what buildNTree makes for this scene and parameters, structurally: every index the GPU pools
// and the traversal follow is in range and the cell geometry is the one the Line Spaces were built for.
bool validStructure(const NTree& tree, const Bvh& bvh) {
    const uint32_t n = tree.params.n, depth = tree.params.depth, cells = n * n * n;
    if (tree.nodes.empty()) return false;
    const NTreeNode root = nTreeRoot(bvh);
    const NTreeNode& stored = tree.nodes[0];
    if (!closeTo(stored.lower, root.lower, root.size) || !(std::abs(stored.size - root.size) <= 1e-5f * root.size) ||
        stored.level != 0 || stored.firstTriangle != 0 || stored.triangleCount != root.triangleCount ||
        tree.triangleRefs.size() < root.triangleCount) {
        return false;
    }
    for (uint32_t i = 0; i < root.triangleCount; ++i) {
        if (tree.triangleRefs[i] != i) return false;
    }
    uint64_t nextChild = 1;
    uint32_t subdivided = 0;
    for (size_t i = 0; i < tree.nodes.size(); ++i) {
        const NTreeNode& node = tree.nodes[i];
        if (node.level > depth || uint64_t(node.firstTriangle) + node.triangleCount > tree.triangleRefs.size()) {
            return false;
        }
        if (node.level < depth && node.triangleCount > 0) {
            if (node.firstChild != nextChild || node.space != subdivided || nextChild + cells > tree.nodes.size()) {
                return false;
            }
            const float childSize = node.size / static_cast<float>(n);
            for (uint32_t z = 0, c = 0; z < n; ++z) {
                for (uint32_t y = 0; y < n; ++y) {
                    for (uint32_t x = 0; x < n; ++x, ++c) {
                        const NTreeNode& child = tree.nodes[node.firstChild + c];
                        const glm::vec3 lower = node.lower + childSize * glm::vec3(float(x), float(y), float(z));
                        if (child.level != node.level + 1 || child.size != childSize ||
                            !closeTo(child.lower, lower, node.size)) {
                            return false;
                        }
                    }
                }
            }
            nextChild += cells;
            ++subdivided;
        } else if (node.firstChild != kNoChild || node.space != kNoChild) {
            return false;
        }
    }
    if (nextChild != tree.nodes.size()) return false;
    for (const uint32_t triangle : tree.triangleRefs) {
        if (triangle >= bvh.triangles.size()) return false;
    }
    const uint32_t words = lsWordCount(n, true), shafts = lsShaftCount(n, true);
    if (tree.binaryWords.size() != size_t(subdivided) * words) return false;
    if (shafts % 32u != 0u) {
        const uint32_t unused = ~((1u << (shafts % 32u)) - 1u);
        for (size_t space = 0; space < subdivided; ++space) {
            if ((tree.binaryWords[space * words + words - 1] & unused) != 0u) return false;
        }
    }
    return true;
}

} // namespace

uint64_t nTreeInputHash(const Bvh& bvh) {
    const Aabb bounds = bvh.rootBounds();
    const float corners[6] = {bounds.lower.x, bounds.lower.y, bounds.lower.z,
                              bounds.upper.x, bounds.upper.y, bounds.upper.z};
    const uint64_t hash = fnv1a64(bvh.triangles.data(), bvh.triangles.size() * sizeof(TriangleGpu));
    return fnv1a64(corners, sizeof(corners), hash);
}

std::filesystem::path nTreeCachePath(const std::filesystem::path& dir, uint64_t inputHash, const NTreeParams& params) {
    char name[96];
    std::snprintf(name, sizeof(name), "ntree_%016llx_N%u_d%u.bin", static_cast<unsigned long long>(inputHash),
                  params.n, params.depth);
    return dir / name;
}

void saveNTreeCache(const std::filesystem::path& file, uint64_t inputHash, const NTree& tree) {
    CacheWriter payload;
    payload.array(tree.nodes);
    payload.array(tree.triangleRefs);
    payload.array(tree.binaryWords);
    payload.value(tree.stats.buildSeconds);
    writeCacheFile(file, makeHeader(tree.params, inputHash), payload.bytes, "N-tree cache");
}

CacheLoad loadNTreeCache(const std::filesystem::path& file, const Bvh& bvh, uint64_t inputHash,
                         const NTreeParams& params, NTree& out) {
    std::vector<uint8_t> bytes;
    if (const CacheLoad read = readCacheFile(file, makeHeader(params, inputHash), bytes); read != CacheLoad::Loaded) {
        return read;
    }
    CacheReader reader(bytes);
    NTree tree;
    tree.params = params;
    double buildSeconds = 0.0;
    if (!reader.array(tree.nodes) || !reader.array(tree.triangleRefs) || !reader.array(tree.binaryWords) ||
        !reader.value(buildSeconds) || !reader.atEnd() || !validStructure(tree, bvh)) {
        return CacheLoad::Corrupt;
    }
    computeNTreeStats(tree);
    tree.stats.buildSeconds = buildSeconds;
    out = std::move(tree);
    return CacheLoad::Loaded;
}

NTree loadOrBuildNTree(const Bvh& bvh, const NTreeParams& params, const std::filesystem::path& cacheDir,
                       Progress& progress, CacheOutcome* outcome) {
    if (cacheDir.empty()) {
        if (outcome != nullptr) *outcome = CacheOutcome::Built;
        return buildNTree(bvh, params, progress);
    }
    const uint64_t hash = nTreeInputHash(bvh);
    const std::filesystem::path file = nTreeCachePath(cacheDir, hash, params);
    return loadOrBuildCached<NTree>([&](NTree& tree) { return loadNTreeCache(file, bvh, hash, params, tree); },
                                    [&] { return buildNTree(bvh, params, progress); },
                                    [&](const NTree& tree) { saveNTreeCache(file, hash, tree); }, outcome);
}

} // namespace chcrt::ls
