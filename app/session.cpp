#include "app/session.h"

#include "renderer/core/error.h"
#include "renderer/core/frame_range.h"
#include "renderer/core/output_path.h"
#include "renderer/outofcore/chs_file.h"
#include "renderer/render/frame_targets.h"
#include "renderer/render/scene_gpu.h"
#include "renderer/scene/scene_loader.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <unistd.h>

namespace chcrt::app {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

CameraPath resolveGltfCamera(const Scene& scene, const std::string& selector) {
    const std::string key = selector.substr(5);
    if (scene.cameras.empty()) throw InputError("--camera " + selector + ": the scene has no cameras");
    for (size_t i = 0; i < scene.cameras.size(); ++i) {
        if (scene.cameras[i].name == key || std::to_string(i) == key) {
            return singleCameraPath(scene.cameras[i].camera, "gltf-camera-" + key);
        }
    }
    throw InputError("--camera " + selector + ": no camera with that index or name (the scene has " +
                     std::to_string(scene.cameras.size()) + ")");
}

CameraPath resolveCameraPath(const CommonOptions& o, const SceneSession& s) {
    if (!o.eye.empty() || !o.target.empty()) {
        if (o.eye.empty() || o.target.empty()) throw InputError("--eye and --target must be given together");
        Camera camera;
        camera.eye = parseVec3(o.eye, "--eye");
        camera.target = parseVec3(o.target, "--target");
        camera.fovYDegrees = o.fovY;
        if (!(o.fovY > 0.0f && o.fovY < 180.0f)) throw InputError("--fov must be between 0 and 180 degrees");
        if (camera.eye == camera.target) throw InputError("--eye and --target must differ");
        return singleCameraPath(camera, "explicit-camera");
    }
    if (!o.camera.empty()) {
        if (o.camera.rfind("gltf:", 0) != 0) throw InputError("--camera expects gltf:<index or name>");
        return resolveGltfCamera(s.scene, o.camera);
    }
    if (o.cameraPath == "near" || o.cameraPath == "far" || o.cameraPath.empty()) {
        if (s.procedural) {
            return o.cameraPath == "far" ? proceduralFarPath(*s.procedural) : proceduralNearPath(*s.procedural);
        }
        if (!o.cameraPath.empty()) {
            throw InputError("--camera-path " + o.cameraPath + " exists only for generated scenes; give a JSON file");
        }
        // A file that stores a camera was framed by its author: its first camera is the default view.
        if (!s.scene.cameras.empty()) return resolveGltfCamera(s.scene, "gltf:0");
        return singleCameraPath(defaultCamera(s.scene, o.fovY), "default-camera");
    }
    return loadCameraPath(o.cameraPath);
}

// The N of "all:N" / "spread:N": a positive integer, else InputError.
int parseFrameCountSuffix(const std::string& text, size_t prefixLength) {
    const std::string digits = text.substr(prefixLength);
    int value = 0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() || value < 1) {
        throw InputError("--frames " + text + ": expected a positive whole number after ':'");
    }
    return value;
}

// Whether a prepared scene is loaded in core: always without --out-of-core; with it by --load-in-core (auto: when
// the estimated host footprint is below a quarter of the physical memory and, where the driver reports GPU memory,
// the scene's GPU buffers take less than half of the available GPU memory; the rest is for the frame's targets,
// the out-of-core tracer's cache and the driver).
bool loadPreparedInCore(const CommonOptions& o) {
    if (!o.outOfCoreScene.enabled) return true;
    if (o.outOfCoreScene.loadInCore != LoadInCore::Auto) return o.outOfCoreScene.loadInCore == LoadInCore::On;
    const outofcore::ChsHeader header = outofcore::ChsFile(o.scene).header();
    const uint64_t ram = uint64_t(sysconf(_SC_PHYS_PAGES)) * uint64_t(sysconf(_SC_PAGE_SIZE));
    if (outofcore::estimatedInCoreBytes(header.triangleCount) >= ram / 4) return false;
    // GPU memory is a property of the device the session will render on: asked on a context of its own.
    const GpuMemoryInfo gpu = [&o] {
        const auto probe = createHeadlessContext(o.gl, false, o.glDevice);
        return queryGpuMemory();
    }();
    if (!gpu.reported) return true;
    const uint64_t gpuBytes = SceneGpu::estimatedBytes(header.triangleCount, 3 * header.triangleCount,
                                                       header.nodeCount + header.upperNodeCount);
    return gpuBytes < gpu.availableBytes / 2;
}

