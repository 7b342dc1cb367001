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
