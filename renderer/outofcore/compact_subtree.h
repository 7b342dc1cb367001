#pragma once
// The compact subtree layout (shaders/shared/bvh_layout.h, "Compact subtree layout"; issue #19): a termination subtree's
// nodes as 16-byte texels whose boxes are 16-bit steps in a frame set by the subtree's root box, and its triangles as
// 16-byte texels of vertex indices into the subtree's distinct positions. Prepared scenes store subtrees and LOD proxies
// this way (.chs version 3, chs_format.h) and the out-of-core GPU cache holds them as stored, so a subtree costs about
// half the bytes to read, upload and keep resident (docs/outofcore.md, "Compact subtrees").
//
// Exactness: decoded boxes contain the exact ones (the encoder rounds outwards and checks the decoded value with the
// shader's arithmetic), so traversal visits a superset of the nodes it would visit; triangles decode bit for bit. The
// hit rule does not depend on the boxes (shared/intersect.h, hitRule), so hits equal those of the full layout bit for
// bit (tests/outofcore/compact_subtree_test.cpp). In-core tracing of a compact file (loadPreparedScene) uses the
// decoded boxes, so it traverses exactly what the GPU cache does.
#include "renderer/bvh/bvh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace chcrt::outofcore {

// The quantization frame of a subtree: its root box's minimum and a power-of-two step per axis (0 on a flat axis).
struct CompactFrame {
    glm::vec3 origin{0.0f};
    glm::vec3 step{0.0f};
};
// The frame of a root box: the smallest steps with origin + CHCRT_COMPACT_MAX_STEPS * step >= upper (in float).
CompactFrame compactFrame(const glm::vec3& lower, const glm::vec3& upper);
// The frame a root's texels hold (boundsMin in texel 0; steps in texel 1 .w and texel 2 .zw).
CompactFrame compactFrameOfRoot(const glm::uvec4& root0, const glm::uvec4& root1, const glm::uvec4& root2);
// origin + q * step per axis, as the traversal shader computes it.
glm::vec3 decodeCompactCoordinate(const CompactFrame& frame, const glm::uvec3& q);
// The steps of the smallest decoded box that contains [lower, upper] (each within the frame).
void quantizeCompactBox(const CompactFrame& frame, const glm::vec3& lower, const glm::vec3& upper, glm::uvec3& qLower,
                        glm::uvec3& qUpper);

// Texel of local node `node` (the root takes CHCRT_COMPACT_ROOT_TEXELS).
inline uint32_t compactNodeTexel(uint32_t node) { return node == 0 ? 0u : node + CHCRT_COMPACT_ROOT_TEXELS - 1; }
inline uint64_t compactNodeTexels(uint64_t nodes) { return nodes + CHCRT_COMPACT_ROOT_TEXELS - 1; }
inline uint32_t compactHeader(uint32_t index, uint32_t count) { return index | (count << CHCRT_COMPACT_INDEX_BITS); }
inline uint32_t compactHeaderIndex(uint32_t header) { return header & CHCRT_COMPACT_INDEX_MASK; }
inline uint32_t compactHeaderCount(uint32_t header) { return header >> CHCRT_COMPACT_INDEX_BITS; }
inline constexpr uint32_t kCompactMaxLeafTriangles = (1u << (32 - CHCRT_COMPACT_INDEX_BITS)) - 1u;
inline constexpr uint32_t kCompactMaxIndex = CHCRT_COMPACT_INDEX_MASK;

// One subtree (or LOD proxy) in the compact layout, with local indices.
struct CompactSubtree {
    std::vector<glm::uvec4> nodes;     // compactNodeTexels(node count); the root's texel 2 is 0 (no bases)
    std::vector<glm::uvec4> triangles; // vertex indices, original id
    std::vector<glm::vec3> vertices;   // distinct positions, in order of first use
    std::vector<uint32_t> materials;   // per triangle (for shading; the GPU cache does not need them)
};

// Encodes a subtree in the full layout (local indices: root 0, leaves' leftFirst into `triangles`). Throws
// InputError when a leaf holds more than kCompactMaxLeafTriangles triangles or an index does not fit.
void encodeCompactSubtree(std::span<const BvhNodeGpu> nodes, std::span<const TriangleGpu> triangles, CompactSubtree& out);

// Welds a triangle soup on bit-equal positions (meshoptimizer's vertex remap): `positions` receives the distinct ones
// in order of first use, cornerVertex[3t + k] the position of triangle t's vertex k. Shared by the compact layout and
// the LOD proxies (lod_proxies.cpp).
void weldCorners(std::span<const TriangleGpu> triangles, std::vector<glm::vec3>& positions,
                 std::vector<uint32_t>& cornerVertex);

// Decodes node texels into the full layout with the decoded (conservative) boxes: `nodes` receives texels.size() - 2
// nodes. Throws InputError for a header out of range (children after their parent and within the subtree, leaves'
// triangles within `triangleCount`): a corrupted blob must not become out-of-bounds reads, on the CPU or the GPU.
void decodeCompactNodes(std::span<const glm::uvec4> texels, uint32_t triangleCount, BvhNodeGpu* nodes);
// One node from its texel and its subtree's root texels (indices local, as decodeCompactNodes gives them; unchecked).
BvhNodeGpu decodeCompactNode(const glm::uvec4 root[3], const glm::uvec4& texel, bool isRoot);
// Validates the node headers as decodeCompactNodes does, without decoding (a GPU-only read).
void checkCompactNodes(std::span<const glm::uvec4> texels, uint32_t triangleCount);
// Decodes triangles exactly; throws InputError for a vertex index out of range.
void decodeCompactTriangles(std::span<const glm::uvec4> triangles, std::span<const glm::vec3> vertices,
                            std::span<const uint32_t> materials, TriangleGpu* out);
void checkCompactTriangles(std::span<const glm::uvec4> triangles, uint32_t vertexCount);

} // namespace chcrt::outofcore
