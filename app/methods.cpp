#include "app/methods.h"

#include "renderer/core/error.h"

namespace chcrt::app {

const std::vector<MethodInfo>& gpuMethods() {
    static const std::vector<MethodInfo> methods = {
        {"bvh", true, "pure BVH traversal in GLSL (the baseline)"},
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

std::unique_ptr<Tracer> makeTracer(const std::string& name, const SceneSession& /*session*/, const GpuSession& /*gpu*/) {
    findGpuMethod(name);
    return nullptr; // "bvh"
}

} // namespace chcrt::app
