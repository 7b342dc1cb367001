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
    // Builds an Embree scene (high quality build, robust/watertight triangle tests) over the scene's positions
    // and triangles (other Scene fields are not read). Throws InputError for a vertex index out of range and
    // std::runtime_error (not GlError) with Embree's message on Embree device errors.
    explicit EmbreeTracer(const Scene& scene);
    ~EmbreeTracer();
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    // Closest hits (t, triangleId, u, v) or any hits for all rays, accepting hits with tmin <= t <= tmax like the
    // other tracers. Any-hit results only say hit or miss: an occluded ray reports triangleId = 0 and t = 0
    // (Embree's rtcOccluded does not say which triangle or where), a miss CHCRT_NO_HIT_ID. Ties between
    // triangles at the same t are Embree's choice, not the lower id. Inactive rays (tmax <= tmin) report a
    // miss; a negative tmin counts as 0. Runs on all cores (dynamic chunks of rays, one thread per core).
    // Throws std::invalid_argument if the spans differ in size, std::runtime_error on Embree errors.
    void trace(std::span<const Ray> rays, std::span<Hit> hits, bool anyHit) const;

    double buildSeconds() const { return buildSeconds_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    double buildSeconds_ = 0.0;
};

} // namespace chcrt
