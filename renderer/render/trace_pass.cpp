#include "renderer/render/trace_pass.h"

#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/render_layout.h"

#include <bit>

namespace chcrt {

void beginTracePass(const RayTextures& rays, HitTargets& hits, int width, int height) {
    const bool masked = hits.maskedFor != 0 && hits.maskedFor == rays.active.id();
    const GLuint framebuffer = masked ? hits.maskedFramebuffer.id() : hits.framebuffer.id();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width, height);
    glDisable(GL_BLEND);
    if (masked) {
        // The trace shaders' inactive output (trace/trace_bvh.frag.glsl): a miss and zero cost.
        const GLuint zero[4] = {0u, 0u, 0u, 0u};
        glClearNamedFramebufferuiv(framebuffer, GL_COLOR, CHCRT_TRACE_OUT_HIT, missHitTexel().data());
        glClearNamedFramebufferuiv(framebuffer, GL_COLOR, CHCRT_TRACE_OUT_COST, zero);
        // The full-screen triangle lies at depth 0 or 0.5 (either clip-control convention): it passes where the
        // mask holds 1 (active) and fails where it holds 0. The mask itself is never written here.
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_FALSE);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, rays.origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, rays.direction.id());
}

std::array<GLuint, 4> missHitTexel() {
    return {std::bit_cast<GLuint>(float(CHCRT_NO_HIT_T)), CHCRT_NO_HIT_ID, 0u, 0u};
}

void endTracePass() {
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
}

} // namespace chcrt
