#pragma once
// Hand-built scenes, a BVH invariant checker and a brute-force tracer for the BVH tests and the benchmark.
// Scenes are made here (not by the procedural generators) so the BVH tests depend on nothing but Scene.
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/cpu_tracer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

namespace chcrt::test {

// Appends one triangle (material 0) with its own three vertices.
void addTriangle(Scene& scene, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

// `count` random triangles with edges up to `size`, uniformly placed in [-extent, extent]^3.
Scene makeTriangleSoup(uint32_t count, uint32_t seed, float extent = 100.0f, float size = 1.0f);

// `count` random small triangles in `clusters` dense Gaussian clusters spread over a large box (teapot in a
// stadium: SAH should isolate the clusters, the object median cuts through them).
Scene makeClusteredSoup(uint32_t count, uint32_t clusters, uint32_t seed);

// An indexed heightfield of cells x cells quads (2 triangles each, shared vertices and edges) over
// [0, cells]^2 in xz; y is a smooth function plus seeded noise. Structured input for builds and tracing.
Scene makeHeightfield(uint32_t cells, uint32_t seed);

// Adversarial for depth: triangles at exponentially spaced positions (x from 2^-120 to 2^120), so every
// binned SAH split peels off only the farthest few and an unguarded build gets deeper than the stack.
Scene makeExponentialRow(uint32_t count);

// Structural invariants of a built tree: all nodes reachable exactly once, sibling pairs in range, every
// triangle in exactly one leaf with leaf sizes in [1, maxLeafTriangles], original ids a permutation with the
// scene's vertices and materials, each node's bounds exactly the union of its triangles' (leaf) or its
// children's (inner) bounds, depth < CHCRT_MAX_BVH_DEPTH. checkBounds = false skips the bounds checks (for
// NaN input).
testing::AssertionResult checkBvhInvariants(const Bvh& bvh, const Scene& scene, uint32_t maxLeafTriangles,
                                            bool checkBounds = true);

// Closest (or any) hit by testing every triangle in id order with the tracers' acceptance rule.
Hit traceBruteForce(const Scene& scene, const Ray& ray, bool anyHit = false);

// A ray from a random point in `box` (grown by `margin` of its diagonal) through a random point in `box`.
Ray makeRandomRay(std::mt19937& rng, const Aabb& box, float margin);

} // namespace chcrt::test
