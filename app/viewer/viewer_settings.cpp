#include "app/viewer/viewer_settings.h"

#include "app/methods.h"
#include "renderer/core/error.h"
#include "renderer/outofcore/chs_file.h"
#include "linespace/ntree_tracer.h"

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

std::string formatFloat(float value) {
    // The shortest text that reads back as the same float (9 significant digits always do).
    char text[32];
    for (int digits = 6; digits <= 9; ++digits) {
        std::snprintf(text, sizeof(text), "%.*g", digits, double(value));
        if (std::strtof(text, nullptr) == value) break;
    }
    return text;
}

std::string formatVec3(const glm::vec3& v) {
    return formatFloat(v.x) + "," + formatFloat(v.y) + "," + formatFloat(v.z);
}

// Quotes a shell word when it holds anything but safe characters.
std::string shellWord(const std::string& word) {
    const bool safe = !word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) ||
               std::string_view("-_./:,=+").find(c) != std::string_view::npos;
    });
    if (safe) return word;
    std::string quoted = "'";
    for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

template <typename T>
T jsonValue(const nlohmann::json& value, const std::string& key) {
    try {
        return value.get<T>();
    } catch (const nlohmann::json::exception&) {
        throw InputError("viewer setting '" + key + "' has the wrong type: " + value.dump());
    }
}

// Options shared by the render and bench lines: scene, camera, size, sampling.
std::string commonArguments(const ViewerSettings& s, const Camera& camera, int width, int height) {
    const CommonOptions& c = s.common;
    std::string line = "--scene " + shellWord(c.scene);
    line += " --eye " + formatVec3(camera.eye) + " --target " + formatVec3(camera.target);
    line += " --fov " + formatFloat(camera.fovYDegrees);
    line += " --width " + std::to_string(width) + " --height " + std::to_string(height);
    line += " --spp " + std::to_string(std::max(c.spp, 1)) + " --seed " + std::to_string(c.seed);
    line += " --rotation " + formatFloat(c.rotation) + " --ao-length " + formatFloat(c.aoLength);
    if (c.primary != CommonOptions{}.primary) line += " --primary " + c.primary;
    if (c.bvhLeafSize != CommonOptions{}.bvhLeafSize) line += " --bvh-leaf-size " + std::to_string(c.bvhLeafSize);
    if (s.method.rfind("chcrt", 0) == 0) { // the CHC+RT parameters changed in the panel
        const CommonOptions d;
        if (c.chcrtThreshold != d.chcrtThreshold) line += " --chcrt-threshold " + std::to_string(c.chcrtThreshold);
        if (c.chcrtMinTile != d.chcrtMinTile) line += " --chcrt-min-tile " + std::to_string(c.chcrtMinTile);
        if (c.chcrtHeight != d.chcrtHeight) line += " --chcrt-height " + std::to_string(c.chcrtHeight);
        if (c.chcrtMultiQuery != d.chcrtMultiQuery) line += " --chcrt-multi-query " + std::to_string(c.chcrtMultiQuery);
        if (!c.chcrtTighterBounds.empty()) line += " --chcrt-tighter-bounds " + c.chcrtTighterBounds;
        if (!c.chcrtRayExtent.empty()) line += " --chcrt-ray-extent " + c.chcrtRayExtent;
        if (!c.chcrtLeafCache.empty()) line += " --chcrt-leaf-cache " + c.chcrtLeafCache;
        if (!c.chcrtMergedBatch.empty()) line += " --chcrt-merged-batch " + c.chcrtMergedBatch;
    }
    if (s.method.find("+ls") != std::string::npos) { // Line Space parameters changed in the panel
        const CommonOptions d;
        if (c.lsN != d.lsN) line += " --ls-n " + std::to_string(c.lsN);
        if (c.lsDepth != d.lsDepth) line += " --ls-depth " + std::to_string(c.lsDepth);
        if (c.lsT != d.lsT) line += " --ls-t " + std::to_string(c.lsT);
        if (c.lsAngle != d.lsAngle) line += " --ls-angle " + formatFloat(c.lsAngle);
        if (!c.lsModes.empty()) line += " --ls-modes " + shellWord(c.lsModes);
        if (!c.lsNtree.empty()) line += " --ls-ntree " + c.lsNtree;
        if (s.method == "ntree+ls") {
            if (c.lsNtreeLevel != d.lsNtreeLevel) line += " --ls-ntree-level " + std::to_string(c.lsNtreeLevel);
            if (c.lsNtreeStart != d.lsNtreeStart) line += " --ls-ntree-start " + c.lsNtreeStart;
            if (c.lsNtreeNear != d.lsNtreeNear) line += " --ls-ntree-near " + formatFloat(c.lsNtreeNear);
        }
    }
    if (c.outOfCore && outofcore::isPreparedScenePath(c.scene)) { // CHC+RT through the GPU subtree cache
        const CommonOptions d;
        line += " --out-of-core --gpu-cache-mb " + std::to_string(c.gpuCacheMb) + " --host-cache-mb " +
                std::to_string(c.hostCacheMb);
        if (c.cachePolicy != d.cachePolicy) line += " --cache-policy " + c.cachePolicy;
        if (c.loadInCore != d.loadInCore) line += " --load-in-core " + c.loadInCore;
    }
    if (c.bvhBins != CommonOptions{}.bvhBins) line += " --bvh-bins " + std::to_string(c.bvhBins);
    return line;
}

} // namespace

