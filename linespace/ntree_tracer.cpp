#include "linespace/ntree_tracer.h"

#include "linespace/shaft_index.h"
#include "renderer/core/error.h"
#include "renderer/render/trace_pass.h"
#include "shaders/shared/ntree_layout.h"
#include "shaders/shared/render_layout.h"

#include <cstdlib>

namespace chcrt::ls {
namespace {

std::vector<ShaderDefine> shadowDefines(const NTreeGpu& gpu, const NTreeShadowOptions& options, unsigned cap) {
    if (gpu.depth() > CHCRT_NT_MAX_DEPTH) {
        throw InputError("N-tree depth " + std::to_string(gpu.depth()) + " exceeds the traversal's " +
                         std::to_string(CHCRT_NT_MAX_DEPTH) + " levels");
    }
    std::vector<ShaderDefine> defines = gpu.defines(options);
    if (cap != 0) defines.push_back({"CHCRT_TRACE_ITERATION_CAP", std::to_string(cap) + "u"});
    return defines;
}

} // namespace

NTreeParams parseNTreeParams(const std::string& text) {
    const size_t colon = text.find(':');
    const auto number = [&](const std::string& part) -> uint32_t {
        char* end = nullptr;
        const unsigned long value = std::strtoul(part.c_str(), &end, 10);
        if (part.empty() || *end != '\0' || value > 64) {
            throw InputError("--ls-ntree expects N:d (e.g. 6:3), got '" + text + "'");
        }
        return static_cast<uint32_t>(value);
    };
    if (colon == std::string::npos) throw InputError("--ls-ntree expects N:d (e.g. 6:3), got '" + text + "'");
    NTreeParams params;
    params.n = number(text.substr(0, colon));
    params.depth = number(text.substr(colon + 1));
    if (params.n < 2 || params.n > CHCRT_LS_MAX_N || params.depth < 1 || params.depth > CHCRT_NT_MAX_DEPTH) {
        throw InputError("--ls-ntree: N must be in 2.." + std::to_string(CHCRT_LS_MAX_N) + " and d in 1.." +
                         std::to_string(CHCRT_NT_MAX_DEPTH) + ", got '" + text + "'");
    }
    return params;
}

NTreeTracer::NTreeTracer(std::string name, std::shared_ptr<const NTreeGpu> gpu, NTreeShadowOptions options,
                         unsigned iterationCap)
    : name_(std::move(name)), gpu_(std::move(gpu)), options_(options),
      shadowProgram_({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                      {GL_FRAGMENT_SHADER, "render/trace_bvh.frag.glsl"}},
                     shadowDefines(*gpu_, options_, iterationCap)),
      bvh_(iterationCap) {}

void NTreeTracer::trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                        int height, TraceStats& stats) {
    const bool shadowRay = request.anyHit && (request.rayType == RayType::Shadow || request.bounceShadow);
    if (!shadowRay) {
        bvh_.trace(request, rays, hits, width, height, stats);
        return;
    }
    beginTracePass(rays, hits, width, height);
    gpu_->bind();
    shadowProgram_.use();
    drawFullscreenTriangle();
    endTracePass();
    ++stats.passes;
}

} // namespace chcrt::ls
