// How many parts each per-triangle texture buffer array has (shared/render_layout.h, "Per-triangle data beyond one
// texture buffer"), for the arrays' readers: render/bvh_triangles.glsl (BVH-ordered triangles),
// render/triangle_attributes.glsl and render/vertex_normals.glsl (by original id). Each reads a texel through one
// function that finds the part holding it: every part but the last has part 0's size, so the part follows from
// textureSize of part 0. With one part (the default) the functions are plain texelFetch calls: llvmpipe executes
// every branch (docs/architecture.md), so the part search is compiled in only where a scene needs it.
#ifndef CHCRT_TRIANGLE_PARTS_GLSL
#define CHCRT_TRIANGLE_PARTS_GLSL
#include "shared/render_layout.h"
#ifndef CHCRT_TRIANGLE_BUFFERS
#define CHCRT_TRIANGLE_BUFFERS 1
#endif
#if CHCRT_TRIANGLE_BUFFERS < 1 || CHCRT_TRIANGLE_BUFFERS > CHCRT_MAX_TRIANGLE_BUFFERS
#error CHCRT_TRIANGLE_BUFFERS must be 1 .. CHCRT_MAX_TRIANGLE_BUFFERS
#endif
#endif