std::vector<std::string> viewerMethods() {
    std::vector<std::string> names = {kRasterOnlyMethod};
    for (const MethodInfo& m : gpuMethods()) names.push_back(m.name);
    return names;
}

void internalSize(const ViewerSettings& s, int windowWidth, int windowHeight, int& width, int& height) {
    width = std::max(1, int(std::lround(windowWidth * s.renderScale)));
    height = std::max(1, int(std::lround(windowHeight * s.renderScale)));
}

RenderSettings toRenderSettings(const ViewerSettings& s, int width, int height, int accumulatedFrame) {
    CommonOptions c = s.common;
    c.width = width;
    c.height = height;
    RenderSettings r = chcrt::app::toRenderSettings(c, 1);
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
        r.seed = s.common.seed + uint32_t(accumulatedFrame);
        if (s.refineWithFullRotation) r.rotationDegrees = 360.0f;
    }
    return r;
}

void applySettings(ViewerSettings& settings, const nlohmann::json& changes) {
    if (!changes.is_object()) throw InputError("viewer settings must be a JSON object, got " + changes.dump());
    ViewerSettings s = settings; // validate everything on a copy first
    for (const auto& [key, value] : changes.items()) {
        if (key == "method") {
            const std::string name = jsonValue<std::string>(value, key);
            if (name != kRasterOnlyMethod) findGpuMethod(name); // throws, listing the methods
            s.method = name;
        } else if (key == "viewMode") {
            s.viewMode = parseViewMode(jsonValue<std::string>(value, key));
        } else if (key == "chcrtThreshold") {
            s.common.chcrtThreshold = jsonValue<int>(value, key);
        } else if (key == "chcrtMinTile") {
            s.common.chcrtMinTile = jsonValue<int>(value, key);
        } else if (key == "chcrtHeight") {
            s.common.chcrtHeight = jsonValue<int>(value, key);
        } else if (key == "chcrtMultiQuery") {
            s.common.chcrtMultiQuery = jsonValue<int>(value, key);
        } else if (key == "chcrtTighterBounds") {
            s.common.chcrtTighterBounds = jsonValue<bool>(value, key) ? "on" : "off";
        } else if (key == "chcrtLeafCache") {
            s.common.chcrtLeafCache = jsonValue<bool>(value, key) ? "on" : "off";
        } else if (key == "chcrtMergedBatch") {
            s.common.chcrtMergedBatch = jsonValue<bool>(value, key) ? "on" : "off";
        } else if (key == "chcrtRayExtent") {
            s.common.chcrtRayExtent = jsonValue<bool>(value, key) ? "on" : "off";
        } else if (key == "lsN") {
            s.common.lsN = jsonValue<uint32_t>(value, key);
        } else if (key == "lsDepth") {
            s.common.lsDepth = jsonValue<uint32_t>(value, key);
        } else if (key == "lsT") {
            s.common.lsT = jsonValue<uint32_t>(value, key);
        } else if (key == "lsAngle") {
            s.common.lsAngle = jsonValue<float>(value, key);
        } else if (key == "lsNtree") {
            s.common.lsNtree = jsonValue<std::string>(value, key);
        } else if (key == "lsNtreeLevel") {
            s.common.lsNtreeLevel = jsonValue<int>(value, key);
        } else if (key == "lsNtreeStart") {
            s.common.lsNtreeStart = jsonValue<std::string>(value, key);
        } else if (key == "lsNtreeNear") {
            s.common.lsNtreeNear = jsonValue<float>(value, key);
        } else if (key == "chcrtAlwaysCull") {
            s.chcrtAlwaysCull = jsonValue<bool>(value, key);
        } else if (key == "primary") {
            const std::string primary = jsonValue<std::string>(value, key);
            parsePrimaryVisibility(primary); // throws for anything but raster / traced
            s.common.primary = primary;
        } else if (key == "effects") {
            s.common.effects = jsonValue<std::string>(value, key);
        } else if (key == "spp") {
            s.common.spp = jsonValue<int>(value, key);
        } else if (key == "seed") {
            s.common.seed = jsonValue<uint32_t>(value, key);
        } else if (key == "rotation") {
            s.common.rotation = jsonValue<float>(value, key);
        } else if (key == "aoLength") {
            s.common.aoLength = jsonValue<float>(value, key);
        } else if (key == "exposure") {
            s.common.exposure = jsonValue<float>(value, key);
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
            throw InputError("unknown viewer setting '" + key +
                             "' (method, viewMode, primary, chcrtAlwaysCull, chcrtThreshold, chcrtMinTile, "
                             "chcrtHeight, chcrtMultiQuery, chcrtTighterBounds, chcrtLeafCache, chcrtMergedBatch, chcrtRayExtent, lsN, lsDepth, lsT, "
                             "lsAngle, lsNtree, lsNtreeLevel, lsNtreeStart, lsNtreeNear, effects, spp, seed, "
                             "rotation, aoLength, exposure, renderScale, "
                             "accumulate, maxAccumulatedFrames, refineWithFullRotation, costRayType, costScale)");
        }
    }
    if (!(s.renderScale >= 0.05f && s.renderScale <= 2.0f)) throw InputError("renderScale must be in [0.05, 2]");
    if (s.maxAccumulatedFrames < 1) throw InputError("maxAccumulatedFrames must be at least 1");
    if (!(s.costScale > 0.0f)) throw InputError("costScale must be positive");
    if (s.common.spp < 1) throw InputError("spp must be at least 1");
    // Method parameters: -1 = the method's default; the tracers validate the rest when they are created.
    if (s.common.chcrtThreshold < -1 || s.common.chcrtMinTile < -1 || s.common.chcrtMinTile == 0 ||
        s.common.chcrtHeight < -1 || s.common.chcrtHeight == 0 || s.common.chcrtMultiQuery < -1 ||
        s.common.chcrtMultiQuery == 0) {
        throw InputError("CHC+RT parameters must be positive (threshold: >= 0)");
    }
    if (s.common.lsN < 1 || s.common.lsDepth < 1 || s.common.lsT < 1 || !(s.common.lsAngle >= 0.0f)) {
        throw InputError("Line Space parameters must be positive");
    }
    // N-tree parameters (ntree+ls, app/methods.cpp makeNTreeTracer): the same checks as the command line.
    if (!s.common.lsNtree.empty()) ls::parseNTreeParams(s.common.lsNtree);
    if (s.common.lsNtreeLevel < -1) throw InputError("lsNtreeLevel must be -1 (d-1) or a level >= 0");
    if (s.common.lsNtreeStart != "skip" && s.common.lsNtreeStart != "exact") {
        throw InputError("lsNtreeStart must be skip or exact, not '" + s.common.lsNtreeStart + "'");
    }
    if (!(s.common.lsNtreeNear >= 0.0f && s.common.lsNtreeNear <= 1000.0f)) throw InputError("lsNtreeNear must be in 0..1000");
    toRenderSettings(s, 1, 1, 0); // validates effects, rotation, lengths, exposure
    settings = s;
}

