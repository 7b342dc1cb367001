#pragma once
// The options shared by the subcommands (pbrt/Blender style). Each area's parameters live in that area's own
// typed struct (RenderSettings, BvhBuildOptions, ChcrtOptions, ls::LineSpaceParams, ...), held here; every flag
// that sets one of their fields is described once in app/parameters.cpp, which registers the flags, validates
// them and tells the viewer and the methods about them. `given` says which flags the user set: a tracing
// method's own defaults (app/methods.h) apply to the others.
#include "culling/chcrt_tracer.h"
#include "linespace/linespace_build.h"
#include "linespace/linespace_tracer.h"
#include "linespace/ntree.h"
#include "linespace/ntree_gpu.h"
#include "linespace/ntree_tracer.h"
#include "renderer/bvh/bvh.h"
#include "renderer/gl/context.h"
#include "culling/outofcore/out_of_core_tracer.h"
#include "renderer/render/render_settings.h"
#include "renderer/render/trace_stage.h"


#include <set>
#include <string>

// CLI11 is header-only and costs seconds per translation unit: only the files that declare flags include it.
namespace CLI {
class App;
}

namespace chcrt::app {

// Line Space tracing settings that have no field in linespace/'s structs.
struct LineSpaceTracing {
    float candidateAngleDegrees = 30.0f; // --ls-angle: LineSpaceTracer's normal-angle threshold of candidates
    // The method's own modes per ray type (set by its defaults, app/methods.cpp); --ls-modes applies on top.
    ls::LineSpaceModes baseModes;
    std::string modes;                   // --ls-modes text, "" = the method's modes as they are
    std::string cacheDirectory = "out/cache/linespace"; // --ls-cache: "" disables caching
};

// --load-in-core: whether an --out-of-core prepared scene is also loaded in core (references, id-indexed shading).
enum class LoadInCore : uint8_t { Auto, On, Off };

// Out-of-core settings of the session (the tracer's budgets are outofcore::OutOfCoreOptions).
struct OutOfCoreScene {
    bool enabled = false;                   // --out-of-core: chcrt methods trace through the GPU subtree cache
    LoadInCore loadInCore = LoadInCore::Auto;
};

struct CommonOptions {
    // The session: what to render and from where (no typed home outside app/).
    std::string scene = "city";     // procedural spec or file; default: the embedded city
    std::string cameraPath;         // JSON file, or "near" / "far" for generated scenes; default near / default camera
    std::string camera;             // "gltf:<index or name>" selects a camera stored in a glTF file
    std::string eye, target;        // "x,y,z": an explicit single camera (overrides paths)
    float fovY = 60.0f;
    std::string frames;             // --frames; default depends on the command
    GlBackend gl = GlBackend::Egl;
    int glDevice = kAutoGlDevice;   // --gl-device: EGL device index, or auto (kAutoGlDevice): hardware first
    TraceStage shaderStage = TraceStage::Auto; // --shader-stage of the pure BVH tracer's passes
    bool glDebug = false;
    bool strict = false;            // --strict: a scene's load warnings (Scene::warnings) are errors
    std::string statsJson;
    bool quiet = false;
    uint64_t maxMemoryBytes = 0;    // --max-memory-mb; 0: defaultMemoryBudgetBytes() (renderer/core/memory_budget.h)

    // Each area's typed home (app/parameters.cpp: the flags that set their fields).
    RenderSettings render;          // samplesPerPixel: the command's default unless --spp is given
    BvhBuildOptions bvh;
    ChcrtOptions chcrt;             // the chcrt* methods (culling/README.md)
    ls::LineSpaceParams lineSpace;  // Line Space methods (linespace/README.md)
    LineSpaceTracing lineSpaceTracing;
    ls::NTreeParams ntree;          // ntree+ls
    ls::NTreeShadowOptions ntreeShadow; // shadowLevel: d - 1 unless --ls-ntree-level is given
    // --out-of-core budgets; maxUploadsPerTrace: the command's default unless --uploads-per-trace is given (0 = no
    // limit: complete, exact traces; the interactive viewer 16: it streams a cold cache).
    outofcore::OutOfCoreOptions outOfCore;
    OutOfCoreScene outOfCoreScene;

    // Flags the user set (the table's `flag` names): on the command line, or in the viewer's panel and scripts.
    std::set<std::string> given;
    bool isGiven(const std::string& flag) const { return given.count(flag) != 0; }
};

// Commands whose flags a parameter belongs to (Parameter::commands).
enum CommandSet : uint8_t {
    kEveryCommand = 0,
    kShadedCommands = 1, // commands that render shaded images (--effects, --exposure): demo, render, bench, view
    kHeadlessCommands = 2, // commands with a headless GL context (--gl): not view
};

// Adds every described parameter of the commands in `commands` to a subcommand, in CLI11 option groups per
// area; values are validated as they are parsed (InputError naming the flag).
void addCommonOptions(CLI::App& command, CommonOptions& options, uint8_t commands);

// The renderer's settings: `options.render` with --spp or the command's default.
RenderSettings toRenderSettings(const CommonOptions& options, int defaultSpp);

// "x,y,z" → vector; throws InputError naming the flag.
glm::vec3 parseVec3(const std::string& text, const char* flag);

} // namespace chcrt::app
