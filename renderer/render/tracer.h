#pragma once
// What a tracing method does, whatever it is: trace the rays of a ray texture set into a hit target set
// (hit buffer layout in shaders/shared/render_layout.h). Pure BVH tracing implements it here; CHC+RT and the
// Line Space variants implement it in culling/ and linespace/ and plug into the same Renderer.
#include "renderer/render/camera_math.h"
#include "renderer/render/frame_targets.h"
#include "renderer/render/render_settings.h"
#include "renderer/scene/scene.h"

#include <cstdint>
#include <optional>
#include <string>

namespace chcrt {

// What is being traced: methods that keep per-ray-set state (CHC+RT visibility fronts, §5.3) key it on this.
struct TraceRequest {
    RayType rayType = RayType::Primary;
    bool anyHit = false;
    bool bounceShadow = false; // shadow rays from diffuse hits (a ray set of its own)
    int sampleIndex = 0;       // pass index within the frame
    Camera camera;             // the frame's camera (methods may order work front to back)
    // Set by the renderer when the ray set holds exactly the primary rays this basis generates (no other ray set):
    // a tracer may bound them from it instead of reading them.
    std::optional<PrimaryRayBasis> cameraRays;
    // Set by the renderer for shadow rays from its G-buffer to its area light. Every such ray set with the same
    // `generation` starts at the same surface points — an inactive ray keeps its origin, with an all-zero direction
    // texel (shared/render_layout.h) — and ends inside the light's box, whatever its sample: a tracer may bound all
    // of them at once (CHC+RT shares one ray bounds grid and one set of cell lists among them).
    struct LightSweep {
        uint64_t generation = 0; // changes whenever the surface points may have changed
        glm::vec3 lightMin{0.0f}, lightMax{0.0f};
    };
    std::optional<LightSweep> lightSweep;
    // Set by the renderer for AO rays from its G-buffer. Every such ray set with the same `generation` starts at the
    // same surface points (an inactive ray keeps its origin, as above), and a set's active ray from a pixel runs
    // from t = 0 to `length` along normalize(l.x T + l.y B + l.z n): n the shading normal in `shadingNormals` (the
    // G-buffer's normal texture, xyz), T and B its tangent frame (buildTangentFrame, shaders/render/sampling.glsl),
    // l = cosineHemisphere(sample, rotation) with the pixel's rotation in [0, maxRotation]. A tracer may bound every
    // set from the surface points, the normals and these values (CHC+RT: one reduction per G-buffer).
    struct HemisphereRays {
        uint64_t generation = 0;
        unsigned shadingNormals = 0; // GL texture name
        glm::vec2 sample{0.0f};
        float maxRotation = 0.0f; // radians
        float length = 0.0f;
    };
    std::optional<HemisphereRays> hemisphereRays;
};

struct TraceStats {
    uint64_t passes = 0;      // tracing passes (full-screen or per batch)
    double milliseconds = 0;  // wall time of tracing, measured with glFinish before and after
};

class Tracer {
public:
    virtual ~Tracer() = default;
    virtual std::string name() const = 0;
    // Traces rays into hits (both sized like the frame). The scene's tracing buffers are bound by the caller.
    virtual void trace(const TraceRequest& request, const RayTextures& rays, HitTargets& hits, int width,
                       int height, TraceStats& stats) = 0;
};

} // namespace chcrt
