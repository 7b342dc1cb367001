#pragma once
// The tracer factories and cache builds of the registered methods (app/methods.cpp registers them). Each reads
// its parameters from options resolved for the method (resolveMethodOptions): the method's defaults with the
// user's flags on top.
#include "app/methods.h"

namespace chcrt::app {

// CHC+RT (culling/README.md) with ChcrtOptions from the --chcrt-* flags; in core or out of core (--out-of-core),
// with Line Spaces in its subtrees for methods that read the LineSpace area (chcrt+ls*).
std::unique_ptr<Tracer> makeChcrtTracer(const MethodInfo& method, const SceneSession& session,
                                        const CommonOptions& resolved, bool alwaysCull);
// bvh+ls-exact, bvh+ls: Line Spaces from the cache (or built), uploaded, and a tracer with the method's modes.
std::unique_ptr<Tracer> makeLineSpaceTracer(const MethodInfo& method, const SceneSession& session,
                                            const CommonOptions& resolved, bool alwaysCull);
// ntree+ls: the N-tree with binary Line Spaces (soft-shadow paper), loaded or built, uploaded, and its tracer.
std::unique_ptr<Tracer> makeNTreeTracer(const MethodInfo& method, const SceneSession& session,
                                        const CommonOptions& resolved, bool alwaysCull);

// Builds into the --ls-cache directory what the tracer factories above would load.
std::function<void(Progress&)> lineSpaceCacheBuild(const MethodInfo& method, const SceneSession& session,
                                                   const CommonOptions& resolved);
std::function<void(Progress&)> nTreeCacheBuild(const MethodInfo& method, const SceneSession& session,
                                               const CommonOptions& resolved);

// The Line Space build parameters of resolved options: candidate Line Spaces only for methods with modes
// (bvh+ls*) when a mode uses them; chcrt+ls* read binary Line Spaces only.
ls::LineSpaceParams lineSpaceBuildParams(const MethodInfo& method, const CommonOptions& resolved);
// The Line Space modes of resolved options: the method's base modes with --ls-modes on top.
ls::LineSpaceModes lineSpaceModes(const CommonOptions& resolved);

} // namespace chcrt::app
