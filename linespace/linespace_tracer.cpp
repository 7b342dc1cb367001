#include "linespace/linespace_tracer.h"

#include "renderer/core/error.h"
#include "renderer/render/trace_pass.h"
#include "shaders/shared/render_layout.h"

#include <sstream>

namespace chcrt::ls {

LineSpaceModes LineSpaceModes::allExact() {
    LineSpaceModes m;
    m.primary = m.shadow = m.ao = m.diffuse = m.bounceShadow = LineSpaceMode::Exact;
    return m;
}

void LineSpaceModes::parse(const std::string& text) {
    std::stringstream stream(text);
    std::string item;
    while (std::getline(stream, item, ',')) {
        if (item.empty()) continue;
        const size_t eq = item.find('=');
        if (eq == std::string::npos) throw InputError("--ls-modes: expected type=mode, got '" + item + "'");
        const std::string type = item.substr(0, eq);
        if (type == "faces") {
            const std::string faces = item.substr(eq + 1);
            if (faces == "both") candidateFaces = CandidateFaces::Both;
            else if (faces == "front-start") candidateFaces = CandidateFaces::FrontInStartNode;
            else if (faces == "front") candidateFaces = CandidateFaces::Front;
            else throw InputError("--ls-modes: faces must be both, front-start or front, not '" + faces + "'");
            continue;
        }
        const LineSpaceMode mode = parseLineSpaceMode(item.substr(eq + 1));
        if (type == "primary") primary = mode;
        else if (type == "shadow") shadow = mode;
        else if (type == "ao") ao = mode;
        else if (type == "diffuse") diffuse = mode;
        else if (type == "bounce") bounceShadow = mode;
        else throw InputError("--ls-modes: unknown ray type '" + type + "' (primary, shadow, ao, diffuse, bounce, faces)");
    }
}

LineSpaceMode LineSpaceModes::forRequest(const TraceRequest& request) const {
    if (request.bounceShadow) return bounceShadow;
    switch (request.rayType) {
    case RayType::Primary: return primary;
    case RayType::Shadow: return shadow;
    case RayType::Ao: return ao;
    case RayType::Diffuse: return diffuse;
    }
    return LineSpaceMode::Off;
}

bool LineSpaceModes::approximate() const {
    for (LineSpaceMode m : {primary, shadow, ao, diffuse, bounceShadow}) {
        if (m != LineSpaceMode::Off && m != LineSpaceMode::Exact) return true;
    }
    return false;
}

std::string LineSpaceModes::toString() const {
    return std::string("primary=") + ls::toString(primary) + ",shadow=" + ls::toString(shadow) +
           ",ao=" + ls::toString(ao) + ",diffuse=" + ls::toString(diffuse) + ",bounce=" + ls::toString(bounceShadow) +
           ",faces=" + ls::toString(candidateFaces);
}

LineSpaceTracer::LineSpaceTracer(std::string name, std::shared_ptr<const LineSpaceGpu> gpu, LineSpaceModes modes,
                                 float maxNormalAngleDegrees, unsigned iterationCap)
    : name_(std::move(name)), gpu_(std::move(gpu)), modes_(modes), maxAngle_(maxNormalAngleDegrees), iterationCap_(iterationCap) {
    for (LineSpaceMode m : {modes.primary, modes.shadow, modes.ao, modes.diffuse, modes.bounceShadow}) {
        gpu_->defines(m, maxAngle_); // validates (candidates present) before the first frame
    }
}

const ShaderProgram& LineSpaceTracer::program(LineSpaceMode mode, bool anyHit) {
    auto& slot = programs_[{int(mode), anyHit}];
    if (!slot) {
        std::vector<ShaderDefine> defines = gpu_->defines(mode, maxAngle_, modes_.candidateFaces);
        defines.push_back({"TRACE_ANY_HIT", anyHit ? "1" : "0"});
        // From the root, candidate traversal reaches triangles only through Line Space nodes that are leaves.
        if (mode == LineSpaceMode::Candidate && !gpu_->hasLeafSpaces() && !keepUnreachableLeafTest) {
            defines.push_back({"CHCRT_LS_CANDIDATE_NO_LEAVES", "1"});
        }
        if (iterationCap_ != 0) defines.push_back({"CHCRT_TRACE_ITERATION_CAP", std::to_string(iterationCap_) + "u"});
        slot = std::make_unique<ShaderProgram>(std::vector<ShaderStage>{{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                                                        {GL_FRAGMENT_SHADER, "render/trace_bvh.frag.glsl"}},
                                               defines);
    }
    return *slot;
}

void LineSpaceTracer::trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                            int height, TraceStats& stats) {
    LineSpaceMode mode = modes_.forRequest(request);
    // Shadow termination only makes sense for any-hit rays; a closest-hit ray falls back to exact skipping.
    if (mode == LineSpaceMode::Shadow && !request.anyHit) mode = LineSpaceMode::Exact;
    const ShaderProgram& p = program(mode, request.anyHit);
    beginTracePass(rays, hits, width, height);
    gpu_->bind();
    p.use();
    drawFullscreenTriangle();
    endTracePass();
    ++stats.passes;
}

} // namespace chcrt::ls
