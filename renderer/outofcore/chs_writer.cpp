#include "renderer/outofcore/chs_writer.h"

#include "renderer/core/error.h"
#include "renderer/outofcore/lod_proxies.h"

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <limits>
#include <cstring>
#include <numeric>
#include <unistd.h>

namespace chcrt::outofcore {

// One termination subtree as written (chs_format.h): nodes with local indices, triangles, per-vertex normals and
// texture coordinates; `source` is the BVH node of each local node.
struct SubtreeBlob {
    std::vector<BvhNodeGpu> nodes;
    std::vector<TriangleGpu> tris;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec2> uvs;
    std::vector<uint32_t> source;
};

namespace {

void setBounds(float (&lo)[3], float (&hi)[3], const glm::vec3& a, const glm::vec3& b) {
    for (int k = 0; k < 3; ++k) lo[k] = a[k], hi[k] = b[k];
}

Aabb boundsOf(const ChsUpperNode& n) {
    Aabb b;
    b.lower = {n.boundsMin[0], n.boundsMin[1], n.boundsMin[2]};
    b.upper = {n.boundsMax[0], n.boundsMax[1], n.boundsMax[2]};
    return b;
}

// Top-level tree over chunk root boxes: full-sweep SAH (chunk counts are small). Nodes in BFS order, root 0,
// siblings adjacent; a leaf's `subtree` holds the chunk index.
std::vector<ChsUpperNode> buildTopLevel(const std::vector<Aabb>& boxes) {
    std::vector<ChsUpperNode> nodes(1);
    std::vector<uint32_t> items(boxes.size());
    std::iota(items.begin(), items.end(), 0u);
    struct Task { uint32_t node, begin, end; };
    std::vector<Task> queue{{0, 0, uint32_t(items.size())}};
    for (size_t q = 0; q < queue.size(); ++q) {
        const Task t = queue[q];
        Aabb all;
        for (uint32_t i = t.begin; i < t.end; ++i) all.grow(boxes[items[i]]);
        ChsUpperNode& n = nodes[t.node];
        setBounds(n.boundsMin, n.boundsMax, all.lower, all.upper);
        if (t.end - t.begin == 1) {
            n.firstChild = 0;
            n.subtree = items[t.begin];
            continue;
        }
        float best = std::numeric_limits<float>::infinity();
        int bestAxis = 0;
        uint32_t bestSplit = t.begin + (t.end - t.begin) / 2;
        for (int axis = 0; axis < 3; ++axis) {
            std::sort(items.begin() + t.begin, items.begin() + t.end, [&](uint32_t a, uint32_t b) {
                const float ca = boxes[a].center()[axis], cb = boxes[b].center()[axis];
                return ca < cb || (ca == cb && a < b);
            });
            std::vector<float> rightArea(t.end - t.begin + 1, 0.0f);
            Aabb right;
            for (uint32_t i = t.end; i-- > t.begin + 1;) {
                right.grow(boxes[items[i]]);
                rightArea[i - t.begin] = right.area() * float(t.end - i);
            }
            Aabb left;
            for (uint32_t i = t.begin + 1; i < t.end; ++i) {
                left.grow(boxes[items[i - 1]]);
                const float cost = left.area() * float(i - t.begin) + rightArea[i - t.begin];
                if (cost < best) best = cost, bestAxis = axis, bestSplit = i;
            }
        }
        std::sort(items.begin() + t.begin, items.begin() + t.end, [&](uint32_t a, uint32_t b) {
            const float ca = boxes[a].center()[bestAxis], cb = boxes[b].center()[bestAxis];
            return ca < cb || (ca == cb && a < b);
        });
        n.firstChild = uint32_t(nodes.size());
        n.subtree = kChsNoSubtree;
        const uint32_t child = uint32_t(nodes.size());
        nodes.resize(nodes.size() + 2);
        queue.push_back({child, t.begin, bestSplit});
        queue.push_back({child + 1, bestSplit, t.end});
    }
    return nodes;
}

// Height (edges to the deepest leaf) and triangle count of every BVH node, bottom-up (children have larger
// indices than their parents).
struct NodeExtents {
    std::vector<uint32_t> height, count;
};

NodeExtents nodeExtents(const Bvh& bvh) {
    const size_t n = bvh.nodes.size();
    NodeExtents e{std::vector<uint32_t>(n, 0), std::vector<uint32_t>(n, 0)};
    for (size_t i = n; i-- > 0;) {
        const BvhNodeGpu& node = bvh.nodes[i];
        if (node.triCount != 0) {
            e.count[i] = node.triCount;
            continue;
        }
        e.height[i] = 1 + std::max(e.height[node.leftFirst], e.height[node.leftFirst + 1]);
        e.count[i] = e.count[node.leftFirst] + e.count[node.leftFirst + 1];
    }
    return e;
}

// Where a chunk's triangles land in the file: original ids offset, positions moved by `translation`.
struct ChunkPlacement {
    uint64_t idOffset;
    glm::vec3 translation;
    bool moved; // translation != 0
    bool hasUv; // the scene has texture coordinates
};

// Copies the subtree under BVH node `root` into `blob` in breadth-first order with local indices.
void copySubtree(const Scene& scene, const Bvh& bvh, uint32_t root, const ChunkPlacement& placement,
                 SubtreeBlob& blob) {
    blob.nodes.clear(), blob.tris.clear(), blob.normals.clear(), blob.uvs.clear(), blob.source.assign(1, root);
    blob.nodes.push_back(bvh.nodes[root]);
    for (size_t k = 0; k < blob.source.size(); ++k) {
        const BvhNodeGpu& s = bvh.nodes[blob.source[k]];
        if (s.triCount != 0) {
            blob.nodes[k].leftFirst = uint32_t(blob.tris.size());
            for (uint32_t t = 0; t < s.triCount; ++t) {
                TriangleGpu tri = bvh.triangles[s.leftFirst + t];
                const glm::uvec3 idx = scene.triangles[tri.originalId];
                for (int v = 0; v < 3; ++v) {
                    blob.normals.push_back(scene.normals[idx[v]]);
                    if (placement.hasUv) blob.uvs.push_back(scene.texcoords[idx[v]]);
                }
                tri.originalId = uint32_t(tri.originalId + placement.idOffset);
                if (placement.moved) {
                    tri.v0 += placement.translation, tri.v1 += placement.translation, tri.v2 += placement.translation;
                }
                blob.tris.push_back(tri);
            }
        } else {
            blob.nodes[k].leftFirst = uint32_t(blob.nodes.size());
            blob.nodes.push_back(bvh.nodes[s.leftFirst]);
            blob.nodes.push_back(bvh.nodes[s.leftFirst + 1]);
            blob.source.push_back(s.leftFirst);
            blob.source.push_back(s.leftFirst + 1);
        }
    }
}

// Boxes of a moved subtree from its moved triangles, bottom-up (exactly conservative after rounding).
void refitBoxes(SubtreeBlob& blob) {
    std::vector<BvhNodeGpu>& nodes = blob.nodes;
    for (size_t k = nodes.size(); k-- > 0;) {
        Aabb b;
        if (nodes[k].triCount != 0) {
            for (uint32_t t = 0; t < nodes[k].triCount; ++t) {
                const TriangleGpu& tri = blob.tris[nodes[k].leftFirst + t];
                b.grow(tri.v0), b.grow(tri.v1), b.grow(tri.v2);
            }
        } else {
            for (uint32_t c = 0; c < 2; ++c) {
                b.grow(nodes[nodes[k].leftFirst + c].boundsMin);
                b.grow(nodes[nodes[k].leftFirst + c].boundsMax);
            }
        }
        nodes[k].boundsMin = b.lower, nodes[k].boundsMax = b.upper;
    }
}

// Boxes of a chunk's upper nodes, bottom-up (BFS order: children after parents): termination roots take their
// subtree's box; inner nodes the union of their children's, or, unmoved, exactly the builder's box of their BVH
// node (cut[i] = (BVH node, upper node i)).
void fitUpperBoxes(std::vector<ChsUpperNode>& upper, const std::vector<ChsSubtreeRecord>& records, const Bvh& bvh,
                   const std::vector<std::pair<uint32_t, uint32_t>>& cut, bool moved) {
    for (size_t i = upper.size(); i-- > 0;) {
        ChsUpperNode& u = upper[i];
        if (u.subtree != kChsNoSubtree) {
            std::memcpy(u.boundsMin, records[u.subtree].boundsMin, sizeof(u.boundsMin));
            std::memcpy(u.boundsMax, records[u.subtree].boundsMax, sizeof(u.boundsMax));
            continue;
        }
        Aabb b = boundsOf(upper[u.firstChild]);
        b.grow(boundsOf(upper[u.firstChild + 1]));
        if (!moved) {
            const BvhNodeGpu& original = bvh.nodes[cut[i].first];
            b.lower = original.boundsMin, b.upper = original.boundsMax;
        }
        setBounds(u.boundsMin, u.boundsMax, b.lower, b.upper);
    }
}

} // namespace

ChsWriter::ChsWriter(const std::filesystem::path& file, const ChsWriterOptions& options)
    : file_(file), temp_(file.string() + ".tmp"), removeTempOnSignal_(temp_), options_(options) {
    if (options.subtreeTriangles == 0 || options.subtreeHeight == 0) {
        throw InputError("prepare: --subtree-triangles and --subtree-height must be positive");
    }
    if (options.lodLevels > kMaxLodLevels) {
        throw InputError("prepare: --lod-levels must be at most " + std::to_string(kMaxLodLevels));
    }
    if (options.subtreeHeight >= CHCRT_MAX_BVH_DEPTH) {
        throw InputError("prepare: --subtree-height must be below " + std::to_string(CHCRT_MAX_BVH_DEPTH));
    }
    out_ = std::fopen(temp_.c_str(), "wb");
    if (!out_) throw InputError("cannot create " + temp_.string() + ": " + std::strerror(errno));
    const ChsHeader placeholder{};
    write(&placeholder, sizeof(placeholder));
}

ChsWriter::~ChsWriter() {
    if (out_) std::fclose(out_);
    if (!finished_) {
        std::error_code ignored;
        std::filesystem::remove(temp_, ignored);
    }
}

void ChsWriter::write(const void* data, size_t bytes) {
    if (bytes != 0 && std::fwrite(data, 1, bytes, out_) != bytes) {
        throw InputError("writing " + temp_.string() + " failed: " + std::strerror(errno));
    }
    offset_ += bytes;
}

void ChsWriter::checkChunk(const Scene& scene, uint64_t idOffset) {
    const bool hasUv = !scene.texcoords.empty();
    if (texcoordsKnown_ && hasUv != texcoords_) throw InputError("prepare: chunks disagree on texture coordinates");
    texcoords_ = hasUv;
    texcoordsKnown_ = true;
    if (idOffset + scene.triangles.size() >= uint64_t(CHCRT_NO_HIT_ID)) {
        throw InputError("prepare: more than 4294967294 triangles (triangle ids are 32-bit)");
    }
}

uint64_t ChsWriter::writeBlob(const std::vector<BvhNodeGpu>& nodes, const std::vector<TriangleGpu>& triangles,
                              const std::vector<glm::vec3>& normals, const std::vector<glm::vec2>& texcoords) {
    uint64_t sum = 0;
    auto put = [&](const void* data, size_t bytes) {
        sum = chsChecksum(data, bytes, sum);
        write(data, bytes);
    };
    if (options_.compact) {
        encodeCompactSubtree(nodes, triangles, compact_);
        put(compact_.nodes.data(), compact_.nodes.size() * sizeof(glm::uvec4));
        put(compact_.triangles.data(), compact_.triangles.size() * sizeof(glm::uvec4));
        put(compact_.vertices.data(), compact_.vertices.size() * sizeof(glm::vec3));
        put(compact_.materials.data(), compact_.materials.size() * sizeof(uint32_t));
        lastBlobVertices_ = compact_.vertices.size();
    } else {
        put(nodes.data(), nodes.size() * sizeof(BvhNodeGpu));
        put(triangles.data(), triangles.size() * sizeof(TriangleGpu));
    }
    put(normals.data(), normals.size() * sizeof(glm::vec3));
    put(texcoords.data(), texcoords.size() * sizeof(glm::vec2));
    return sum;
}

uint32_t ChsWriter::writeSubtree(const SubtreeBlob& blob, uint32_t height) {
    ChsSubtreeRecord record{};
    record.offset = offset_;
    record.nodeCount = uint32_t(blob.nodes.size());
    record.triangleCount = uint32_t(blob.tris.size());
    record.height = height;
    setBounds(record.boundsMin, record.boundsMax, blob.nodes[0].boundsMin, blob.nodes[0].boundsMax);
    const size_t before = offset_;
    record.checksum = writeBlob(blob.nodes, blob.tris, blob.normals, blob.uvs);
    record.bytes = offset_ - before;
    vertices_ += lastBlobVertices_;
    subtreeBytes_ += record.bytes;
    records_.push_back(record);
    triangles_ += blob.tris.size();
    nodes_ += blob.nodes.size();
    maxNodes_ = std::max(maxNodes_, uint32_t(blob.nodes.size()));
    maxTriangles_ = std::max(maxTriangles_, uint32_t(blob.tris.size()));
    writeProxies(blob);
    return uint32_t(records_.size() - 1);
}

// The subtree's LOD proxies right after it (lod_proxies.h): a far view that uses a subtree's proxy reads only it.
void ChsWriter::writeProxies(const SubtreeBlob& blob) {
    if (options_.lodLevels == 0) return;
    const std::vector<LodProxy> proxies = buildLodProxies(blob.tris, blob.normals, blob.uvs, options_.lodLevels);
    for (const LodProxy& p : proxies) {
        ChsLodRecord r{};
        r.errorWorld = p.errorWorld;
        if (!p.empty()) {
            r.offset = offset_;
            r.nodeCount = uint32_t(p.nodes.size());
            r.triangleCount = uint32_t(p.triangles.size());
            r.checksum = writeBlob(p.nodes, p.triangles, p.normals, p.texcoords);
            r.bytes = offset_ - r.offset;
            proxyBytes_ += r.bytes;
            ++proxyCount_;
            maxProxyNodes_ = std::max(maxProxyNodes_, r.nodeCount);
            maxProxyTriangles_ = std::max(maxProxyTriangles_, r.triangleCount);
        }
        lodRecords_.push_back(r);
    }
}

void ChsWriter::addChunk(const Scene& scene, const Bvh& bvh, uint64_t idOffset, const glm::vec3& translation) {
    checkChunk(scene, idOffset);
    const ChunkPlacement placement{idOffset, translation, translation != glm::vec3(0.0f), !scene.texcoords.empty()};
    const NodeExtents extents = nodeExtents(bvh);
    Chunk chunk;
    chunk.nodes.resize(1);
    SubtreeBlob blob; // reused for every subtree of the chunk
    // Breadth-first over the upper part; (bvh node, chunk node): entry i is chunk node i.
    std::vector<std::pair<uint32_t, uint32_t>> queue{{0u, 0u}};
    for (size_t q = 0; q < queue.size(); ++q) {
        const auto [bvhNode, upperIndex] = queue[q];
        const BvhNodeGpu& node = bvh.nodes[bvhNode];
        const bool fits = extents.height[bvhNode] <= options_.subtreeHeight &&
                          extents.count[bvhNode] <= options_.subtreeTriangles;
        if (!(fits || node.triCount != 0)) {
            const uint32_t child = uint32_t(chunk.nodes.size());
            chunk.nodes.resize(chunk.nodes.size() + 2);
            chunk.nodes[upperIndex].firstChild = child;
            chunk.nodes[upperIndex].subtree = kChsNoSubtree;
            queue.push_back({node.leftFirst, child});
            queue.push_back({node.leftFirst + 1, child + 1});
            continue;
        }
        copySubtree(scene, bvh, bvhNode, placement, blob);
        if (placement.moved) refitBoxes(blob);
        ChsUpperNode& u = chunk.nodes[upperIndex];
        u.firstChild = 0;
        u.subtree = writeSubtree(blob, extents.height[bvhNode]);
    }
    fitUpperBoxes(chunk.nodes, records_, bvh, queue, placement.moved);
    chunks_.push_back(std::move(chunk));
}

uint64_t ChsWriter::finish(const ChsSceneInfo& info) {
    if (chunks_.empty()) throw InputError("prepare: the scene has no triangles");
    // Join the chunks: top-level tree over their roots, then each chunk's upper nodes, breadth-first.
    std::vector<Aabb> boxes;
    for (const Chunk& c : chunks_) boxes.push_back(boundsOf(c.nodes[0]));
    const std::vector<ChsUpperNode> top = buildTopLevel(boxes);
    std::vector<ChsUpperNode> upper(1);
    struct Item { int chunk; uint32_t node, out; }; // chunk -1: top-level node
    std::vector<Item> queue{{-1, 0, 0}};
    for (size_t q = 0; q < queue.size(); ++q) {
        Item item = queue[q];
        if (item.chunk < 0 && top[item.node].subtree != kChsNoSubtree) item = {int(top[item.node].subtree), 0, item.out};
        const ChsUpperNode& src = item.chunk < 0 ? top[item.node] : chunks_[item.chunk].nodes[item.node];
        ChsUpperNode& dst = upper[item.out];
        dst = src;
        if (item.chunk >= 0 && src.subtree != kChsNoSubtree) {
            records_[src.subtree].upperNode = item.out;
            continue;
        }
        const uint32_t child = uint32_t(upper.size());
        upper[item.out].firstChild = child;
        upper.resize(upper.size() + 2);
        queue.push_back({item.chunk, src.firstChild, child});
        queue.push_back({item.chunk, src.firstChild + 1, child + 1});
    }
    chunks_.clear();
    // Directory in increasing upper-node order (the order of SubtreePartition::roots() over the loaded BVH,
    // whose first nodes are the upper nodes), whatever order the parts were written in.
    std::vector<uint32_t> order(records_.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return records_[a].upperNode < records_[b].upperNode; });
    std::vector<ChsSubtreeRecord> sorted;
    std::vector<ChsLodRecord> sortedLod; // each subtree's levels move with it
    const uint32_t levels = options_.lodLevels;
    for (uint32_t i : order) {
        sorted.push_back(records_[i]);
        for (uint32_t l = 0; l < levels; ++l) sortedLod.push_back(lodRecords_[size_t(i) * levels + l]);
    }
    records_ = std::move(sorted);
    lodRecords_ = std::move(sortedLod);
    for (uint32_t i = 0; i < records_.size(); ++i) upper[records_[i].upperNode].subtree = i;

