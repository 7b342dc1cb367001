#pragma once
// Pure BVH tracing in GLSL (the baseline): one full-screen fragment pass per ray texture, stack-based
// while-while traversal of the whole BVH (shaders/render/trace_bvh.frag.glsl).
#include "renderer/gl/shader.h"
#include "renderer/render/tracer.h"

namespace chcrt {

class BvhTracer final : public Tracer {
public:
    // iterationCap: loop iterations per ray before the tracer gives up and flags the ray (default: the
    // CHCRT_TRACE_ITERATION_CAP below llvmpipe's limit); tests lower it to check that capping is reported.
    explicit BvhTracer(unsigned iterationCap = 0);
    std::string name() const override { return "bvh"; }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override;

private:
    ShaderProgram closestHit_;
    ShaderProgram anyHit_;
};

} // namespace chcrt
