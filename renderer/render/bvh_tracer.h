#pragma once
// Pure BVH tracing in GLSL (the baseline): one pass per ray texture, stack-based while-while traversal of the whole
// BVH, as a full-screen fragment pass (shaders/render/trace_bvh.frag.glsl) or a compute pass
// (shaders/render/trace_bvh.comp.glsl) over the same per-ray code (render/trace_ray.glsl): the same bits either way.
#include "renderer/gl/shader.h"
#include "renderer/render/trace_stage.h"
#include "renderer/render/tracer.h"

namespace chcrt {

class BvhTracer final : public Tracer {
public:
    // iterationCap: loop iterations per ray before the tracer gives up and flags the ray (default: the
    // CHCRT_TRACE_ITERATION_CAP below llvmpipe's limit, where the renderer needs one); tests lower it to check that
    // capping is reported. The stage is preferredTraceStage(), resolved on the current context.
    explicit BvhTracer(unsigned iterationCap = 0);
    // The stage given (Auto: resolveTraceStage on the current context).
    explicit BvhTracer(TraceStage stage, unsigned iterationCap = 0);
    std::string name() const override { return "bvh"; }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override;
    TraceStage stage() const { return stage_; } // fragment or compute

private:
    TraceStage stage_;
    ShaderProgram closestHit_;
    ShaderProgram anyHit_;
};

} // namespace chcrt
