#pragma once
// Method `ntree+ls` (soft-shadow paper, "SS"): shadow and bounce-shadow rays traverse the N-tree with binary
// Line Spaces (shaders/linespace/ntree_traverse.glsl as the traversal of the full-screen tracer, SS Algorithm 1), every other ray type the pure BVH
// (the paper uses the N-tree for shadows only; primary visibility is rasterized there).
#include "linespace/ntree_gpu.h"
#include "renderer/render/bvh_tracer.h"
#include "renderer/render/tracer.h"

#include <memory>
#include <string>

namespace chcrt::ls {

class NTreeTracer final : public Tracer {
public:
    // Requires a current GL context. Throws InputError for a tree deeper than CHCRT_NT_MAX_DEPTH.
    NTreeTracer(std::string name, std::shared_ptr<const NTreeGpu> gpu, NTreeShadowOptions options,
                unsigned iterationCap = 0);
    std::string name() const override { return name_; }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override;
    const NTreeShadowOptions& options() const { return options_; }
    uint64_t gpuBytes() const { return gpu_->gpuBytes(); }
    // Build statistics of the tree (for reports); set by whoever built it.
    NTreeStats buildStats;
    std::string cacheOutcome; // toString(CacheOutcome): built, loaded from cache, rebuilt
    std::string paramsText;

private:
    std::string name_;
    std::shared_ptr<const NTreeGpu> gpu_;
    NTreeShadowOptions options_;
    ShaderProgram shadowProgram_;
    BvhTracer bvh_;
};

// "N:d" -> NTreeParams (threads left at 0); InputError for anything else or N, d out of range.
NTreeParams parseNTreeParams(const std::string& text);

} // namespace chcrt::ls
