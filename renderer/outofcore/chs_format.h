#pragma once
// The prepared scene file (.chs) of out-of-core rendering (CHC+RT §5.4): a fixed header, the termination
// subtrees one after another (each one contiguous, so that one read brings a whole subtree), and at the end a
// metadata block with the BVH's upper part, the subtree directory, the materials and the source spec. The
// metadata comes last because a streaming prepare learns the upper part only after every chunk is written;
// the header (rewritten last, then the temp file is renamed) points to it.
//
// Subtree blob: nodes (shaders/shared/bvh_layout.h, indices local to the subtree: root = 0, inner nodes'
// leftFirst = local first child, leaves' leftFirst = local first triangle), triangles (BVH order, original ids
// global), then per triangle the three vertex normals and, when the scene has them, three texture coordinates.
// An upload rebases the local indices by the slot's first node / triangle.
//
// Level-of-detail proxies (version 2, flag kChsFlagLod; issue #19, renderer/outofcore/lod_proxies.h): each subtree's
// proxy levels follow its blob, each a blob of the same layout (so uploads and traversal are the subtree's); the
// metadata ends with a ChsLodHeader and one ChsLodRecord per (subtree, level), subtree-major in directory order.
// Files without proxies are written as version 1, byte for byte as before; both versions are read.
//
// Compact subtrees (version 3, flag kChsFlagCompact, the default of `chcrt prepare`; issue #19,
// renderer/outofcore/compact_subtree.h): every blob (subtrees and proxies alike) holds the node texels of the compact
// layout (shared/bvh_layout.h: nodeCount + 2 texels of 16 bytes, boxes quantized in the root's frame), the triangle
// texels (16 bytes: vertex indices, original id), the subtree's distinct vertices (12 bytes each), then per triangle
// its material id (4 bytes), three vertex normals and, when the scene has them, three texture coordinates. The vertex
// count follows from the record's byte count (chsCompactVertexCount). The first three parts are what the GPU cache
// holds, read with one pread. Version 3 has LOD proxies with kChsFlagLod, as version 2.
//
// All integers little-endian (the only platform this runs on); records are plain structs with fixed sizes.
#include "renderer/bvh/bvh.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace chcrt::outofcore {

inline constexpr char kChsMagic[8] = {'C', 'H', 'C', 'R', 'T', 'S', 'C', 'N'};
inline constexpr uint32_t kChsVersion = 1;    // without LOD proxies
inline constexpr uint32_t kChsVersionLod = 2; // with LOD proxies (kChsFlagLod)
inline constexpr uint32_t kChsVersionCompact = 3; // compact subtrees (kChsFlagCompact), LOD proxies optional
inline constexpr uint32_t kChsNoSubtree = 0xffffffffu;
inline constexpr uint32_t kChsFlagTexcoords = 1u << 0;
inline constexpr uint32_t kChsFlagCamera = 1u << 1;
inline constexpr uint32_t kChsFlagLod = 1u << 2; // version 2: LOD proxies and their directory
inline constexpr uint32_t kChsFlagCompact = 1u << 3; // version 3: blobs in the compact layout

struct ChsHeader {
    char magic[8];
    uint32_t version;
    uint32_t headerBytes; // sizeof(ChsHeader)
    uint32_t flags;       // kChsFlag*
    uint32_t subtreeCount;
    uint32_t upperNodeCount;
    uint32_t materialCount;
    uint64_t triangleCount;
    uint64_t nodeCount;   // all subtree nodes
    uint32_t subtreeTriangleLimit; // the cut's limits (CHC+RT §5.2)
    uint32_t subtreeHeightLimit;
    uint32_t maxSubtreeNodes;      // largest subtree actually written (GPU cache slot size)
    uint32_t maxSubtreeTriangles;
    float boundsMin[3];
    float boundsMax[3];
    float light[12];  // AreaLight corner, edgeU, edgeV, radiance
    float camera[10]; // eye, target, up, fovY (valid with kChsFlagCamera)
    uint32_t sourceBytes;  // length of the source spec string in the metadata
    uint32_t chunkCount;
    uint64_t metaOffset;
    uint64_t metaBytes;
    uint64_t metaChecksum;
    uint64_t fileBytes;
    uint64_t headerChecksum; // over every byte before this field
};
static_assert(sizeof(ChsHeader) == 224);

