#pragma once
// The render state of a full-screen tracing pass (pure BVH, Line Space and N-tree tracers, CHC+RT's pure passes):
// the hit targets bound for drawing, the ray textures bound for reading, and — when the ray set carries its
// active-ray mask — an early depth test against that mask, so that fragment groups without an active ray are not
// shaded. Why it pays: llvmpipe executes every branch and at least one iteration of every loop of a shader for
// each fragment group, so an inactive pixel (sky, a surface facing away from the light) otherwise costs a pass
// through the whole traversal code; the early test is the one place where it skips a group
// (docs/architecture.md, "llvmpipe executes every branch", has the measurements). The shaders declare
// layout(early_fragment_tests).
#include "renderer/gl/shader.h"
#include "renderer/render/frame_targets.h"

#include <array>

namespace chcrt {

// Binds `hits` (with the mask of `rays` when FrameTargets paired them) and `rays`, sets the viewport and the
// depth state. Pixels the mask skips are cleared to what a tracer writes for an inactive ray (a miss with
// t = CHCRT_NO_HIT_T and zero cost), so the results do not depend on whether the mask was used.
void beginTracePass(const RayTextures& rays, HitTargets& hits, int width, int height);

// Restores the depth state beginTracePass changed (test off, writes on).
void endTracePass();

// The compute form of a tracing pass (render/trace_bvh.comp.glsl and passes like it): binds `rays` for reading and
// the hit and cost textures of `hits` as images (CHCRT_IMAGE_TRACE_HIT / _COST), dispatches `program` with one
// invocation per pixel in CHCRT_TRACE_GROUP_SIZE² groups over the scissor box when the scissor test is on (as a
// fragment pass would be clipped; Renderer::warmUp traces one pixel), else over width × height, and makes the
// stores visible to every later read (texture fetches, image loads, read-backs, framebuffer use, the capped-ray
// counter). The program's uniforms regionOrigin, regionSize receive the traced rectangle.
void dispatchTracePass(const ShaderProgram& program, const RayTextures& rays, HitTargets& hits, int width, int height);

// The hit-target texel (CHCRT_TRACE_OUT_HIT layout) of a ray that is not traced or hits nothing: t =
// CHCRT_NO_HIT_T, no triangle, zero barycentrics. Tracers clear to it before they trace only some pixels.
std::array<GLuint, 4> missHitTexel();
// Clears the hit target's texture to missHitTexel() (a texture update: image loads after it need
// GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT).
void clearHitsToMisses(const HitTargets& hits);

} // namespace chcrt