    ChsHeader h{};
    std::memcpy(h.magic, kChsMagic, sizeof(h.magic));
    const bool lod = levels != 0;
    h.version = options_.compact ? kChsVersionCompact : lod ? kChsVersionLod : kChsVersion;
    h.headerBytes = sizeof(ChsHeader);
    h.flags = (texcoords_ ? kChsFlagTexcoords : 0u) | (info.hasCamera ? kChsFlagCamera : 0u) | (lod ? kChsFlagLod : 0u) |
              (options_.compact ? kChsFlagCompact : 0u);
    h.subtreeCount = uint32_t(records_.size());
    h.upperNodeCount = uint32_t(upper.size());
    h.materialCount = uint32_t(info.materials.size());
    h.triangleCount = triangles_;
    h.nodeCount = nodes_;
    h.subtreeTriangleLimit = options_.subtreeTriangles;
    h.subtreeHeightLimit = options_.subtreeHeight;
    h.maxSubtreeNodes = maxNodes_;
    h.maxSubtreeTriangles = maxTriangles_;
    std::memcpy(h.boundsMin, upper[0].boundsMin, sizeof(h.boundsMin));
    std::memcpy(h.boundsMax, upper[0].boundsMax, sizeof(h.boundsMax));
    const glm::vec3 light[4] = {info.light.corner, info.light.edgeU, info.light.edgeV, info.light.radiance};
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k) h.light[i * 3 + k] = light[i][k];
    const glm::vec3 cam[3] = {info.camera.eye, info.camera.target, info.camera.up};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) h.camera[i * 3 + k] = cam[i][k];
    h.camera[9] = info.camera.fovYDegrees;
    h.sourceBytes = uint32_t(info.source.size());
    h.chunkCount = uint32_t(boxes.size());

    std::vector<ChsMaterialRecord> materials(info.materials.size());
    for (size_t i = 0; i < materials.size(); ++i) {
        for (int k = 0; k < 4; ++k) materials[i].baseColor[k] = info.materials[i].baseColorFactor[k];
        materials[i].texture = info.materials[i].baseColorTexture;
        std::strncpy(materials[i].name, info.materials[i].name.c_str(), sizeof(materials[i].name) - 1);
    }
    h.metaOffset = offset_;
    uint64_t sum = chsChecksum(upper.data(), upper.size() * sizeof(ChsUpperNode));
    sum = chsChecksum(records_.data(), records_.size() * sizeof(ChsSubtreeRecord), sum);
    sum = chsChecksum(materials.data(), materials.size() * sizeof(ChsMaterialRecord), sum);
    sum = chsChecksum(info.source.data(), info.source.size(), sum);
    ChsLodHeader lodHeader{};
    if (lod) {
        lodHeader = {levels, kLodCoarsestRatio, maxProxyNodes_, maxProxyTriangles_, proxyBytes_, 0};
        sum = chsChecksum(&lodHeader, sizeof(lodHeader), sum);
        sum = chsChecksum(lodRecords_.data(), lodRecords_.size() * sizeof(ChsLodRecord), sum);
    }
    write(upper.data(), upper.size() * sizeof(ChsUpperNode));
    write(records_.data(), records_.size() * sizeof(ChsSubtreeRecord));
    write(materials.data(), materials.size() * sizeof(ChsMaterialRecord));
    write(info.source.data(), info.source.size());
    if (lod) {
        write(&lodHeader, sizeof(lodHeader));
        write(lodRecords_.data(), lodRecords_.size() * sizeof(ChsLodRecord));
    }
    h.metaBytes = offset_ - h.metaOffset;
    h.metaChecksum = sum;
    h.fileBytes = offset_;
    h.headerChecksum = chsChecksum(&h, offsetof(ChsHeader, headerChecksum));
    if (std::fseek(out_, 0, SEEK_SET) != 0 || std::fwrite(&h, sizeof(h), 1, out_) != 1 || std::fflush(out_) != 0 ||
        ::fsync(fileno(out_)) != 0) {
        throw InputError("writing " + temp_.string() + " failed: " + std::strerror(errno));
    }
    std::fclose(out_);
    out_ = nullptr;
    std::error_code error;
    std::filesystem::rename(temp_, file_, error);
    if (error) throw InputError("cannot rename " + temp_.string() + " to " + file_.string() + ": " + error.message());
    finished_ = true;
    return h.fileBytes;
}

} // namespace chcrt::outofcore
