#include "renderer/render/bvh_tracer.h"

#include "shaders/shared/render_layout.h"

namespace chcrt {
namespace {

ShaderProgram makeTraceProgram(bool anyHit, unsigned iterationCap) {
    std::vector<ShaderDefine> defines = {{"TRACE_ANY_HIT", anyHit ? "1" : "0"}};
    if (iterationCap != 0) defines.push_back({"CHCRT_TRACE_ITERATION_CAP", std::to_string(iterationCap) + "u"});
    return ShaderProgram({{GL_VERTEX_SHADER, "common/fullscreen.vert.glsl"},
                          {GL_FRAGMENT_SHADER, "trace/trace_bvh.frag.glsl"}},
                         defines);
}

} // namespace

BvhTracer::BvhTracer(unsigned iterationCap)
    : closestHit_(makeTraceProgram(false, iterationCap)), anyHit_(makeTraceProgram(true, iterationCap)) {}

void BvhTracer::trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                      int height, TraceStats& stats) {
    glBindFramebuffer(GL_FRAMEBUFFER, hits.framebuffer.id());
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, rays.origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, rays.direction.id());
    (request.anyHit ? anyHit_ : closestHit_).use();
    drawFullscreenTriangle();
    ++stats.passes;
}

} // namespace chcrt
