#include "renderer/render/bvh_tracer.h"

#include "renderer/render/trace_pass.h"

namespace chcrt {
namespace {

ShaderProgram makeTraceProgram(TraceStage stage, bool anyHit, unsigned iterationCap) {
    std::vector<ShaderDefine> defines = {{"TRACE_ANY_HIT", anyHit ? "1" : "0"}};
    if (iterationCap != 0) defines.push_back({"CHCRT_TRACE_ITERATION_CAP", std::to_string(iterationCap) + "u"});
    if (stage == TraceStage::Compute) return ShaderProgram({{GL_COMPUTE_SHADER, "render/trace_bvh.comp.glsl"}}, defines);
    return ShaderProgram({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                          {GL_FRAGMENT_SHADER, "render/trace_bvh.frag.glsl"}},
                         defines);
}

} // namespace

BvhTracer::BvhTracer(unsigned iterationCap) : BvhTracer(preferredTraceStage(), iterationCap) {}

BvhTracer::BvhTracer(TraceStage stage, unsigned iterationCap)
    : stage_(resolveTraceStage(stage)), closestHit_(makeTraceProgram(stage_, false, iterationCap)),
      anyHit_(makeTraceProgram(stage_, true, iterationCap)) {}

void BvhTracer::trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                      int height, TraceStats& stats) {
    const ShaderProgram& program = request.anyHit ? anyHit_ : closestHit_;
    if (stage_ == TraceStage::Compute) {
        dispatchTracePass(program, rays, hits, width, height);
    } else {
        beginTracePass(rays, hits, width, height);
        program.use();
        drawFullscreenTriangle();
        endTracePass();
    }
    ++stats.passes;
}

} // namespace chcrt
