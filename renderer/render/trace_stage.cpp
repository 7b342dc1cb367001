#include "renderer/render/trace_stage.h"

#include "renderer/core/error.h"
#include "renderer/gl/context.h"

#include <atomic>
#include <cstdlib>

namespace chcrt {
namespace {

std::atomic<TraceStage>& preferred() {
    static std::atomic<TraceStage> stage{TraceStage::Auto};
    return stage;
}

} // namespace

TraceStage parseTraceStage(const std::string& name) {
    if (name == "fragment") return TraceStage::Fragment;
    if (name == "compute") return TraceStage::Compute;
    if (name == "auto") return TraceStage::Auto;
    throw InputError("shader stage must be fragment, compute or auto, not '" + name + "'");
}

const char* toString(TraceStage stage) {
    switch (stage) {
    case TraceStage::Fragment: return "fragment";
    case TraceStage::Compute: return "compute";
    case TraceStage::Auto: return "auto";
    }
    return "?";
}

void setPreferredTraceStage(TraceStage stage) { preferred() = stage; }
TraceStage preferredTraceStage() { return preferred(); }

TraceStage autoTraceStage(const RendererTraits& renderer) {
    return renderer.software ? TraceStage::Fragment : TraceStage::Compute;
}

TraceStage resolveTraceStage(TraceStage requested) {
    if (requested != TraceStage::Auto) return requested;
    if (const char* forced = std::getenv("CHCRT_SHADER_STAGE"); forced != nullptr && *forced != '\0') {
        const TraceStage stage = parseTraceStage(forced);
        if (stage == TraceStage::Auto) throw InputError("CHCRT_SHADER_STAGE must be fragment or compute, not 'auto'");
        return stage;
    }
    return autoTraceStage(currentRendererTraits());
}

} // namespace chcrt
