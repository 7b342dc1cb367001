#ifndef CHCRT_SHARED_RENDER_LAYOUT_H
#define CHCRT_SHARED_RENDER_LAYOUT_H
// Binding slots, render-target layouts and constants shared by the C++ render passes (renderer/render/) and
// their shaders. Every texture unit and colour attachment a shader uses is named here, once.
#include "shared_begin.h"

// --- Texture units -------------------------------------------------------------------------------------
#define CHCRT_UNIT_BVH_NODES 0       // samplerBuffer, RGBA32F, CHCRT_BVH_TEXELS_PER_NODE per node (compact: usamplerBuffer)
#define CHCRT_UNIT_BVH_TRIANGLES 1   // samplerBuffer, RGBA32F, CHCRT_TRI_TEXELS_PER_TRIANGLE per triangle (compact: usamplerBuffer)
#define CHCRT_UNIT_TRI_ATTRIBUTES 2  // samplerBuffer, RGBA32F, CHCRT_ATTR_TEXELS_PER_TRIANGLE per original id
#define CHCRT_UNIT_MATERIALS 3       // samplerBuffer, RGBA32F, CHCRT_MATERIAL_TEXELS per material
#define CHCRT_UNIT_BASE_COLOR 4      // sampler2DArray, SRGB8_ALPHA8: one layer per scene texture
#define CHCRT_UNIT_RAY_ORIGIN 5      // sampler2D RGBA32F: origin.xyz, tmin
#define CHCRT_UNIT_RAY_DIRECTION 6   // sampler2D RGBA32F: direction.xyz, tmax (tmax <= tmin: inactive ray)
// An inactive shadow, AO or diffuse ray whose surface point another ray set of its kind in the frame may use writes
// its origin and a direction texel of all zeros (raygen.frag.glsl), the others an origin of zeros and direction
// (0, 0, 1, 0).
#define CHCRT_UNIT_HIT 7             // usampler2D RGBA32UI: bits of t, triangle id, bits of u, bits of v
#define CHCRT_UNIT_GBUFFER_POSITION 8 // sampler2D RGBA32F: world position, 1 = covered / 0 = background
#define CHCRT_UNIT_GBUFFER_NORMAL 9   // sampler2D RGBA32F: world normal facing the camera, linear depth
#define CHCRT_UNIT_GBUFFER_ALBEDO 10  // sampler2D RGBA8: base colour (linear after SRGB decode), 1
#define CHCRT_UNIT_GBUFFER_TRIANGLE 11 // usampler2D R32UI: original triangle id, CHCRT_NO_HIT_ID = background
#define CHCRT_UNIT_ACCUM_DIRECT 12   // sampler2D RGBA32F: sum of direct-light samples (rgb), sample count
#define CHCRT_UNIT_ACCUM_AO 13       // sampler2D RGBA32F: r = sum of unoccluded AO samples, a = count
#define CHCRT_UNIT_ACCUM_INDIRECT 14 // sampler2D RGBA32F: sum of one-bounce diffuse radiance (rgb), count
#define CHCRT_UNIT_BOUNCE_HIT 15     // usampler2D RGBA32UI: the diffuse pass's hit buffer (for its shadow rays)
// Units 16-21: Line Space (shaders/shared/linespace_bindings.h).
#define CHCRT_UNIT_TRI_NORMALS 22    // usamplerBuffer, RGBA16UI ((n * 0.5 + 0.5) * 65535), per original id
#define CHCRT_UNIT_PIXEL_GEOMETRIC_NORMAL 23 // sampler2D RGBA32F: out of core, the G-buffer pixels' geometric normals
#define CHCRT_UNIT_BVH_VERTICES 32   // samplerBuffer, RGB32F: the compact layout's vertices (shared/bvh_layout.h)
// Units 24-30: the N-tree and CHC+RT (shared/ntree_layout.h, shared/culling_layout.h). Units 40-48: parts 1-3 of the
// per-triangle buffers of a scene larger than one texture buffer (below).

// --- Per-triangle data beyond one texture buffer ---------------------------------------------------------
// GL_MAX_TEXTURE_BUFFER_SIZE (2^27 texels on llvmpipe and NVIDIA) holds 44.7M triangles at 3 texels each. A larger
// scene splits each per-triangle array (BVH-ordered triangles, attributes and vertex normals by original id) into
// parts of equal size (the last one shorter, no triangle across two parts): part 0 at the array's own unit, part k
// at its PART1 unit + k - 1. Shaders compiled with CHCRT_TRIANGLE_BUFFERS = K address K parts
// (render/triangle_parts.glsl); renderer/render/scene_gpu.h sets it for every program once a scene needs it.
#define CHCRT_MAX_TRIANGLE_BUFFERS 4
#define CHCRT_UNIT_BVH_TRIANGLES_PART1 40  // parts 1-3: units 40-42
#define CHCRT_UNIT_TRI_ATTRIBUTES_PART1 43 // units 43-45
#define CHCRT_UNIT_TRI_NORMALS_PART1 46    // units 46-48

