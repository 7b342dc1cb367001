#pragma once
// Reference tracer on the CPU with Embree 3 over exactly the scene's triangles (original ids = Embree primIDs).
// It is the oracle for the GLSL tracer (tests, `chcrt verify`) and a speed reference in `chcrt bench`.
#include "renderer/bvh/cpu_tracer.h"
#include "renderer/scene/scene.h"

#include <memory>
#include <span>

namespace chcrt {

class EmbreeTracer {
public:
    // Builds an Embree scene (high quality build) over the scene's triangles. Throws GlError-free
    // std::runtime_error on Embree device errors.
    explicit EmbreeTracer(const Scene& scene);
    ~EmbreeTracer();
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    // Closest hits (t, triangleId, u, v) or any hits (occlusion: triangleId = 0 for "occluded", t = tmax ...
    // see implementation) for all rays, on all cores (rtcIntersect16/rtcOccluded16 over packets or
    // rtcIntersect1 in parallel). Inactive rays (tmax <= tmin) report a miss.
    void trace(std::span<const Ray> rays, std::span<Hit> hits, bool anyHit) const;

    double buildSeconds() const { return buildSeconds_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    double buildSeconds_ = 0.0;
};

} // namespace chcrt
