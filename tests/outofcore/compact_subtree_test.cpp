// The compact subtree layout (renderer/outofcore/compact_subtree.h): over random trees (random triangle soups at
// offsets and scales from millimetres to hundreds of kilometres, flat ones included), every decoded box contains its
// node's exact box and lies within its decoded parent, overshoots by less than one step per side, and decodes with the
// arithmetic the traversal shader uses; triangles decode bit for bit; corrupted headers and indices are refused.
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/cpu_tracer.h"
#include "renderer/core/error.h"
#include "renderer/outofcore/compact_subtree.h"
#include "renderer/scene/procedural/procedural.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace chcrt {
namespace {

using outofcore::CompactSubtree;

// Random triangles around `offset` within `scale`; `flatAxis` >= 0 puts every vertex on one plane.
Scene randomSoup(std::mt19937& rng, int triangles, const glm::vec3& offset, float scale, int flatAxis) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Scene scene;
    scene.materials.resize(3);
    for (int t = 0; t < triangles; ++t) {
        const glm::vec3 base = offset + scale * glm::vec3(u(rng), u(rng), u(rng));
        for (int v = 0; v < 3; ++v) {
            glm::vec3 p = base + 0.05f * scale * glm::vec3(u(rng), u(rng), u(rng));
            if (flatAxis >= 0) p[flatAxis] = offset[flatAxis];
            scene.positions.push_back(p);
            scene.normals.push_back({0.0f, 1.0f, 0.0f});
        }
        scene.triangles.push_back(glm::uvec3(3 * t, 3 * t + 1, 3 * t + 2));
        scene.triangleMaterials.push_back(uint32_t(t % 3));
    }
    return scene;
}

bool contains(const glm::vec3& lo, const glm::vec3& hi, const glm::vec3& innerLo, const glm::vec3& innerHi) {
    return glm::all(glm::lessThanEqual(lo, innerLo)) && glm::all(glm::greaterThanEqual(hi, innerHi));
}

