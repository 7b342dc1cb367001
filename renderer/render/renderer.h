#pragma once
// The hybrid frame: make the G-buffer (primary visibility: rasterised, or traced with the current Tracer and
// resolved from the hit buffer, RenderSettings::primaryVisibility), then for each enabled effect and each of the
// N samples per pixel generate one ray per pixel into the ray textures, trace them with the current Tracer
// (pure BVH by default; CHC+RT and Line Space plug in through the same interface) and accumulate; finally
// compose and tone-map. The same object serves `chcrt render`, `bench`, `verify` and the viewer.
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/cpu_tracer.h"
#include "renderer/core/image_io.h"
#include "renderer/gl/shader.h"
#include "renderer/render/frame_targets.h"
#include "renderer/render/render_settings.h"
#include "renderer/render/scene_gpu.h"
#include "renderer/render/trace_stage.h"
#include "renderer/render/tracer.h"

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

namespace chcrt {

struct FrameStats {
    double gbufferMs = 0;
    double raygenMs = 0;
    double shadeMs = 0; // accumulation + compose
    double totalMs = 0;
    // Tracing time and passes per ray type (bounce shadow rays of the diffuse effect count as diffuse).
    std::array<TraceStats, 4> trace{};
    uint64_t raysGenerated = 0; // pixels × passes (inactive rays included)
    uint64_t cappedRays = 0;    // rays that hit the loop cap (must be 0; see render_layout.h)
    uint64_t gbufferTriangles = 0; // triangles submitted to the G-buffer pass after frustum culling
    double traceMs() const;
};

class Renderer {
public:
    // Requires a current GL context. Keeps references to nothing: scene data is uploaded, or taken from `uploaded`
    // when given (the same scene and BVH already on the GPU, e.g. uploaded by a worker thread on a shared context).
    Renderer(const Scene& scene, const Bvh& bvh, const AreaLight& light, const RenderSettings& settings,
             std::unique_ptr<SceneGpu> uploaded = nullptr);
    ~Renderer();

    // Changes settings; recreates targets when the size changes. Throws InputError for invalid settings.
    void setSettings(const RenderSettings& settings);
    const RenderSettings& settings() const { return settings_; }
    // The tracing method used from now on (not owned; must outlive its use); nullptr = pure BVH tracing.
    void useTracer(Tracer* tracer) { activeTracer_ = tracer ? tracer : bvhTracer_.get(); }
    Tracer& tracer() { return *activeTracer_; }
    // The shader stage of the renderer's own pure BVH tracer (preferredTraceStage() resolved at construction).
    TraceStage pureTracerStage() const;
    // Scene data on the GPU, for tracers that bind more than the BVH (CHC+RT subtrees, Line Space).
    const SceneGpu& sceneGpu() const { return *sceneGpu_; }

    // The whole frame: G-buffer, effects, composition.
    FrameStats renderFrame(const Camera& camera);
    // Passes of renderFrame with the current settings (G-buffer + one per traced ray set + composition); each
    // completed pass calls the pass callback (progress bars).
    int passesPerFrame() const;
    void setPassCallback(std::function<void()> callback) { passCallback_ = std::move(callback); }
    // Compiles every shader variant the frame uses by rendering one pixel of a frame (llvmpipe compiles shaders
    // at their first draw, 90-280 ms each: keep that out of timings).
    void warmUp(const Camera& camera);

    // Building blocks for bench/verify and the viewer.
    // The G-buffer by settings().primaryVisibility: rasterised (timed into gbufferMs), or traced: primary rays
    // (raygenMs) traced with the current tracer into hit set 0 (trace[Primary]) and resolved (gbufferMs).
    void renderGBuffer(const Camera& camera, FrameStats& stats);
    // Generates the rays of one pass (for `type` and sample `sampleIndex`) into ray set 0. Secondary rays need
    // the G-buffer of the same camera.
    void generateRayPass(const Camera& camera, RayType type, int sampleIndex, FrameStats& stats);
    // Traces ray set 0 into hit set 0 with the current tracer (timed into stats.trace[type]); counts capped rays.
    // Does not accumulate.
    void traceRayPass(const Camera& camera, RayType type, int sampleIndex, FrameStats& stats);

