#include "renderer/outofcore/compact_subtree.h"

#include "renderer/core/error.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <meshoptimizer.h>
#include <string>

namespace chcrt::outofcore {
namespace {

constexpr int kMinExponent = -110; // steps stay normal floats, and so does every non-zero q * step
constexpr int kMaxExponent = 110;  // 65,535 steps of 2^110 span any finite box
constexpr float kMaxSteps = float(CHCRT_COMPACT_MAX_STEPS);

// origin + q * step in float: q * step is exact (a power of two times q < 2^16), so this is the shader's result
// whether or not its compiler fuses the multiply-add.
float decodeAxis(float origin, float step, uint32_t q) { return origin + float(q) * step; }

uint32_t floatBits(float f) { return std::bit_cast<uint32_t>(f); }
float bitsFloat(uint32_t u) { return std::bit_cast<float>(u); }

[[noreturn]] void corrupted(const std::string& what) { throw InputError("corrupted compact subtree (" + what + ")"); }

} // namespace

CompactFrame compactFrame(const glm::vec3& lower, const glm::vec3& upper) {
    CompactFrame frame;
    frame.origin = lower;
    for (int axis = 0; axis < 3; ++axis) {
        const double extent = double(upper[axis]) - double(lower[axis]);
        if (extent > 0.0) {
            int e = std::max(kMinExponent, int(std::ceil(std::log2(extent / double(kMaxSteps)))));
            // Rounding of the sum may leave the last step short of upper: take the next power of two then.
            while (e <= kMaxExponent && decodeAxis(lower[axis], std::ldexp(1.0f, e), CHCRT_COMPACT_MAX_STEPS) < upper[axis]) ++e;
            if (e > kMaxExponent) throw InputError("compact subtree: box extent out of range");
            frame.step[axis] = std::ldexp(1.0f, e);
        } else if (!(extent == 0.0)) {
            throw InputError("compact subtree: invalid root box");
        }
    }
    return frame;
}

CompactFrame compactFrameOfRoot(const glm::uvec4& root0, const glm::uvec4& root1, const glm::uvec4& root2) {
    CompactFrame frame;
    frame.origin = {bitsFloat(root0.x), bitsFloat(root0.y), bitsFloat(root0.z)};
    frame.step = {bitsFloat(root1.w), bitsFloat(root2.z), bitsFloat(root2.w)};
    return frame;
}

glm::vec3 decodeCompactCoordinate(const CompactFrame& frame, const glm::uvec3& q) {
    return {decodeAxis(frame.origin.x, frame.step.x, q.x), decodeAxis(frame.origin.y, frame.step.y, q.y),
            decodeAxis(frame.origin.z, frame.step.z, q.z)};
}

void quantizeCompactBox(const CompactFrame& frame, const glm::vec3& lower, const glm::vec3& upper, glm::uvec3& qLower,
                        glm::uvec3& qUpper) {
    const uint32_t top = CHCRT_COMPACT_MAX_STEPS;
    for (int axis = 0; axis < 3; ++axis) {
        const float o = frame.origin[axis], s = frame.step[axis];
        uint32_t lo = 0, hi = 0;
        if (s > 0.0f) {
            const double l = std::floor((double(lower[axis]) - o) / s), u = std::ceil((double(upper[axis]) - o) / s);
            lo = uint32_t(std::clamp(l, 0.0, double(top)));
            hi = uint32_t(std::clamp(u, 0.0, double(top)));
            // The estimate from doubles, corrected with the float arithmetic the traversal uses: outwards until the
            // decoded box contains the exact one, then inwards while it still does.
            while (lo > 0 && decodeAxis(o, s, lo) > lower[axis]) --lo;
            while (lo < top && decodeAxis(o, s, lo + 1) <= lower[axis]) ++lo;
            while (hi < top && decodeAxis(o, s, hi) < upper[axis]) ++hi;
            while (hi > 0 && decodeAxis(o, s, hi - 1) >= upper[axis]) --hi;
        }
        if (!(decodeAxis(o, s, lo) <= lower[axis]) || !(decodeAxis(o, s, hi) >= upper[axis])) {
            throw InputError("compact subtree: a node's box is not inside its subtree's root box");
        }
        qLower[axis] = lo, qUpper[axis] = hi;
    }
}

void encodeCompactSubtree(std::span<const BvhNodeGpu> nodes, std::span<const TriangleGpu> triangles, CompactSubtree& out) {
    if (nodes.empty()) throw InputError("compact subtree: no nodes");
    if (compactNodeTexels(nodes.size()) > kCompactMaxIndex || triangles.size() > kCompactMaxIndex) {
        throw InputError("compact subtree: more than " + std::to_string(kCompactMaxIndex) + " nodes or triangles");
    }
    const CompactFrame frame = compactFrame(nodes[0].boundsMin, nodes[0].boundsMax);
    out.nodes.assign(compactNodeTexels(nodes.size()), glm::uvec4(0u));
    for (size_t k = 0; k < nodes.size(); ++k) {
        const BvhNodeGpu& n = nodes[k];
        uint32_t header;
        if (n.triCount == 0) {
            header = compactHeader(compactNodeTexel(n.leftFirst), 0);
        } else {
            if (n.triCount > kCompactMaxLeafTriangles) {
                throw InputError("compact subtree: a leaf of " + std::to_string(n.triCount) + " triangles (at most " +
                                 std::to_string(kCompactMaxLeafTriangles) + ")");
            }
            header = compactHeader(n.leftFirst, n.triCount);
        }
        if (k == 0) {
            out.nodes[0] = {floatBits(n.boundsMin.x), floatBits(n.boundsMin.y), floatBits(n.boundsMin.z), header};
            out.nodes[1] = {floatBits(n.boundsMax.x), floatBits(n.boundsMax.y), floatBits(n.boundsMax.z), floatBits(frame.step.x)};
            // The bases (0 here: the GPU cache's upload writes its slot's), the other two steps.
            out.nodes[2] = {0u, 0u, floatBits(frame.step.y), floatBits(frame.step.z)};
            continue;
        }
        glm::uvec3 lo, hi;
        quantizeCompactBox(frame, n.boundsMin, n.boundsMax, lo, hi);
        out.nodes[compactNodeTexel(uint32_t(k))] = {lo.x | (lo.y << 16), lo.z | (hi.x << 16), hi.y | (hi.z << 16), header};
    }
    std::vector<uint32_t> corner;
    weldCorners(triangles, out.vertices, corner);
    out.triangles.resize(triangles.size());
    out.materials.resize(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t) {
        out.triangles[t] = {corner[3 * t], corner[3 * t + 1], corner[3 * t + 2], triangles[t].originalId};
        out.materials[t] = triangles[t].materialId;
    }
}

void weldCorners(std::span<const TriangleGpu> triangles, std::vector<glm::vec3>& positions,
                 std::vector<uint32_t>& cornerVertex) {
    const size_t cornerCount = triangles.size() * 3;
    std::vector<glm::vec3> soup(cornerCount);
    for (size_t t = 0; t < triangles.size(); ++t) {
        soup[t * 3] = triangles[t].v0, soup[t * 3 + 1] = triangles[t].v1, soup[t * 3 + 2] = triangles[t].v2;
    }
    cornerVertex.resize(cornerCount);
    const size_t unique = cornerCount == 0 ? 0
                                           : meshopt_generateVertexRemap(cornerVertex.data(), nullptr, cornerCount,
                                                                         soup.data(), cornerCount, sizeof(glm::vec3));
    positions.resize(unique);
    if (unique != 0) {
        meshopt_remapVertexBuffer(positions.data(), soup.data(), cornerCount, sizeof(glm::vec3), cornerVertex.data());
    }
}

void checkCompactNodes(std::span<const glm::uvec4> texels, uint32_t triangleCount) {
    if (texels.size() < CHCRT_COMPACT_ROOT_TEXELS) corrupted("no root");
    const uint64_t nodeCount = texels.size() - (CHCRT_COMPACT_ROOT_TEXELS - 1);
    // Inner node k: children k' > k and k' + 1 < nodeCount (texels k' + 2, k' + 3: index > k + 2, index < nodeCount + 1);
    // leaf: triangles within the subtree. One pass without branches (every GPU read of every upload runs it); the
    // offending node is looked for only when one is found.
    const auto bad = [&](uint64_t k, uint32_t header) {
        const uint64_t index = compactHeaderIndex(header), count = compactHeaderCount(header);
        return count == 0 ? !(index > k + 2 && index <= nodeCount) : index + count > triangleCount;
    };
    bool any = bad(0, texels[0].w);
    for (uint64_t k = 1; k < nodeCount; ++k) any |= bad(k, texels[k + CHCRT_COMPACT_ROOT_TEXELS - 1].w);
    if (!any) return;
    for (uint64_t k = 0; k < nodeCount; ++k) {
        if (bad(k, texels[compactNodeTexel(uint32_t(k))].w)) corrupted("node " + std::to_string(k));
    }
}

BvhNodeGpu decodeCompactNode(const glm::uvec4 root[3], const glm::uvec4& texel, bool isRoot) {
    BvhNodeGpu n;
    const CompactFrame frame = compactFrameOfRoot(root[0], root[1], root[2]);
    if (isRoot) {
        n.boundsMin = frame.origin;
        n.boundsMax = {bitsFloat(root[1].x), bitsFloat(root[1].y), bitsFloat(root[1].z)};
    } else {
        n.boundsMin = decodeCompactCoordinate(frame, {texel.x & 0xffffu, texel.x >> 16, texel.y & 0xffffu});
        n.boundsMax = decodeCompactCoordinate(frame, {texel.y >> 16, texel.z & 0xffffu, texel.z >> 16});
    }
    const uint32_t index = compactHeaderIndex(texel.w), count = compactHeaderCount(texel.w);
    n.triCount = count;
    n.leftFirst = count == 0 ? index - (CHCRT_COMPACT_ROOT_TEXELS - 1) : index; // an inner node's children: texels index, index + 1
    return n;
}

void decodeCompactNodes(std::span<const glm::uvec4> texels, uint32_t triangleCount, BvhNodeGpu* nodes) {
    checkCompactNodes(texels, triangleCount);
    const size_t nodeCount = texels.size() - (CHCRT_COMPACT_ROOT_TEXELS - 1);
    for (size_t k = 0; k < nodeCount; ++k) {
        nodes[k] = decodeCompactNode(texels.data(), texels[compactNodeTexel(uint32_t(k))], k == 0);
    }
}

void checkCompactTriangles(std::span<const glm::uvec4> triangles, uint32_t vertexCount) {
    uint32_t largest = 0; // one pass without branches; the offending triangle is looked for only when there is one
    for (const glm::uvec4& t : triangles) largest = std::max(largest, std::max(t.x, std::max(t.y, t.z)));
    if (triangles.empty() || largest < vertexCount) return;
    for (size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec4& tri = triangles[t];
        if (tri.x >= vertexCount || tri.y >= vertexCount || tri.z >= vertexCount) corrupted("triangle " + std::to_string(t));
    }
}

void decodeCompactTriangles(std::span<const glm::uvec4> triangles, std::span<const glm::vec3> vertices,
                            std::span<const uint32_t> materials, TriangleGpu* out) {
    checkCompactTriangles(triangles, uint32_t(vertices.size()));
    for (size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec4& tri = triangles[t];
        out[t].v0 = vertices[tri.x];
        out[t].v1 = vertices[tri.y];
        out[t].v2 = vertices[tri.z];
        out[t].originalId = tri.w;
        out[t].materialId = materials[t];
        out[t].pad = 0;
    }
}

} // namespace chcrt::outofcore