// A --scene that is neither a generator nor an existing file: say both, with the generators, rather than "no such
// file" for what was meant as a generator ("town:10k"); a directory is named as one.
void refuseWhatIsNoSceneFile(const std::string& scene) {
    std::error_code error;
    const std::filesystem::path file(scene);
    if (std::filesystem::is_directory(file, error)) {
        throw InputError(scene + ": is a directory, not a scene file (.gltf, .glb, .ply, .obj or .chs)");
    }
    if (!std::filesystem::exists(file, error)) {
        throw InputError(scene + ": neither a scene file (no such file) nor a generator (" + proceduralGeneratorNames() +
                         ", e.g. city:2m:seed=3)");
    }
}

// A scene loaded with warnings renders, but not silently: each is printed; --strict refuses the scene.
void reportLoadWarnings(const CommonOptions& o, const Scene& scene) {
    if (scene.warnings.empty()) return;
    if (o.strict) {
        throw InputError(scene.warnings.front() + (scene.warnings.size() > 1 ? " (and " + std::to_string(scene.warnings.size() - 1) + " more warning(s))" : std::string()) + " [--strict]");
    }
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
}

// Out-of-core budgets and choices only act with --out-of-core: say so rather than ignore them silently.
void warnAboutOutOfCoreFlagsWithoutOutOfCore(const CommonOptions& o) {
    if (o.outOfCoreScene.enabled) return;
    for (const char* flag : {"--gpu-cache-mb", "--host-cache-mb", "--uploads-per-trace", "--cache-policy", "--load-in-core"}) {
        if (o.isGiven(flag)) std::fprintf(stderr, "warning: %s has no effect without --out-of-core\n", flag);
    }
}

// The triangles a scene will have in core, as far as they are known before it is loaded: a generator's count
// (generators land within 10 % of it) or a prepared scene's header; 0 for scene files (checked once loaded).
uint64_t trianglesKnownUpFront(const CommonOptions& o, bool prepared, bool inCore) {
    if (prepared) return inCore ? outofcore::ChsFile(o.scene).header().triangleCount : 0;
    ProceduralSpec spec;
    if (!parseProceduralSpec(o.scene, spec)) return 0;
    const bool analytic = spec.kind == ProceduralKind::PlaneAndBox || spec.kind == ProceduralKind::ClosedBox ||
                          spec.kind == ProceduralKind::OneTriangle; // a few triangles whatever the count says
    return analytic ? 0 : spec.targetTriangles / 10 * 11;
}

} // namespace

MemoryParts sessionMemory(const CommonOptions& o, uint64_t sceneTriangles) {
    const uint64_t pixels = uint64_t(std::max(o.render.width, 0)) * uint64_t(std::max(o.render.height, 0));
    MemoryParts parts;
    // The targets and the image read back from them (RGBA32F).
    parts.emplace_back("render targets " + std::to_string(o.render.width) + "x" + std::to_string(o.render.height),
                       pixels * (FrameTargets::kBytesPerPixel + 16));
    parts.emplace_back("scene and BVH of " + std::to_string(sceneTriangles) + " triangles",
                       outofcore::estimatedInCoreBytes(sceneTriangles));
    if (o.outOfCoreScene.enabled) {
        parts.emplace_back("--gpu-cache-mb", o.outOfCore.gpuCacheBytes);
        parts.emplace_back("--host-cache-mb", o.outOfCore.hostCacheBytes);
    }
    return parts;
}

MemoryParts sessionMemory(const SceneSession& s) {
    return sessionMemory(s.options, s.sceneInCore ? s.scene.triangleCount() : 0);
}