TEST(CompactSubtree, EveryQuantizedBoxContainsItsNodeAndLiesInItsParent) {
    std::mt19937 rng(11);
    const glm::vec3 offsets[] = {{0.0f, 0.0f, 0.0f}, {-3.0f, 1.5f, 2.0f}, {1.0e5f, -2.0e4f, 3.3e5f}, {0.25f, 0.5f, -7.0f}};
    const float scales[] = {1.0e-3f, 1.0f, 40.0f, 2.0e5f};
    int trees = 0;
    for (const glm::vec3& offset : offsets) {
        for (float scale : scales) {
            for (int flatAxis = -1; flatAxis < 3; flatAxis += 2) { // -1: a volume; 1: every vertex on a plane y = c
                SCOPED_TRACE("offset " + std::to_string(offset.x) + " scale " + std::to_string(scale) + " flat " +
                             std::to_string(flatAxis));
                const Scene scene = randomSoup(rng, 200 + int(rng() % 800), offset, scale, flatAxis);
                const Bvh bvh = buildBvh(scene);
                CompactSubtree compact;
                outofcore::encodeCompactSubtree(bvh.nodes, bvh.triangles, compact);
                ASSERT_EQ(compact.nodes.size(), bvh.nodes.size() + 2);
                std::vector<BvhNodeGpu> decoded(bvh.nodes.size());
                outofcore::decodeCompactNodes(compact.nodes, uint32_t(bvh.triangles.size()), decoded.data());
                const outofcore::CompactFrame frame =
                    outofcore::compactFrame(bvh.nodes[0].boundsMin, bvh.nodes[0].boundsMax);
                if (flatAxis >= 0) {
                    EXPECT_EQ(frame.step[flatAxis], 0.0f);
                }
                // Steps: powers of two within 2x of the finest that spans the root in 65,535 steps.
                for (int axis = 0; axis < 3; ++axis) {
                    const double extent = double(bvh.nodes[0].boundsMax[axis]) - bvh.nodes[0].boundsMin[axis];
                    if (extent == 0.0) continue;
                    int exponent = 0;
                    EXPECT_EQ(std::frexp(frame.step[axis], &exponent), 0.5f);
                    EXPECT_LE(frame.step[axis], std::max(2.0 * extent / 65535.0, std::ldexp(1.0, -110)) * 1.0001);
                }
                std::vector<uint32_t> parent(bvh.nodes.size(), UINT32_MAX);
                for (uint32_t k = 0; k < bvh.nodes.size(); ++k) {
                    const BvhNodeGpu& exact = bvh.nodes[k];
                    const BvhNodeGpu& d = decoded[k];
                    ASSERT_EQ(d.leftFirst, exact.leftFirst) << "node " << k;
                    ASSERT_EQ(d.triCount, exact.triCount) << "node " << k;
                    ASSERT_TRUE(contains(d.boundsMin, d.boundsMax, exact.boundsMin, exact.boundsMax)) << "node " << k;
                    // Outward rounding by less than one step per side (the root is stored exactly).
                    const glm::vec3 slackLo = exact.boundsMin - d.boundsMin, slackHi = d.boundsMax - exact.boundsMax;
                    for (int axis = 0; axis < 3; ++axis) {
                        if (k == 0) {
                            EXPECT_EQ(slackLo[axis], 0.0f);
                            EXPECT_EQ(slackHi[axis], 0.0f);
                        } else if (frame.step[axis] > 0.0f) {
                            EXPECT_LT(slackLo[axis], frame.step[axis] * 1.0001f) << "node " << k;
                            EXPECT_LT(slackHi[axis], frame.step[axis] * 1.0001f) << "node " << k;
                        }
                    }
                    // The decoding the shader does (origin + q * step) is the one decodeCompactNodes did.
                    if (k != 0) {
                        const glm::uvec4 t = compact.nodes[outofcore::compactNodeTexel(k)];
                        EXPECT_EQ(d.boundsMin, frame.origin + glm::vec3(t.x & 0xffffu, t.x >> 16, t.y & 0xffffu) * frame.step);
                        EXPECT_EQ(d.boundsMax, frame.origin + glm::vec3(t.y >> 16, t.z & 0xffffu, t.z >> 16) * frame.step);
                    }
                    if (exact.triCount == 0) parent[exact.leftFirst] = parent[exact.leftFirst + 1] = k;
                    if (k != 0 && parent[k] != 0) { // below the root, children lie in their decoded parent
                        const BvhNodeGpu& p = decoded[parent[k]];
                        ASSERT_TRUE(contains(p.boundsMin, p.boundsMax, d.boundsMin, d.boundsMax)) << "node " << k;
                    }
                }
                // Triangles bit for bit, through the distinct vertices.
                ASSERT_EQ(compact.triangles.size(), bvh.triangles.size());
                EXPECT_LE(compact.vertices.size(), 3 * bvh.triangles.size());
                std::vector<TriangleGpu> triangles(bvh.triangles.size());
                outofcore::decodeCompactTriangles(compact.triangles, compact.vertices, compact.materials, triangles.data());
                for (size_t t = 0; t < triangles.size(); ++t) {
                    TriangleGpu expected = bvh.triangles[t];
                    expected.pad = 0;
                    ASSERT_EQ(std::memcmp(&expected, &triangles[t], sizeof(TriangleGpu)), 0) << "triangle " << t;
                }
                ++trees;
            }
        }
    }
    EXPECT_EQ(trees, 32);
}

TEST(CompactSubtree, SharedVerticesAreStoredOnce) {
    Scene scene;
    scene.materials.resize(1);
    // A fan of 8 triangles around one centre: 10 distinct positions.
    scene.positions.push_back({0.0f, 0.0f, 0.0f});
    for (int i = 0; i <= 8; ++i) scene.positions.push_back({std::cos(0.7f * float(i)), 0.1f * float(i), std::sin(0.7f * float(i))});
    scene.normals.assign(scene.positions.size(), glm::vec3(0.0f, 1.0f, 0.0f));
    for (uint32_t i = 0; i < 8; ++i) {
        scene.triangles.push_back({0u, i + 1, i + 2});
        scene.triangleMaterials.push_back(0);
    }
    const Bvh bvh = buildBvh(scene);
    CompactSubtree compact;
    outofcore::encodeCompactSubtree(bvh.nodes, bvh.triangles, compact);
    EXPECT_EQ(compact.vertices.size(), 10u);
}