// A node of the upper hierarchy: inner (subtree == kChsNoSubtree; children firstChild, firstChild + 1) or a
// termination root (subtree = index into the directory). Breadth-first, root 0; the directory is sorted by
// upper node, so subtree i is the i-th termination root in node order.
struct ChsUpperNode {
    float boundsMin[3];
    uint32_t firstChild;
    float boundsMax[3];
    uint32_t subtree;
};
static_assert(sizeof(ChsUpperNode) == 32);

struct ChsSubtreeRecord {
    uint64_t offset;
    uint64_t bytes;
    uint64_t checksum;
    uint32_t nodeCount;
    uint32_t triangleCount;
    uint32_t height;    // edges from the subtree root to its deepest leaf
    uint32_t upperNode; // its node in the upper hierarchy
    float boundsMin[3];
    float boundsMax[3];
};
static_assert(sizeof(ChsSubtreeRecord) == 64);

struct ChsMaterialRecord {
    float baseColor[4];
    int32_t texture;
    char name[28];
};
static_assert(sizeof(ChsMaterialRecord) == 48);

// The LOD directory's header (after the source spec, with kChsFlagLod).
struct ChsLodHeader {
    uint32_t levels;            // proxy levels per subtree (1 ... levels; level 0 = the subtree itself)
    uint32_t coarsestRatio;     // the coarsest level aimed at 1 / coarsestRatio of the subtree's triangles
    uint32_t maxProxyNodes;     // largest proxy of any level (the GPU cache's proxy slots)
    uint32_t maxProxyTriangles;
    uint64_t proxyBytes;        // all proxy blobs
    uint64_t reserved;
};
static_assert(sizeof(ChsLodHeader) == 32);

// One proxy level of one subtree; nodeCount 0 = the level was not kept (the subtree at the finer level is used).
struct ChsLodRecord {
    uint64_t offset;
    uint64_t bytes;
    uint64_t checksum;
    uint32_t nodeCount;
    uint32_t triangleCount;
    float errorWorld;   // geometric error bound in world units (lod_proxies.h)
    uint32_t reserved;
};
static_assert(sizeof(ChsLodRecord) == 40);

// Bytes of a subtree blob.
inline uint64_t chsSubtreeBytes(uint64_t nodes, uint64_t triangles, bool texcoords) {
    return nodes * sizeof(BvhNodeGpu) + triangles * (sizeof(TriangleGpu) + 36 + (texcoords ? 24 : 0));
}

// Bytes of a compact blob (version 3) and the vertex count its byte count implies (UINT32_MAX when it implies none:
// not a whole number of vertices, or more than three per triangle).
inline uint64_t chsCompactFixedBytes(uint64_t nodes, uint64_t triangles, bool texcoords) {
    return (nodes + CHCRT_COMPACT_ROOT_TEXELS - 1) * 16 + triangles * (16 + 4 + 36 + (texcoords ? 24 : 0));
}
inline uint64_t chsCompactSubtreeBytes(uint64_t nodes, uint64_t triangles, uint64_t vertices, bool texcoords) {
    return chsCompactFixedBytes(nodes, triangles, texcoords) + vertices * 12;
}
inline uint32_t chsCompactVertexCount(uint64_t bytes, uint64_t nodes, uint64_t triangles, bool texcoords) {
    const uint64_t fixed = chsCompactFixedBytes(nodes, triangles, texcoords);
    if (bytes < fixed || (bytes - fixed) % 12 != 0 || (bytes - fixed) / 12 > 3 * triangles) return UINT32_MAX;
    return uint32_t((bytes - fixed) / 12);
}

// 64-bit checksum of a byte range (word-wise multiply-rotate; detects flipped bytes and truncation, not an
// adversary). Deterministic across runs.
uint64_t chsChecksum(const void* data, size_t bytes, uint64_t seed = 0);

} // namespace chcrt::outofcore
