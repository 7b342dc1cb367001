#include "renderer/render/bvh_tracer.h"

#include "renderer/render/trace_pass.h"

namespace chcrt {
namespace {

ShaderProgram makeTraceProgram(bool anyHit, unsigned iterationCap) {
    std::vector<ShaderDefine> defines = {{"TRACE_ANY_HIT", anyHit ? "1" : "0"}};
    if (iterationCap != 0) defines.push_back({"CHCRT_TRACE_ITERATION_CAP", std::to_string(iterationCap) + "u"});
    return ShaderProgram({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                          {GL_FRAGMENT_SHADER, "render/trace_bvh.frag.glsl"}},
                         defines);
}

} // namespace

BvhTracer::BvhTracer(unsigned iterationCap)
    : closestHit_(makeTraceProgram(false, iterationCap)), anyHit_(makeTraceProgram(true, iterationCap)) {}

void BvhTracer::trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                      int height, TraceStats& stats) {
    beginTracePass(rays, hits, width, height);
    (request.anyHit ? anyHit_ : closestHit_).use();
    drawFullscreenTriangle();
    endTracePass();
    ++stats.passes;
}

} // namespace chcrt