TEST(CompactSubtree, CorruptedHeadersAndIndicesAreRefused) {
    std::mt19937 rng(5);
    const Scene scene = randomSoup(rng, 300, glm::vec3(0.0f), 10.0f, -1);
    const Bvh bvh = buildBvh(scene);
    CompactSubtree compact;
    outofcore::encodeCompactSubtree(bvh.nodes, bvh.triangles, compact);
    const uint32_t triangleCount = uint32_t(bvh.triangles.size());
    const uint32_t vertexCount = uint32_t(compact.vertices.size());
    EXPECT_NO_THROW(outofcore::checkCompactNodes(compact.nodes, triangleCount));
    EXPECT_NO_THROW(outofcore::checkCompactTriangles(compact.triangles, vertexCount));
    // An inner node pointing back at the root, beyond the subtree, or a leaf past the triangles.
    for (uint32_t bad : {outofcore::compactHeader(0, 0), outofcore::compactHeader(2, 0),
                         outofcore::compactHeader(uint32_t(compact.nodes.size()), 0),
                         outofcore::compactHeader(triangleCount - 1, 2)}) {
        std::vector<glm::uvec4> nodes = compact.nodes;
        nodes[0].w = bad;
        EXPECT_THROW(outofcore::checkCompactNodes(nodes, triangleCount), InputError) << bad;
    }
    std::vector<glm::uvec4> triangles = compact.triangles;
    triangles[triangles.size() / 2].y = vertexCount;
    EXPECT_THROW(outofcore::checkCompactTriangles(triangles, vertexCount), InputError);
    // A leaf larger than the header holds cannot be encoded.
    std::vector<BvhNodeGpu> oneLeaf = {bvh.nodes[0]};
    oneLeaf[0].leftFirst = 0;
    oneLeaf[0].triCount = triangleCount; // 300 > 31
    EXPECT_THROW(outofcore::encodeCompactSubtree(oneLeaf, bvh.triangles, compact), InputError);
}

// The hit rule does not depend on the boxes (shared/intersect.h, hitRule): the city's BVH with every box decoded from
// the compact layout (larger, in a subtree frame) gives the exact BVH's hits bit for bit, for rays that graze the
// city's axis-aligned walls (the rays where a tight box's slab test and the triangle test disagree) and for random ones.
TEST(CompactSubtree, QuantizedBoxesGiveTheExactBoxesHitsForGrazingRays) {
    const Scene scene = generateProceduralScene({ProceduralKind::City, 20000, 1});
    const Bvh exact = buildBvh(scene);
    CompactSubtree compact;
    outofcore::encodeCompactSubtree(exact.nodes, exact.triangles, compact);
    Bvh quantized = exact;
    outofcore::decodeCompactNodes(compact.nodes, uint32_t(exact.triangles.size()), quantized.nodes.data());
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < 60000; ++i) {
        const TriangleGpu& tri = exact.triangles[rng() % exact.triangles.size()];
        const glm::vec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
        const glm::vec3 normal = glm::cross(e1, e2);
        if (glm::length(normal) == 0.0f) continue;
        // A point of the triangle near an edge, a direction within ~1e-6..1e-2 rad of its plane.
        float a = u(rng), b = u(rng) * (1.0f - a);
        const glm::vec3 target = tri.v0 + a * e1 + b * e2;
        const glm::vec3 along = glm::normalize(glm::mix(e1, e2, u(rng)));
        const float tilt = std::pow(10.0f, -6.0f + 4.0f * u(rng)) * (u(rng) < 0.5f ? -1.0f : 1.0f);
        const glm::vec3 direction = glm::normalize(along + tilt * glm::normalize(normal));
        Ray r;
        r.origin = target - (1.0f + 60.0f * u(rng)) * direction;
        r.direction = direction;
        r.tmin = 0.0f;
        r.tmax = 1e30f;
        rays.push_back(r);
    }
    std::vector<Hit> a(rays.size()), b(rays.size());
    traceCpu(exact, rays, a, false);
    traceCpu(quantized, rays, b, false);
    size_t hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(a[i].triangleId, b[i].triangleId) << "ray " << i;
        ASSERT_EQ(a[i].t, b[i].t) << "ray " << i;
        hits += a[i].hit();
    }
    EXPECT_GT(hits, rays.size() / 2);
}

} // namespace
} // namespace chcrt