SceneSession openSceneSession(const CommonOptions& o, std::unique_ptr<Progress> progress) {
    warnAboutOutOfCoreFlagsWithoutOutOfCore(o);
    setMemoryBudgetBytes(o.maxMemoryBytes);
    SceneSession s;
    s.options = o;
    s.progress = progress ? std::move(progress) : makeTerminalProgress(!o.quiet);
    const auto start = Clock::now();
    ProceduralSpec spec;
    const bool prepared = outofcore::isPreparedScenePath(o.scene);
    if (prepared) s.sceneInCore = loadPreparedInCore(o);
    checkMemoryBudget(sessionMemory(o, trianglesKnownUpFront(o, prepared, s.sceneInCore)));
    if (prepared) { // a prepared scene loaded in core: its BVH comes from the file (renderer/outofcore/)
        s.progress->begin(std::string(s.sceneInCore ? "Loading " : "Opening (out of core) ") + o.scene, 0);
        outofcore::LoadedPreparedScene loaded = s.sceneInCore ? outofcore::loadPreparedScene(o.scene)
                                                              : outofcore::loadPreparedSceneProxy(o.scene);
        s.progress->end();
        s.fileTriangles = outofcore::ChsFile(o.scene).header().triangleCount;
        s.scene = std::move(loaded.scene);
        s.bvh = std::move(loaded.bvh);
        s.light = loaded.light;
        if (parseProceduralSpec(loaded.source, spec)) s.procedural = spec;
    } else if (parseProceduralSpec(o.scene, spec)) {
        s.scene = generateProceduralScene(spec, *s.progress);
        s.procedural = spec;
        s.light = proceduralAreaLight(spec);
    } else {
        refuseWhatIsNoSceneFile(o.scene);
        s.scene = loadSceneFile(o.scene, *s.progress);
        s.light = defaultAreaLight(s.scene);
    }
    reportLoadWarnings(o, s.scene);
    validateScene(s.scene);
    s.sceneSeconds = secondsSince(start);
    s.path = resolveCameraPath(o, s);
    if (!prepared && !s.procedural) checkMemoryBudget(sessionMemory(s)); // a scene file: now its size is known
    if (!prepared) s.bvh = buildBvh(s.scene, o.bvh, *s.progress);
    return s;
}

std::vector<int> selectFrames(const CommonOptions& o, const CameraPath& path, const std::string& defaultFrames) {
    if (o.frames.empty() && o.isGiven("--frames")) {
        throw InputError("--frames is empty: give frames like 7, 1-100, 3,5-9 or all (see chcrt --help)");
    }
    const std::string text = o.frames.empty() ? defaultFrames : o.frames;
    const int count = path.frameCount();
    std::vector<int> frames;
    if (text == "all" || text.rfind("all:", 0) == 0) {
        const int step = text == "all" ? 1 : parseFrameCountSuffix(text, 4);
        for (int f = 0; f < count; f += step) frames.push_back(f);
    } else if (text.rfind("spread:", 0) == 0) {
        const int n = std::min(parseFrameCountSuffix(text, 7), count);
        for (int i = 0; i < n; ++i) frames.push_back(n == 1 ? 0 : int(int64_t(i) * (count - 1) / (n - 1)));
        frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
    } else {
        frames = parseFrameRange(text);
    }
    for (int f : frames) {
        if (f >= count) {
            throw InputError("--frames: frame " + std::to_string(f) + " is past the end of the camera path (" +
                             std::to_string(count) + " frames, 0-" + std::to_string(count - 1) + ")");
        }
    }
    return frames;
}

void checkOutputFiles(const std::vector<std::string>& files) {
    for (const std::string& file : files) {
        if (!file.empty()) checkOutputPath(file);
    }
}

void warnIfSoftwareRenderer(const CommonOptions& o, const GlContext& context) {
    if (o.quiet) return; // -q: errors only (scripts and tests read one line per failure)
    const GlInfo info = queryGlInfo();
    if (!info.softwareRenderer) return;
    const bool autoDevice = o.gl == GlBackend::Egl && o.glDevice == kAutoGlDevice;
    std::fprintf(stderr, "warning: OpenGL renders on the software renderer %s (%s): timings are CPU timings, not GPU "
                         "timings%s\n",
                 info.renderer.c_str(), context.description().c_str(),
                 autoDevice ? "; --gl-device auto found no hardware EGL device that makes an OpenGL 4.5 core context "
                              "(chcrt info --devices lists them)"
                            : "");
}

GpuSession openGpuSession(const CommonOptions& o, const SceneSession& s, const RenderSettings& settings) {
    const auto start = Clock::now();
    GpuSession g;
    g.context = createHeadlessContext(o.gl, o.glDebug, o.glDevice);
    warnIfSoftwareRenderer(o, *g.context);
    setPreferredTraceStage(o.shaderStage);
    RenderSettings effective = settings;
    if (!s.sceneInCore) {
        // Not in core (docs/outofcore.md): primary visibility from out-of-core primary rays; the diffuse effect
        // shades bounce hits through per-triangle buffers of the whole scene, which do not exist here.
        effective.primaryVisibility = PrimaryVisibility::Traced;
        if (effective.effects.diffuse && !o.quiet) {
            std::fprintf(stderr, "chcrt: note: the diffuse effect needs the scene in core; rendering without it\n");
        }
        effective.effects.diffuse = false;
    }
    g.renderer = std::make_unique<Renderer>(s.scene, s.bvh, s.light, effective);
    g.setupSeconds = secondsSince(start);
    return g;
}

} // namespace chcrt::app
