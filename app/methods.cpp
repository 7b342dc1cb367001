#include "app/methods.h"

#include "culling/chcrt_tracer.h"
#include "renderer/core/error.h"

namespace chcrt::app {

const std::vector<MethodInfo>& gpuMethods() {
    static const std::vector<MethodInfo> methods = {
        {"bvh", true, "pure BVH traversal in GLSL (the baseline)"},
        {"chcrt", true, "CHC+RT: occlusion-query culling of BVH subtrees per screen tile (conservative, exact)"},
        {"chcrt-aggressive", false, "CHC+RT culling pairs whose query passes <= 20 rays (approximate)"},
    };
    return methods;
}

const MethodInfo& findGpuMethod(const std::string& name) {
    std::string names;
    for (const MethodInfo& m : gpuMethods()) {
        if (m.name == name) return m;
        names += (names.empty() ? "" : ", ") + m.name;
    }
    throw InputError("unknown method '" + name + "' (available: " + names + ", embree)");
}

std::unique_ptr<Tracer> makeTracer(const std::string& name, const SceneSession& session, const GpuSession& /*gpu*/) {
    findGpuMethod(name);
    if (name == "chcrt") return std::make_unique<ChcrtTracer>(session.bvh);
    if (name == "chcrt-aggressive") {
        // CHC+RT §7, Table 4: a pair counts as visible only when more rays than the threshold pass its query.
        ChcrtOptions options;
        options.visibleThreshold = 20;
        return std::make_unique<ChcrtTracer>(session.bvh, options, name);
    }
    return nullptr; // "bvh"
}

} // namespace chcrt::app
