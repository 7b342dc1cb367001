#pragma once
// What every command starts from: the scene (generated or loaded), its walkthrough, its light and BVH, and
// when needed a headless GL context with a Renderer. Timings of each step are kept for the summaries.
#include "app/options.h"
#include "renderer/bvh/bvh.h"
#include "renderer/core/memory_budget.h"
#include "renderer/core/progress.h"
#include "renderer/gl/context.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/camera_path.h"
#include "renderer/scene/procedural/procedural.h"
#include "renderer/scene/scene.h"

#include <memory>
#include <optional>
#include <vector>

namespace chcrt::app {

struct SceneSession {
    Scene scene;
    std::optional<ProceduralSpec> procedural; // set for generated scenes
    CameraPath path;
    AreaLight light;
    Bvh bvh;
    double sceneSeconds = 0; // load or generation
    std::unique_ptr<Progress> progress;
    CommonOptions options; // as opened (methods read their parameters, e.g. --ls-*)
    // False for an --out-of-core scene that was not loaded: `scene` and `bvh` are a geometry-free proxy
    // (outofcore::loadPreparedSceneProxy) and every hit comes from the out-of-core tracer.
    bool sceneInCore = true;
    uint64_t fileTriangles = 0; // triangles of a prepared scene's file
};

// Loads/generates the scene, resolves the camera path and builds the BVH (with progress bars on a TTY).
// `progress`: where the steps report instead (the viewer's panel); it becomes the session's progress.
// Sets the memory budget from --max-memory-mb and checks sessionMemory's estimate against it before loading
// (with the triangle count a generator spec or a prepared scene's header gives) and again before building the
// BVH of a scene file (InputError naming the flag; renderer/core/memory_budget.h).
SceneSession openSceneSession(const CommonOptions& options, std::unique_ptr<Progress> progress = nullptr);

// The big buffers of a session with `sceneTriangles` triangles in core: render targets at --width x --height,
// the scene with its BVH and GPU copies (outofcore::estimatedInCoreBytes), and with --out-of-core the two
// subtree caches' budgets. A tracer adds its own parts (Line Spaces) before checking.
MemoryParts sessionMemory(const CommonOptions& options, uint64_t sceneTriangles);
MemoryParts sessionMemory(const SceneSession& session);

// Frames to render: --frames if given, else `defaultFrames` of the path ("all" = every frame, "all:N" = every
// N-th frame, "spread:N" = N frames evenly spread over the path). Frames past the path's end are an InputError.
std::vector<int> selectFrames(const CommonOptions& options, const CameraPath& path, const std::string& defaultFrames);
// Refuses (InputError) output files that could not be written, before any work: empty names are skipped.
void checkOutputFiles(const std::vector<std::string>& files);

struct GpuSession {
    std::unique_ptr<GlContext> context;
    std::unique_ptr<Renderer> renderer;
    double setupSeconds = 0; // context + upload + shader compilation
};
// Creates the context (--gl, --gl-device; warns on a software renderer), sets the preferred shader stage
// (--shader-stage) and makes the renderer.
GpuSession openGpuSession(const CommonOptions& options, const SceneSession& session, const RenderSettings& settings);
// The warning line on stderr when the current context renders in software (llvmpipe): its timings are not GPU
// timings; with --gl-device auto it also says that no hardware EGL device made a context. Nothing otherwise.
void warnIfSoftwareRenderer(const CommonOptions& options, const GlContext& context);

} // namespace chcrt::app
