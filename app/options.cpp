#include "app/options.h"

#include "renderer/core/error.h"

#include <cmath>
#include <sstream>

namespace chcrt::app {

void addCommonOptions(CLI::App& c, CommonOptions& o, bool withEffects) {
    c.add_option("--scene", o.scene,
                 "Scene: a .gltf/.glb/.ply/.obj file or a generator spec (city, interior, plant, plane-and-box, "
                 "closed-box, one-triangle; e.g. city:2m:seed=3)")
        ->capture_default_str();
    c.add_option("--camera-path", o.cameraPath,
                 "Walkthrough JSON file, or near/far for a generated scene's street-level/bird's-eye path "
                 "(default: near for generated scenes, the default camera otherwise)");
    c.add_option("--camera", o.camera, "A camera stored in a glTF file: gltf:<index or name>");
    c.add_option("--eye", o.eye, "Explicit camera position x,y,z (with --target; overrides paths)");
    c.add_option("--target", o.target, "Explicit camera target x,y,z");
    c.add_option("--fov", o.fovY, "Vertical field of view in degrees for --eye/--target")->capture_default_str();
    c.add_option("--frames", o.frames, "Frames of the path: all, all:10 (every 10th), 7, 1-100, 1-100:10, 3,5-9, spread:5 (0-based)");
    c.add_option("--width", o.width, "Image width in pixels")->capture_default_str();
    c.add_option("--height", o.height, "Image height in pixels")->capture_default_str();
    c.add_option("--seed", o.seed, "Seed of the per-pixel sample perturbation")->capture_default_str();
    c.add_option("--rotation", o.rotation,
                 "Per-pixel random rotation of the shared sample in degrees (0, 18, 36, 360 = full)")
        ->capture_default_str();
    c.add_option("--ao-length", o.aoLength, "AO ray length as a fraction of the scene diagonal")->capture_default_str();
    c.add_option("--spp", o.spp, "Samples per pixel per effect (= ray passes)");
    if (withEffects) {
        c.add_option("--effects", o.effects, "Secondary effects: any of shadow,ao,diffuse, or all / none")
            ->capture_default_str();
        c.add_option("--exposure", o.exposure, "Exposure before tone mapping")->capture_default_str();
    }
    c.add_option("--gl", o.gl, "OpenGL context: egl (headless, default) or osmesa")->capture_default_str();
    c.add_flag("--gl-debug", o.glDebug, "Print KHR_debug messages from the driver");
    c.add_option("--stats-json", o.statsJson, "Write per-frame statistics as JSON to this file");
    c.add_flag("-q,--quiet", o.quiet, "No progress bars");
    c.add_option("--bvh-leaf-size", o.bvhLeafSize, "Maximum triangles per BVH leaf")->capture_default_str();
    c.add_option("--bvh-bins", o.bvhBins, "SAH bins per axis")->capture_default_str();
}

RenderSettings toRenderSettings(const CommonOptions& o, int defaultSpp) {
    RenderSettings s;
    s.width = o.width;
    s.height = o.height;
    s.samplesPerPixel = o.spp > 0 ? o.spp : defaultSpp;
    if (o.spp == 0 || o.spp < -1) throw InputError("--spp must be at least 1");
    s.effects = parseEffects(o.effects);
    s.seed = o.seed;
    s.rotationDegrees = o.rotation;
    s.aoLengthFraction = o.aoLength;
    s.exposure = o.exposure;
    validateSettings(s);
    return s;
}

BvhBuildOptions toBvhOptions(const CommonOptions& o) {
    if (o.bvhLeafSize < 1 || o.bvhLeafSize > 64) throw InputError("--bvh-leaf-size must be between 1 and 64");
    if (o.bvhBins < 2 || o.bvhBins > 256) throw InputError("--bvh-bins must be between 2 and 256");
    BvhBuildOptions b;
    b.maxLeafTriangles = o.bvhLeafSize;
    b.binCount = o.bvhBins;
    return b;
}

glm::vec3 parseVec3(const std::string& text, const char* flag) {
    std::stringstream stream(text);
    glm::vec3 v;
    char comma1 = 0, comma2 = 0;
    stream >> v.x >> comma1 >> v.y >> comma2 >> v.z;
    if (!stream || comma1 != ',' || comma2 != ',' || !(stream >> std::ws).eof() || !std::isfinite(v.x) ||
        !std::isfinite(v.y) || !std::isfinite(v.z)) {
        throw InputError(std::string(flag) + " expects three finite numbers x,y,z, got '" + text + "'");
    }
    return v;
}

} // namespace chcrt::app