std::string methodParameters(const CommonOptions& c) {
    std::ostringstream out;
    out << c.chcrtThreshold << ' ' << c.chcrtMinTile << ' ' << c.chcrtHeight << ' ' << c.chcrtMultiQuery << ' '
        << c.chcrtTighterBounds << ' ' << c.chcrtLeafCache << ' ' << c.chcrtMergedBatch << ' ' << c.chcrtRayExtent << ' ' << c.lsN << ' ' << c.lsDepth << ' ' << c.lsT << ' '
        << c.lsAngle << ' ' << c.lsNtree << ' ' << c.lsNtreeLevel << ' ' << c.lsNtreeStart << ' ' << c.lsNtreeNear
        << ' ' << c.lsModes;
    return out.str();
}

void copyMethodParameters(const CommonOptions& from, CommonOptions& to) {
    to.chcrtThreshold = from.chcrtThreshold;
    to.chcrtMinTile = from.chcrtMinTile;
    to.chcrtHeight = from.chcrtHeight;
    to.chcrtMultiQuery = from.chcrtMultiQuery;
    to.chcrtTighterBounds = from.chcrtTighterBounds;
    to.chcrtLeafCache = from.chcrtLeafCache;
    to.chcrtMergedBatch = from.chcrtMergedBatch;
    to.chcrtRayExtent = from.chcrtRayExtent;
    to.lsN = from.lsN;
    to.lsDepth = from.lsDepth;
    to.lsT = from.lsT;
    to.lsAngle = from.lsAngle;
    to.lsNtree = from.lsNtree;
    to.lsNtreeLevel = from.lsNtreeLevel;
    to.lsNtreeStart = from.lsNtreeStart;
    to.lsNtreeNear = from.lsNtreeNear;
    to.lsModes = from.lsModes;
}

