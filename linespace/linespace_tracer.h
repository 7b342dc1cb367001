#pragma once
// Line Space tracing methods (`bvh+ls-exact`, `bvh+ls`): the pure BVH tracer's fragment pass
// (shaders/render/trace_bvh.frag.glsl) compiled with Line Space defines per ray type, see
// shaders/linespace/linespace_traverse.glsl. Which ray type uses which mode is a parameter (LineSpaceModes).
#include "linespace/linespace_gpu.h"
#include "renderer/render/tracer.h"

#include <map>
#include <memory>
#include <string>

namespace chcrt::ls {

// Mode per ray type. Defaults = `bvh+ls`, Line Spaces only where they paid on llvmpipe (docs/benchmarks.md):
// shadow and bounce shadow rays terminate at occupied shafts (SS §4.1; 0.84-1.22x), diffuse rays use
// candidates (RC §3.2; 0.95-1.73x). Primary rays (exact skipping: 0.63-1.03x) and AO rays (candidates with the
// start node exact: 0.41-0.91x, short rays mostly inside their start node) trace the pure BVH; --ls-modes
// primary=exact,ao=candidate-exact-start brings them back.
struct LineSpaceModes {
    LineSpaceMode primary = LineSpaceMode::Off;
    LineSpaceMode shadow = LineSpaceMode::Shadow;
    LineSpaceMode ao = LineSpaceMode::Off;
    LineSpaceMode diffuse = LineSpaceMode::Candidate;
    LineSpaceMode bounceShadow = LineSpaceMode::Shadow;
    // Candidate planes met from behind are no hit in the node the ray starts in (`faces=front-start`, default),
    // in every node (`faces=front`), or never (`faces=both`, the paper). Measured (docs/benchmarks.md): the
    // start-node rule removes the self-occlusion of candidates (dragon AO 29 -> 38 dB) without losing hits on
    // the back of open geometry elsewhere (interior, castle).
    CandidateFaces candidateFaces = CandidateFaces::FrontInStartNode;
    static LineSpaceModes allExact();
    // "primary=exact,shadow=shadow,ao=candidate,diffuse=candidate,bounce=shadow,faces=front-start" (any subset,
    // applied on top of *this); throws InputError for unknown names or modes that do not fit the ray type (shadow mode on
    // closest-hit rays, candidates on primary rays are allowed but approximate).
    void parse(const std::string& text);
    LineSpaceMode forRequest(const TraceRequest& request) const;
    bool approximate() const;
    std::string toString() const;
};

class LineSpaceTracer final : public Tracer {
public:
    // Requires a current GL context.
    LineSpaceTracer(std::string name, std::shared_ptr<const LineSpaceGpu> gpu, LineSpaceModes modes,
                    float maxNormalAngleDegrees, unsigned iterationCap = 0);
    std::string name() const override { return name_; }
    void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width, int height,
               TraceStats& stats) override;
    const LineSpaceModes& modes() const { return modes_; }
    const LineSpaceGpu& gpu() const { return *gpu_; }
    // Build statistics of the Line Spaces used (for reports); set by whoever built them.
    LineSpaceStats buildStats;
    std::string cacheOutcome;
    std::string paramsText; // LineSpaceParams::toString()
    // Candidate passes compile the leaf test out when no Line Space node is a BVH leaf (no ray can reach one; same
    // hits, CHCRT_LS_CANDIDATE_NO_LEAVES). Tests set this before the first trace to keep it and compare.
    bool keepUnreachableLeafTest = false;

private:
    const ShaderProgram& program(LineSpaceMode mode, bool anyHit);
    std::string name_;
    std::shared_ptr<const LineSpaceGpu> gpu_;
    LineSpaceModes modes_;
    float maxAngle_;
    unsigned iterationCap_;
    std::map<std::pair<int, bool>, std::unique_ptr<ShaderProgram>> programs_;
};

} // namespace chcrt::ls