    // Read-backs (blocking) for checks and image output.
    ImageRgba32f readDisplayImage() const;
    ImageRgba32f readHdrImage() const;
    // The one-bounce diffuse contribution alone (albedo × mean incoming radiance, linear HDR, background 0) of
    // the last frame, for error metrics of approximate indirect tracing (Line Space). Re-runs composition in its
    // indirect-only mode and restores the composed frame; all zero when the diffuse effect is off.
    ImageRgba32f readIndirectImage();
    std::vector<Ray> readRays(int set) const;
    std::vector<Hit> readHits(int set) const;
    // BVH traversal steps per pixel of the last full-screen trace into hit set `set` (inner nodes + leaves +
    // triangles of its cost target), bit 31 set where the ray reached the loop cap: the encoding of CHC+RT's
    // cost debug image (culling/chcrt_tracer.h), so that `chcrt bench --steps` compares the two per ray.
    std::vector<uint32_t> readTraceSteps(int set) const;
    const FrameTargets& targets() const { return *targets_; }
    // Frustum culling of BVH clusters in the G-buffer pass (on by default; off only for tests and comparisons).
    void setFrustumCulling(bool enabled) { frustumCulling_ = enabled; }

    float sceneDiagonal() const { return sceneDiagonal_; }

    // Out of core (culling/outofcore/primary_resolve.h): with traced primary visibility, `resolve` writes the
    // G-buffer from the primary hits (ray set 0, hit set 0) and returns a texture (RGBA32F, frame size) of the
    // pixels' geometric normals, which secondary ray generation then reads instead of the per-triangle buffers
    // indexed by original id (those cannot hold a scene that is not in core). An empty function restores the
    // in-core passes. The diffuse effect still shades bounce hits by id: not for scenes that are not in core.
    using OutOfCorePrimaryResolve = std::function<GLuint(const Camera&, const FrameTargets&, float nearPlane)>;
    void setOutOfCorePrimary(OutOfCorePrimaryResolve resolve);

private:
    void rasterizeGBuffer(const Camera& camera, FrameStats& stats);
    void traceGBuffer(const Camera& camera, FrameStats& stats);
    void compose(FrameStats& stats, int outputMode);
    void generateRays(const Camera& camera, int rayProgram, int sampleIndex, int raySet, FrameStats& stats);
    void trace(const Camera& camera, RayType type, bool bounceShadow, int sampleIndex, int raySet, int hitSet,
               FrameStats& stats);
    void accumulate(RayType type, int sampleIndex, FrameStats& stats);
    void compose(FrameStats& stats);
    uint64_t readAndResetCappedRays();

    RenderSettings settings_;
    AreaLight light_;
    Aabb sceneBounds_;
    float sceneDiagonal_ = 1.0f;
    std::unique_ptr<SceneGpu> sceneGpu_;
    std::unique_ptr<FrameTargets> targets_;
    std::unique_ptr<Tracer> bvhTracer_;
    Tracer* activeTracer_ = nullptr;
    ShaderProgram gbufferProgram_;
    ShaderProgram gbufferFromHitsProgram_; // traced primary visibility
    std::array<ShaderProgram, 5> raygenPrograms_; // indexed by CHCRT_RAY_*
    std::array<ShaderProgram, 5> pixelNormalRaygenPrograms_; // out of core: geometric normals per pixel
    OutOfCorePrimaryResolve outOfCorePrimary_;
    GLuint pixelGeometricNormals_ = 0; // from the last out-of-core resolve
    // Per ray set: the basis of the primary rays it holds (generateRays), for TraceRequest::cameraRays.
    std::array<std::optional<PrimaryRayBasis>, std::extent_v<decltype(FrameTargets::rays)>> cameraRays_;
    // Per ray set: the light sweep of the shadow rays it holds (generateRays), for TraceRequest::lightSweep; and the
    // generation of the surface points they start from, advanced by every G-buffer, settings change and camera move.
    std::array<std::optional<TraceRequest::LightSweep>, std::extent_v<decltype(FrameTargets::rays)>> lightSweeps_;
    // Per ray set: what bounds the AO rays it holds (generateRays), for TraceRequest::hemisphereRays.
    std::array<std::optional<TraceRequest::HemisphereRays>, std::extent_v<decltype(FrameTargets::rays)>>
        hemisphereRays_;
    uint64_t originGeneration_ = 0;
    glm::vec3 originEye_{0.0f}; // the eye the ray generator offset the points for last
    ShaderProgram accumulateShadow_, accumulateAo_, accumulateDiffuse_;
    ShaderProgram composeProgram_;
    GlBuffer cappedRayCounter_;
    std::function<void()> passCallback_;
    bool frustumCulling_ = true;
};

} // namespace chcrt