std::string renderCommandLine(const ViewerSettings& s, const Camera& camera, int width, int height) {
    const bool raster = s.method == kRasterOnlyMethod;
    // The raster method has no tracer of its own: its render line traces (--primary traced) with pure BVH.
    std::string line = "chcrt render " + commonArguments(s, camera, width, height) + " --method " +
                       (raster ? std::string("bvh") : s.method);
    line += " --effects " + (raster ? std::string("none") : toString(parseEffects(s.common.effects)));
    line += " --exposure " + formatFloat(s.common.exposure) + " -o view.png";
    return line;
}

std::string benchCommandLine(const ViewerSettings& s, const Camera& camera, int width, int height) {
    std::string rayTypes;
    const EffectSet effects = parseEffects(s.common.effects);
    if (effects.shadows) rayTypes += "shadow,";
    if (effects.ao) rayTypes += "ao,";
    if (effects.diffuse) rayTypes += "diffuse,";
    rayTypes = rayTypes.empty() ? "primary" : rayTypes.substr(0, rayTypes.size() - 1);
    const std::string method = s.method == kRasterOnlyMethod ? "bvh" : s.method;
    return "chcrt bench " + commonArguments(s, camera, width, height) + " --method " + method + " --ray-type " +
           rayTypes;
}

} // namespace chcrt::app
