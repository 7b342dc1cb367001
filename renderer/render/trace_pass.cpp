#include "renderer/render/trace_pass.h"

#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/render_layout.h"

#include <glm/glm.hpp>

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

void dispatchTracePass(const ShaderProgram& program, const RayTextures& rays, HitTargets& hits, int width, int height) {
    glm::ivec2 origin(0), size(width, height);
    if (glIsEnabled(GL_SCISSOR_TEST)) {
        GLint box[4] = {0, 0, 0, 0};
        glGetIntegerv(GL_SCISSOR_BOX, box);
        const glm::ivec2 lower = glm::clamp(glm::ivec2(box[0], box[1]), glm::ivec2(0), size);
        const glm::ivec2 upper = glm::clamp(glm::ivec2(box[0] + box[2], box[1] + box[3]), lower, size);
        origin = lower;
        size = upper - lower;
    }
    if (size.x == 0 || size.y == 0) return;
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, rays.origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, rays.direction.id());
    glBindImageTexture(CHCRT_IMAGE_TRACE_HIT, hits.hit.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    glBindImageTexture(CHCRT_IMAGE_TRACE_COST, hits.cost.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    program.set("regionOrigin", origin);
    program.set("regionSize", size);
    program.use();
    const GLuint group = CHCRT_TRACE_GROUP_SIZE;
    glDispatchCompute((GLuint(size.x) + group - 1) / group, (GLuint(size.y) + group - 1) / group, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

std::array<GLuint, 4> missHitTexel() {
    return {std::bit_cast<GLuint>(float(CHCRT_NO_HIT_T)), CHCRT_NO_HIT_ID, 0u, 0u};
}

void clearHitsToMisses(const HitTargets& hits) {
    glClearTexImage(hits.hit.id(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, missHitTexel().data());
}

void endTracePass() {
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
}

} // namespace chcrt
