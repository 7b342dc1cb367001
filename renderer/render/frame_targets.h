#pragma once
// The per-resolution render targets of a frame: the G-buffer, two ray-texture sets (the diffuse pass keeps its
// rays while generating the bounce shadow rays), two hit buffers, the effects' accumulation targets and the
// composed output. Recreated on resize.
#include "renderer/gl/gl_objects.h"

#include <cstdint>

namespace chcrt {

// One ray per pixel: origin + tmin, direction + tmax (RGBA32F each), CHC+RT §5.3.
struct RayTextures {
    GlTexture origin;
    GlTexture direction;
    // Active-ray mask (DEPTH_COMPONENT16, the framebuffer's depth): 1 where tmax > tmin, else 0, written with the
    // rays by rays/raygen.frag.glsl. Tracing passes test it early (renderer/render/trace_pass.h) so that fragment
    // groups without an active ray are not shaded at all: llvmpipe runs every branch of a shader for every group
    // (docs/architecture.md, "llvmpipe executes every branch"), so an inactive pixel otherwise costs a pass
    // through the whole traversal code.
    GlTexture active;
    GlFramebuffer framebuffer;
};

// Tracing results: hit = (bits of t, triangle id, bits of u, bits of v) RGBA32UI; cost = (inner nodes, leaves, triangles, capped)
// RGBA32UI. `depth` (DEPTH32F) is unused by pure BVH tracing and reserved for CHC+RT's generalized occlusion
// queries, which keep the nearest hit distance per ray there (CHC+RT §4.1).
struct HitTargets {
    GlTexture hit;
    GlTexture cost;
    GlTexture depth;
    GlFramebuffer framebuffer;
    // `hit` and `cost` with a ray set's `active` mask as depth: FrameTargets pairs rays[i] with hits[i] (ray set i
    // is always traced into hit set i); maskedFor = that mask's texture name (0: no mask, trace unmasked).
    GlFramebuffer maskedFramebuffer;
    GLuint maskedFor = 0;
};

struct FrameTargets {
    int width = 0;
    int height = 0;
    // G-buffer (attachments in the order of CHCRT_GBUFFER_OUT_*), with a reversed-Z float depth buffer.
    GlTexture gbufferPosition, gbufferNormal, gbufferAlbedo, gbufferTriangle, gbufferDepth;
    GlFramebuffer gbuffer;
    RayTextures rays[2];
    HitTargets hits[2];
    GlTexture accumDirect, accumAo, accumIndirect;
    GlFramebuffer accumDirectFbo, accumAoFbo, accumIndirectFbo;
    GlTexture outputHdr, outputDisplay;
    GlFramebuffer output;

    FrameTargets(int width, int height);

    // Bytes per pixel of the targets above: G-buffer 16 + 16 + 8 + 4 + 4, two ray sets of 16 + 16 + 2, two hit
    // sets of 16 + 16 + 4, three accumulation targets and two outputs of 16 (what a resolution costs before a
    // tracer adds per-pixel buffers of its own; the memory estimate of app/session.cpp).
    static constexpr uint64_t kBytesPerPixel = 48 + 2 * 34 + 2 * 36 + 3 * 16 + 2 * 16;
};

} // namespace chcrt
