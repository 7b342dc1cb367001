#pragma once
// The tracing methods, registered once (methodRegistry(), app/methods.cpp): name, exact or approximate, what each
// needs, which parameter areas it reads (app/parameters.h), its own defaults and the factory of its tracer. The
// CLI's --method help and checks, bench, verify, render, the viewer's method list and panel sections and
// `chcrt methods` (docs/cli.md's table) read it.
#include "app/parameters.h"
#include "app/session.h"
#include "renderer/render/tracer.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace chcrt::app {

// The baseline every other method is measured and verified against: pure BVH traversal in GLSL (the renderer's
// own tracer).
inline constexpr const char* kPureBvhMethod = "bvh";

// The order in which `bench` traces pass `passIndex` with `methods` (GPU methods, in the order given): pure BVH first
// (the reference the others' hits are compared with), the others in the given order on even passes and reversed on
// odd ones. A method that traces the same rays right after another culling method finds the caches warm with what
// both need (the hinted leaves and their triangles, the ray and hit images): on the city's near shadow rays the method
// second of `chcrt,chcrt-noadapt` ran 4-9 % faster than it did first (docs/benchmarks.md, 2026-12-07), so a fixed
// order favoured the later method.
std::vector<std::string> benchTraceOrder(const std::vector<std::string>& methods, size_t passIndex);

// What a method needs beyond the scene's BVH on the GPU.
enum MethodNeeds : uint8_t {
    kNeedsNothing = 0,
    kNeedsLineSpaces = 1, // binary (and candidate) Line Spaces of the BVH: built or loaded from --ls-cache
    kNeedsNTree = 2,      // an N-tree with binary Line Spaces: built or loaded from --ls-cache
    kNeedsEmbree = 4,     // the scene in core for Embree (CPU)
};
std::string describeNeeds(uint8_t needs); // "Line Spaces (--ls-cache)", "-" for none

struct MethodInfo;
// Makes a method's tracer from its resolved options (resolveMethodOptions); requires the session's GL context to
// be current. `alwaysCull`: CHC+RT without the adaptive fallback to a pure pass, bvh+ls-exact without its
// fallback to pure BVH traversal (verify checks the culling / the Line Space path itself).
using TracerFactory = std::unique_ptr<Tracer> (*)(const MethodInfo& method, const SceneSession& session,
                                                  const CommonOptions& resolved, bool alwaysCull);
// The CPU part of a method's set-up that may run on another thread (methodCacheBuild).
using CacheBuildFactory = std::function<void(Progress&)> (*)(const MethodInfo& method, const SceneSession& session,
                                                            const CommonOptions& resolved);

struct MethodInfo {
    std::string name;
    bool exact = true;        // must produce exactly the hits of pure BVH tracing (verify checks it)
    std::string description;
    bool gpu = true;          // traces the renderer's ray textures; false: embree, the CPU reference on read-back rays
    std::vector<ParameterArea> areas; // the parameter areas it reads
    uint8_t needs = kNeedsNothing;    // MethodNeeds
    bool outOfCoreForm = false;       // traces a prepared scene out of core (--out-of-core)
    bool chcrtDebugImages = false;    // CHC+RT debug images (--debug-image, the viewer's debug views)
    // Starts from recommendedChcrtOptions() in core: its tracer takes the renderer's list decisions
    // (recommendedChcrtOptions(traits), app/method_tracers.cpp) unless --chcrt-queries is given.
    bool recommendedChcrt = false;
    // Its own defaults, written into `defaults` (whose method parameters start from their structs' defaults);
    // `user` holds the user's values, for defaults derived from them (ntree+ls: the shadow level d - 1).
    void (*setDefaults)(CommonOptions& defaults, const CommonOptions& user, uint64_t sceneTriangles) = nullptr;
    TracerFactory makeTracer = nullptr;    // nullptr: the renderer's pure BVH tracer (bvh), or not a GPU method
    CacheBuildFactory cacheBuild = nullptr; // nullptr: nothing to build ahead
    bool reads(ParameterArea area) const;
};

// Every method, embree (the CPU reference) last.
const std::vector<MethodInfo>& methodRegistry();
// The GPU methods (all but embree).
std::vector<const MethodInfo*> gpuMethods();
// Throw InputError listing the available methods for unknown names; findGpuMethod also for embree.
const MethodInfo& findMethod(const std::string& name);
const MethodInfo& findGpuMethod(const std::string& name);
// "bvh, chcrt, ..., embree" (with embree, the CPU reference) or the GPU methods only, for --help and errors.
std::string methodNames(bool withReference = true);
// The methods as a table: name, description, exact / approximate, needs, out of core (`chcrt methods`).
struct Table;
Table methodTable();

// The method's parameters: its defaults for a scene of `sceneTriangles` triangles, then the flags given in `user`
// (all of them: the factories refuse those that contradict the method).
CommonOptions resolveMethodOptions(const MethodInfo& method, const CommonOptions& user, uint64_t sceneTriangles);
// The method's defaults alone (what --help and the viewer's panel show for parameters not given).
CommonOptions methodDefaults(const MethodInfo& method, const CommonOptions& user, uint64_t sceneTriangles);
// Triangles of the session's scene (of the file, for a prepared scene not in core).
uint64_t sceneTriangles(const SceneSession& session);

// Creates the tracer of a GPU method for a session (requires the session's GL context to be current).
// Returns nullptr for "bvh": the renderer's own pure BVH tracer.
std::unique_ptr<Tracer> makeTracer(const std::string& name, const SceneSession& session, bool alwaysCull = false);

// The CPU part of a method's set-up that can run on another thread: building its Line Spaces / N-tree into the
// --ls-cache directory (nothing when the cache file exists), so that makeTracer afterwards only loads them (the
// viewer runs it on a worker and keeps its window responding, issue #6). Empty when there is nothing to build
// ahead: methods without Line Spaces, an empty --ls-cache (the build then happens inside makeTracer), out of core.
// The job reads `session.bvh`, which must outlive it; it throws what the builders throw (InputError for an
// unwritable cache directory).
std::function<void(Progress&)> methodCacheBuild(const std::string& name, const SceneSession& session);

} // namespace chcrt::app
