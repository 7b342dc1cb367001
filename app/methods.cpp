#include "app/methods.h"

#include "culling/chcrt_tracer.h"
#include "renderer/core/error.h"
#include <cstdlib>  // EXPERIMENT

namespace chcrt::app {

const std::vector<MethodInfo>& gpuMethods() {
    static const std::vector<MethodInfo> methods = {
        {"bvh", true, "pure BVH traversal in GLSL (the baseline)"},
        {"chcrt", true, "CHC+RT: occlusion-query culling of BVH subtrees per screen tile (conservative, exact)"},
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
    if (name == "chcrt") {
        ChcrtOptions o;
        if (const char* e = std::getenv("CHCRT_EXP_HEIGHT")) o.partition.maxSubtreeHeight = uint32_t(std::atoi(e));
        if (const char* e = std::getenv("CHCRT_EXP_TILE")) o.pairs.minTileSize = std::atoi(e);
        if (const char* e = std::getenv("CHCRT_EXP_TQ")) o.pairs.tq = float(std::atof(e));
        auto t = std::make_unique<ChcrtTracer>(session.bvh, o);
        return t;
    }
    return nullptr; // "bvh"
}

} // namespace chcrt::app
