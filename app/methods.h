#pragma once
// Tracing methods by name, for bench, verify and render: "bvh" (pure BVH GLSL tracing, the baseline) and the
// methods later issues add (CHC+RT, Line Space variants). "embree" is the CPU reference and is handled by the
// commands themselves (it traces read-back rays, not ray textures).
#include "app/session.h"
#include "renderer/render/tracer.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace chcrt::app {

struct MethodInfo {
    std::string name;
    bool exact = true; // must produce exactly the hits of pure BVH tracing
    std::string description;
};
const std::vector<MethodInfo>& gpuMethods();
const MethodInfo& findGpuMethod(const std::string& name); // throws InputError listing the available ones

// Creates the tracer of a GPU method for a session (requires the session's GL context to be current).
// Returns nullptr for "bvh": the renderer's own pure BVH tracer.
std::unique_ptr<Tracer> makeTracer(const std::string& name, const SceneSession& session, const GpuSession& gpu);
// `alwaysCull`: CHC+RT methods without the adaptive fallback to a pure pass, bvh+ls-exact without its fallback
// to pure BVH traversal (verify checks the culling / the Line Space path itself).
std::unique_ptr<Tracer> makeTracer(const std::string& name, const SceneSession& session, const GpuSession& gpu,
                                   bool alwaysCull);

// Whether a GPU method can trace a prepared scene out of core (--out-of-core): the CHC+RT methods without Line
// Spaces (pure BVH and Line Space tracing need the whole scene on the GPU).
bool hasOutOfCoreForm(const std::string& name);

// The CPU part of a method's set-up that can run on another thread: building its Line Spaces / N-tree into the
// --ls-cache directory (nothing when the cache file exists), so that makeTracer afterwards only loads them (the
// viewer runs it on a worker and keeps its window responding, issue #6). Empty when there is nothing to build
// ahead: methods without Line Spaces, an empty --ls-cache (the build then happens inside makeTracer), out of core.
// The job reads `session.bvh`, which must outlive it; it throws what the builders throw (InputError for an
// unwritable cache directory).
std::function<void(Progress&)> methodCacheBuild(const std::string& name, const SceneSession& session);

} // namespace chcrt::app