// --- Per-triangle attributes by original id (for shading hits): 3 texels = 48 bytes ----------------------
//   texel 0: geometric normal.xyz (unit), material id   texel 1: uv0.xy, uv1.xy
//   texel 2: uv2.xy, sqrt(uv area / world area) (texture-space scale for the traced G-buffer's mip level), 0
#define CHCRT_ATTR_TEXELS_PER_TRIANGLE 3
// --- Per-triangle vertex normals by original id (the traced G-buffer interpolates them at the hit's
//     barycentrics, like rasterisation does): 3 texels = 24 bytes, texel k = vertex k's normal.xyz, 0 ---------
#define CHCRT_NORMAL_TEXELS_PER_TRIANGLE 3
// --- Materials: 2 texels = 32 bytes -------------------------------------------------------------------
//   texel 0: base colour factor (linear rgba)   texel 1: texture layer (-1 = none), uv scale to the layer
#define CHCRT_MATERIAL_TEXELS 2

// --- Colour attachments ---------------------------------------------------------------------------------
#define CHCRT_GBUFFER_OUT_POSITION 0
#define CHCRT_GBUFFER_OUT_NORMAL 1
#define CHCRT_GBUFFER_OUT_ALBEDO 2
#define CHCRT_GBUFFER_OUT_TRIANGLE 3
#define CHCRT_RAYGEN_OUT_ORIGIN 0
#define CHCRT_RAYGEN_OUT_DIRECTION 1
#define CHCRT_TRACE_OUT_HIT 0
#define CHCRT_TRACE_OUT_COST 1 // RGBA32UI: inner nodes visited, leaves visited, triangles tested, loop cap hit
// Traversal steps of a pixel as one word, the one encoding of Renderer::readTraceSteps, CHC+RT's cost debug image
// (ChcrtDebugImage::Cost) and the viewer's cost view: the low 31 bits count inner nodes + leaves + triangles,
// saturating at CHCRT_TRACE_STEPS_COUNT (never carrying into the flag); CHCRT_TRACE_STEPS_CAPPED marks a ray that
// reached the loop cap.
#define CHCRT_TRACE_STEPS_CAPPED 0x80000000u
#define CHCRT_TRACE_STEPS_COUNT 0x7fffffffu

// --- Ray types (one ray per pixel per pass; CHC+RT §5.3) ------------------------------------------------
#define CHCRT_RAY_PRIMARY 0
#define CHCRT_RAY_SHADOW 1
#define CHCRT_RAY_AO 2
#define CHCRT_RAY_DIFFUSE 3
#define CHCRT_RAY_BOUNCE_SHADOW 4 // shadow rays from the diffuse pass's hit points to the light

// llvmpipe silently ends every loop of a shader invocation after 65,535 iterations in total. Where the renderer
// needs it (CHCRT_TRACE_LOOP_CAP 1), the tracers count all their loop iterations and stop at
// CHCRT_TRACE_ITERATION_CAP, flagging the ray in their cost output, so the limit is never reached silently; the
// renderer counts flagged rays and `verify` fails on any. CHCRT_TRACE_LOOP_CAP is chosen per GL context from its
// renderer string (renderer/gl/context.h, rendererTraits: llvmpipe only) and given to every program compiled there
// (renderer/gl/shader.h); with 0 the counting is compiled out of the shared traversal (CHCRT_COUNT_ITERATION,
// CHCRT_BELOW_ITERATION_CAP), and loops that count on their own compare against a cap no ray reaches. A host that
// sets CHCRT_TRACE_ITERATION_CAP (tests lowering the cap) turns the counting on wherever it runs.
#ifndef CHCRT_TRACE_LOOP_CAP
#define CHCRT_TRACE_LOOP_CAP 1
#endif
#if defined(CHCRT_TRACE_ITERATION_CAP) || CHCRT_TRACE_LOOP_CAP
#define CHCRT_TRACE_COUNTS_ITERATIONS 1
#ifndef CHCRT_TRACE_ITERATION_CAP
#define CHCRT_TRACE_ITERATION_CAP 65000u // tests lower it (BvhTracer's iterationCap) to check the detection
#endif
#define CHCRT_COUNT_ITERATION(cost) ++(cost).iterations
#define CHCRT_BELOW_ITERATION_CAP(cost) ((cost).iterations < CHCRT_TRACE_ITERATION_CAP)
#else
#define CHCRT_TRACE_COUNTS_ITERATIONS 0
#define CHCRT_TRACE_ITERATION_CAP 0xffffffffu
#define CHCRT_COUNT_ITERATION(cost)
#define CHCRT_BELOW_ITERATION_CAP(cost) true
#endif
// Atomic counter binding: rays that reached CHCRT_TRACE_ITERATION_CAP (read back after each frame).
#define CHCRT_ATOMIC_BINDING_CAPPED_RAYS 0

// --- The pure tracer's compute pass (render/trace_bvh.comp.glsl): one invocation per ray in work groups of
//     CHCRT_TRACE_GROUP_SIZE² pixels, writing the hit and cost targets through these image units (CHC+RT's
//     passes use units 0-2, shared/culling_layout.h) -----------------------------------------------------------
#define CHCRT_TRACE_GROUP_SIZE 8
#define CHCRT_IMAGE_TRACE_HIT 3  // uimage2D RGBA32UI, the CHCRT_TRACE_OUT_HIT layout
#define CHCRT_IMAGE_TRACE_COST 4 // uimage2D RGBA32UI, the CHCRT_TRACE_OUT_COST layout

#include "shared_end.h"
#endif
