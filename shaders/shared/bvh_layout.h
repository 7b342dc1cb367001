#ifndef CHCRT_SHARED_BVH_LAYOUT_H
#define CHCRT_SHARED_BVH_LAYOUT_H
// GPU layout of the BVH and its triangles, shared by C++ (renderer/bvh) and GLSL (shaders/render/*).
// Both live in RGBA32F texture buffers (texture buffers are ~10x faster than SSBOs on llvmpipe;
// CHC+RT §5.2 does the same). Integers are stored as float bit patterns (floatBitsToUint in GLSL).
#include "shared_begin.h"

// One BVH node = 2 texels = 32 bytes (Acceleration Structures lecture: 32-byte nodes).
//   texel 0: boundsMin.xyz, leftFirst   texel 1: boundsMax.xyz, triCount
// Inner node (triCount == 0): children are leftFirst and leftFirst + 1 (siblings adjacent).
// Leaf (triCount > 0): triangles [leftFirst, leftFirst + triCount) of the BVH-ordered triangle buffer.
#define CHCRT_BVH_TEXELS_PER_NODE 2

// One triangle = 3 texels = 48 bytes, in BVH leaf order:
//   texel 0: v0.xyz, original triangle id   texel 1: v1.xyz, material id   texel 2: v2.xyz, 0
// The original id (index into Scene::triangles) is what hit buffers report, so results do not depend on
// the build's ordering.
#define CHCRT_TRI_TEXELS_PER_TRIANGLE 3

// Compact subtree layout (.chs version 3 and the out-of-core GPU cache; issue #19, renderer/outofcore/compact_subtree.h):
// a termination subtree's nodes and triangles in about half the bytes, decoded in the traversal (CHCRT_COMPACT_SUBTREES,
// render/bvh_nodes.glsl). Both buffers hold uvec4 texels (RGBA32UI); vertices are an RGB32F buffer. Indices are local
// to the subtree, as in the file: the traversal adds the bases its root holds, so an upload copies the file's bytes and
// writes one texel (the root's texel 2) instead of rebasing every node and triangle.
//   Root (3 texels, full precision; its box is also the quantization frame of the whole subtree):
//     texel 0: bits of boundsMin.xyz, header   texel 1: bits of boundsMax.xyz, bits of step.x
//     texel 2: where the subtree's triangles and vertices start in their buffers (0, 0 in the file), bits of step.yz
//   Any other node (1 texel): its box as 16-bit steps from the root's boundsMin, rounded outwards, then its header:
//     x: lo.x | lo.y << 16   y: lo.z | hi.x << 16   z: hi.y | hi.z << 16   w: header
//     coordinate = boundsMin + q * step, step a power of two per axis (0 on a flat axis; stored as a float, so the
//     traversal does no ldexp per root). A power-of-two step makes q * step exact, so the one rounding of the sum is
//     the same with or without a fused multiply-add, and the writer checks that every decoded box contains the
//     node's exact one.
//   Header: local index (low CHCRT_COMPACT_INDEX_BITS) | triangle count << CHCRT_COMPACT_INDEX_BITS; count 0 = inner
//     node with children at texels root + index, root + index + 1; else a leaf with triangles [index, index + count)
//     from the subtree's first triangle.
//   Texel of node k of a subtree, from its root: 0 for the root, k + 2 for k >= 1 (the root takes three).
//   Triangle (1 texel): vertex indices x, y, z (from the subtree's first vertex), original id w. Vertices: each
//     subtree's distinct positions (exactly equal floats merged), so decoded triangles are bit for bit the original ones.
#define CHCRT_COMPACT_ROOT_TEXELS 3
#define CHCRT_COMPACT_INDEX_BITS 27
#define CHCRT_COMPACT_INDEX_MASK 0x07FFFFFFu
#define CHCRT_COMPACT_MAX_STEPS 65535u

// Hit buffer convention of every tracer (GLSL, CPU, Embree): t = CHCRT_NO_HIT_T and triangle id
// CHCRT_NO_HIT_ID for a miss. Ties on equal t go to the lower original triangle id.
#define CHCRT_NO_HIT_ID 0xFFFFFFFFu
#define CHCRT_NO_HIT_T 3.402823466e+38

// Traversal stack entries per ray; the builder guarantees depth < this (falls back to median splits).
#define CHCRT_MAX_BVH_DEPTH 64

#ifdef __cplusplus
struct BvhNodeGpu {
    vec3 boundsMin;
    uint leftFirst; // 16 bytes
    vec3 boundsMax;
    uint triCount; // 32 bytes
};
static_assert(sizeof(BvhNodeGpu) == 16 * CHCRT_BVH_TEXELS_PER_NODE);

struct TriangleGpu {
    vec3 v0;
    uint originalId; // 16 bytes
    vec3 v1;
    uint materialId; // 32 bytes
    vec3 v2;
    uint pad; // 48 bytes
};
static_assert(sizeof(TriangleGpu) == 16 * CHCRT_TRI_TEXELS_PER_TRIANGLE);
#endif

#include "shared_end.h"
#endif
