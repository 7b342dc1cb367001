#pragma once
// Pure BVH tracing as the oracle of the tracers that must find its hits (conservative CHC+RT, exact Line Space
// skipping, out of core): one generated ray pass traced by both, the hits compared pixel by pixel.
#include "renderer/render/renderer.h"

#include <algorithm>
#include <cstring>
#include <vector>

namespace chcrt::test {

// The frame of the tracing tests: several 16-pixel cells and tiles across, small enough for llvmpipe.
inline RenderSettings smallTraceSettings() {
    RenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    return settings;
}

// The same answer: the bits of t and the triangle for closest-hit rays, hit or miss for any-hit rays.
inline bool sameHit(const Hit& a, const Hit& b, bool anyHit) {
    const bool hitA = a.triangleId != CHCRT_NO_HIT_ID, hitB = b.triangleId != CHCRT_NO_HIT_ID;
    if (anyHit) return hitA == hitB;
    return a.triangleId == b.triangleId && std::memcmp(&a.t, &b.t, sizeof(float)) == 0;
}

// Pixels whose hits differ between two traces of one ray pass (sameHit); traces of different sizes all differ.
inline size_t countDifferingHits(const std::vector<Hit>& reference, const std::vector<Hit>& traced, bool anyHit) {
    if (reference.size() != traced.size()) return std::max(reference.size(), traced.size());
    size_t differing = 0;
    for (size_t i = 0; i < reference.size(); ++i) differing += !sameHit(reference[i], traced[i], anyHit);
    return differing;
}

struct OracleComparison {
    std::vector<Hit> reference; // pure BVH's hits
    std::vector<Hit> traced;    // the tracer's
    size_t differing = 0;
};

// Traces the generated ray pass (type, sampleIndex) with pure BVH, then with `tracer`, which stays in use.
inline OracleComparison traceAgainstPureBvh(Renderer& renderer, Tracer& tracer, const Camera& camera, RayType type,
                                            int sampleIndex, FrameStats& stats) {
    OracleComparison result;
    renderer.useTracer(nullptr);
    renderer.traceRayPass(camera, type, sampleIndex, stats);
    result.reference = renderer.readHits(0);
    renderer.useTracer(&tracer);
    renderer.traceRayPass(camera, type, sampleIndex, stats);
    result.traced = renderer.readHits(0);
    result.differing = countDifferingHits(result.reference, result.traced, isAnyHit(type));
    return result;
}

} // namespace chcrt::test
