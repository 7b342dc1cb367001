#include "app/viewer/viewer_settings.h"

#include "app/methods.h"
#include "app/parameters.h"
#include "renderer/core/error.h"
#include "renderer/outofcore/chs_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string_view>

namespace chcrt::app {
namespace {

std::string formatVec3(const glm::vec3& v) {
    return formatFloat(v.x) + "," + formatFloat(v.y) + "," + formatFloat(v.z);
}

template <typename T>
T jsonValue(const nlohmann::json& value, const std::string& key) {
    try {
        return value.get<T>();
    } catch (const nlohmann::json::exception&) {
        throw InputError("viewer setting '" + key + "' has the wrong type: " + value.dump());
    }
}

bool isMethodParameter(const Parameter& p) { return isMethodArea(p.area); }

// Options shared by the render and bench lines: scene, camera, size, and every parameter of the table that
// applies (app/parameters.h, Emit): sampling, the method's parameters, out of core.
std::string commonArguments(const ViewerSettings& s, const Camera& camera, int width, int height) {
    const CommonOptions& c = s.common;
    std::string line = "--scene " + shellWord(c.scene);
    line += " --eye " + formatVec3(camera.eye) + " --target " + formatVec3(camera.target);
    line += " --fov " + formatFloat(camera.fovYDegrees);
    line += " --width " + std::to_string(width) + " --height " + std::to_string(height);
    const MethodInfo* method = viewerMethod(s);
    const bool outOfCore = c.outOfCoreScene.enabled && outofcore::isPreparedScenePath(c.scene); // the GPU subtree cache
    line += commandLineArguments(c, [&](ParameterArea area) {
        if (area == ParameterArea::OutOfCore) return outOfCore;
        return !isMethodArea(area) || (method && method->reads(area));
    });
    return line;
}

// The viewer's own settings (not flags of the table), by key; false for other keys.
bool applyViewerSetting(ViewerSettings& s, const std::string& key, const nlohmann::json& value) {
    if (key == "method") {
        const std::string name = jsonValue<std::string>(value, key);
        if (name != kRasterOnlyMethod) findGpuMethod(name); // throws, listing the methods
        s.method = name;
    } else if (key == "viewMode") {
        s.viewMode = parseViewMode(jsonValue<std::string>(value, key));
    } else if (key == "chcrtAlwaysCull") {
        s.chcrtAlwaysCull = jsonValue<bool>(value, key);
    } else if (key == "renderScale") {
        s.renderScale = jsonValue<float>(value, key);
    } else if (key == "accumulate") {
        s.accumulate = jsonValue<bool>(value, key);
    } else if (key == "maxAccumulatedFrames") {
        s.maxAccumulatedFrames = jsonValue<int>(value, key);
    } else if (key == "refineWithFullRotation") {
        s.refineWithFullRotation = jsonValue<bool>(value, key);
    } else if (key == "costRayType") {
        s.costRayType = parseRayType(jsonValue<std::string>(value, key));
    } else if (key == "costScale") {
        s.costScale = jsonValue<float>(value, key);
    } else {
        return false;
    }
    return true;
}

[[noreturn]] void unknownSetting(const std::string& key) {
    std::string keys = "method, viewMode, chcrtAlwaysCull, renderScale, accumulate, maxAccumulatedFrames, "
                       "refineWithFullRotation, costRayType, costScale";
    for (const Parameter& p : parameterTable()) {
        if (!p.key.empty()) keys += ", " + p.key;
    }
    throw InputError("unknown viewer setting '" + key + "' (" + keys + ")");
}

} // namespace

std::vector<std::string> viewerMethods() {
    std::vector<std::string> names = {kRasterOnlyMethod};
    for (const MethodInfo* m : gpuMethods()) names.push_back(m->name);
    return names;
}

const MethodInfo* viewerMethod(const ViewerSettings& s) {
    return s.method == kRasterOnlyMethod ? nullptr : &findGpuMethod(s.method);
}

CommonOptions shownParameters(const ViewerSettings& s, uint64_t sceneTriangles) {
    const MethodInfo* method = viewerMethod(s);
    return method ? resolveMethodOptions(*method, s.common, sceneTriangles) : s.common;
}

void internalSize(const ViewerSettings& s, int windowWidth, int windowHeight, int& width, int& height) {
    width = std::max(1, int(std::lround(windowWidth * s.renderScale)));
    height = std::max(1, int(std::lround(windowHeight * s.renderScale)));
}

RenderSettings toRenderSettings(const ViewerSettings& s, int width, int height, int accumulatedFrame) {
    CommonOptions c = s.common;
    c.render.width = width;
    c.render.height = height;
    RenderSettings r = chcrt::app::toRenderSettings(c, c.render.samplesPerPixel);
    if (s.method == kRasterOnlyMethod) {
        // "raster": no secondary rays. With --primary traced its G-buffer comes from primary rays traced with
        // pure BVH (the renderer's own tracer), the reference the other methods' traced G-buffers equal.
        r.effects = EffectSet{false, false, false};
    }
    if (s.sceneNotInCore) { // as openGpuSession: out-of-core primary rays, no id-indexed bounce shading
        r.primaryVisibility = PrimaryVisibility::Traced;
        r.effects.diffuse = false;
    }
    if (accumulatedFrame > 0) {
        r.seed = s.common.render.seed + uint32_t(accumulatedFrame);
        if (s.refineWithFullRotation) r.rotationDegrees = 360.0f;
    }
    return r;
}

void applySettings(ViewerSettings& settings, const nlohmann::json& changes) {
    if (!changes.is_object()) throw InputError("viewer settings must be a JSON object, got " + changes.dump());
    ViewerSettings s = settings; // validate everything on a copy first
    for (const auto& [key, value] : changes.items()) {
        if (applyViewerSetting(s, key, value)) continue;
        const Parameter* p = findParameterByKey(key);
        if (!p) unknownSetting(key);
        setParameter(s.common, *p, value); // validates (the same checks as the command line)
    }
    if (!(s.renderScale >= 0.05f && s.renderScale <= 2.0f)) throw InputError("renderScale must be in [0.05, 2]");
    if (s.maxAccumulatedFrames < 1) throw InputError("maxAccumulatedFrames must be at least 1");
    if (!(s.costScale > 0.0f)) throw InputError("costScale must be positive");
    toRenderSettings(s, 1, 1, 0); // validates effects, rotation, lengths, exposure
    settings = s;
}

std::string methodParameters(const CommonOptions& c) { return givenParameters(c, isMethodParameter); }

void copyMethodParameters(const CommonOptions& from, CommonOptions& to) { copyParameters(from, to, isMethodParameter); }

std::string renderCommandLine(const ViewerSettings& s, const Camera& camera, int width, int height) {
    const bool raster = s.method == kRasterOnlyMethod;
    // The raster method has no tracer of its own: its render line traces (--primary traced) with pure BVH.
    std::string line = "chcrt render " + commonArguments(s, camera, width, height) + " --method " +
                       (raster ? std::string(kPureBvhMethod) : s.method);
    line += " --effects " + (raster ? std::string("none") : toString(s.common.render.effects));
    line += " --exposure " + formatFloat(s.common.render.exposure) + " -o view.png";
    return line;
}

std::string benchCommandLine(const ViewerSettings& s, const Camera& camera, int width, int height) {
    std::string rayTypes;
    const EffectSet& effects = s.common.render.effects;
    if (effects.shadows) rayTypes += "shadow,";
    if (effects.ao) rayTypes += "ao,";
    if (effects.diffuse) rayTypes += "diffuse,";
    rayTypes = rayTypes.empty() ? "primary" : rayTypes.substr(0, rayTypes.size() - 1);
    const std::string method = s.method == kRasterOnlyMethod ? std::string(kPureBvhMethod) : s.method;
    return "chcrt bench " + commonArguments(s, camera, width, height) + " --method " + method + " --ray-type " +
           rayTypes;
}

} // namespace chcrt::app
