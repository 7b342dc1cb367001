#include "renderer/render/renderer.h"

#include "renderer/core/timing.h"
#include "renderer/render/bvh_tracer.h"
#include "renderer/render/camera_math.h"
#include "renderer/render/halton.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <chrono>
#include <cstring>

namespace chcrt {
namespace {

using Clock = std::chrono::steady_clock;

ShaderProgram makeFullscreenProgram(const char* fragment, std::vector<ShaderDefine> defines = {}) {
    return ShaderProgram({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"}, {GL_FRAGMENT_SHADER, fragment}},
                         defines);
}

void setLightUniforms(const ShaderProgram& program, const AreaLight& light) {
    program.set("lightCorner", light.corner);
    program.set("lightEdgeU", light.edgeU);
    program.set("lightEdgeV", light.edgeV);
    program.set("lightRadiance", light.radiance);
}

int rayProgramIndex(RayType type) {
    switch (type) {
    case RayType::Primary: return CHCRT_RAY_PRIMARY;
    case RayType::Shadow: return CHCRT_RAY_SHADOW;
    case RayType::Ao: return CHCRT_RAY_AO;
    case RayType::Diffuse: return CHCRT_RAY_DIFFUSE;
    }
    return CHCRT_RAY_PRIMARY;
}

// Reads a 4-channel texture (float or 32-bit integer) as 4 values per pixel, rows bottom to top.
template <typename T>
std::vector<T> readTexture(GLuint texture, int width, int height, GLenum format, GLenum type) {
    std::vector<T> data(size_t(width) * height * 4);
    glGetTextureImage(texture, 0, format, type, GLsizei(data.size() * sizeof(T)), data.data());
    return data;
}

// Reads a colour target as an image (rows top to bottom).
ImageRgba32f readImageTexture(GLuint texture, int width, int height) {
    ImageRgba32f image{width, height, readTexture<float>(texture, width, height, GL_RGBA, GL_FLOAT)};
    const size_t row = size_t(width) * 4;
    for (int y = 0; y < height / 2; ++y) {
        std::swap_ranges(image.pixels.begin() + y * row, image.pixels.begin() + (y + 1) * row,
                         image.pixels.end() - (y + 1) * row);
    }
    return image;
}

} // namespace

double FrameStats::traceMs() const {
    double sum = 0;
    for (const TraceStats& t : trace) sum += t.milliseconds;
    return sum;
}

Renderer::Renderer(const Scene& scene, const Bvh& bvh, const AreaLight& light, const RenderSettings& settings,
                   std::unique_ptr<SceneGpu> uploaded)
    : light_(light), sceneBounds_(scene.bounds()) {
    sceneDiagonal_ = std::max(sceneBounds_.diagonal(), 1e-6f);
    sceneGpu_ = uploaded ? std::move(uploaded) : std::make_unique<SceneGpu>(scene, bvh);
    bvhTracer_ = std::make_unique<BvhTracer>();
    activeTracer_ = bvhTracer_.get();
    gbufferProgram_ = ShaderProgram(
        {{GL_VERTEX_SHADER, "render/gbuffer.vert.glsl"}, {GL_FRAGMENT_SHADER, "render/gbuffer.frag.glsl"}});
    gbufferFromHitsProgram_ = makeFullscreenProgram("render/gbuffer_from_hits.frag.glsl");
    for (int type = 0; type < int(raygenPrograms_.size()); ++type) {
        raygenPrograms_[type] = makeFullscreenProgram("render/raygen.frag.glsl", {{"RAY_TYPE", std::to_string(type)}});
    }
    accumulateShadow_ = makeFullscreenProgram("render/accumulate.frag.glsl", {{"ACCUMULATE", "CHCRT_RAY_SHADOW"}});
    accumulateAo_ = makeFullscreenProgram("render/accumulate.frag.glsl", {{"ACCUMULATE", "CHCRT_RAY_AO"}});
    accumulateDiffuse_ =
        makeFullscreenProgram("render/accumulate.frag.glsl", {{"ACCUMULATE", "CHCRT_RAY_DIFFUSE"}});
    composeProgram_ = makeFullscreenProgram("render/compose.frag.glsl");
    const uint32_t zero = 0;
    cappedRayCounter_ = createBuffer(sizeof(uint32_t), &zero, GL_DYNAMIC_STORAGE_BIT);
    setSettings(settings);
}

Renderer::~Renderer() = default;

TraceStage Renderer::pureTracerStage() const { return static_cast<const BvhTracer&>(*bvhTracer_).stage(); }

void Renderer::setOutOfCorePrimary(OutOfCorePrimaryResolve resolve) {
    outOfCorePrimary_ = std::move(resolve);
    pixelGeometricNormals_ = 0;
    if (!outOfCorePrimary_ || pixelNormalRaygenPrograms_[0].id() != 0) return;
    for (int type = 0; type < int(pixelNormalRaygenPrograms_.size()); ++type) {
        pixelNormalRaygenPrograms_[type] = makeFullscreenProgram(
            "render/raygen.frag.glsl", {{"RAY_TYPE", std::to_string(type)}, {"CHCRT_PIXEL_GEOMETRIC_NORMALS", "1"}});
    }
}

void Renderer::setSettings(const RenderSettings& settings) {
    validateSettings(settings);
    if (!targets_ || settings.width != settings_.width || settings.height != settings_.height) {
        targets_ = std::make_unique<FrameTargets>(settings.width, settings.height);
        cameraRays_.fill(std::nullopt); // new ray textures hold no rays yet
        lightSweeps_.fill(std::nullopt);
        hemisphereRays_.fill(std::nullopt);
    }
    settings_ = settings;
    ++originGeneration_; // the origin offset may have changed
}

FrameStats Renderer::renderFrame(const Camera& camera) {
    const auto start = Clock::now();
    FrameStats stats;
    renderGBuffer(camera, stats);
    const float clearZero[4] = {0, 0, 0, 0};
    glClearNamedFramebufferfv(targets_->accumDirectFbo.id(), GL_COLOR, 0, clearZero);
    glClearNamedFramebufferfv(targets_->accumAoFbo.id(), GL_COLOR, 0, clearZero);
    glClearNamedFramebufferfv(targets_->accumIndirectFbo.id(), GL_COLOR, 0, clearZero);

    const EffectSet& effects = settings_.effects;
    for (int sample = 0; sample < settings_.samplesPerPixel; ++sample) {
        if (effects.shadows) {
            generateRays(camera, CHCRT_RAY_SHADOW, sample, 0, stats);
            trace(camera, RayType::Shadow, false, sample, 0, 0, stats);
            accumulate(RayType::Shadow, sample, stats);
        }
        if (effects.ao) {
            generateRays(camera, CHCRT_RAY_AO, sample, 0, stats);
            trace(camera, RayType::Ao, false, sample, 0, 0, stats);
            accumulate(RayType::Ao, sample, stats);
        }
        if (effects.diffuse) {
            // One bounce: trace the diffuse rays (set 0 → hits 0), then shadow rays from their hits to the light
            // (set 1 → hits 1), then accumulate the light reflected at the hits.
            generateRays(camera, CHCRT_RAY_DIFFUSE, sample, 0, stats);
            trace(camera, RayType::Diffuse, false, sample, 0, 0, stats);
            generateRays(camera, CHCRT_RAY_BOUNCE_SHADOW, sample, 1, stats);
            trace(camera, RayType::Diffuse, true, sample, 1, 1, stats);
            accumulate(RayType::Diffuse, sample, stats);
        }
    }
    compose(stats);
    stats.cappedRays = readAndResetCappedRays();
    stats.totalMs = millisecondsSince(start);
    return stats;
}

int Renderer::passesPerFrame() const {
    const EffectSet& e = settings_.effects;
    const int gbufferPasses = settings_.primaryVisibility == PrimaryVisibility::Traced ? 2 : 1; // trace + resolve
    return 1 + gbufferPasses + settings_.samplesPerPixel * (int(e.shadows) + int(e.ao) + 2 * int(e.diffuse));
}

void Renderer::warmUp(const Camera& camera) {
    const RenderSettings saved = settings_;
    RenderSettings onePass = settings_;
    onePass.samplesPerPixel = 1;
    onePass.effects = EffectSet{};
    settings_ = onePass;
    std::function<void()> callback = std::move(passCallback_);
    passCallback_ = nullptr;
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, 1, 1);
    renderFrame(camera);
    FrameStats scratch;
    traceRayPass(camera, RayType::Primary, 0, scratch); // the only variant a frame does not use
    glDisable(GL_SCISSOR_TEST);
    settings_ = saved;
    passCallback_ = std::move(callback);
}

void Renderer::renderGBuffer(const Camera& camera, FrameStats& stats) {
    ++originGeneration_;
    if (settings_.primaryVisibility == PrimaryVisibility::Traced) {
        traceGBuffer(camera, stats);
    } else {
        rasterizeGBuffer(camera, stats);
    }
}

void Renderer::traceGBuffer(const Camera& camera, FrameStats& stats) {
    // Primary rays into ray set 0, traced by the active tracer into hit set 0 (CHC+RT keeps its primary-ray
    // visibility front across frames like any other ray set), then resolved into the G-buffer targets.
    generateRays(camera, CHCRT_RAY_PRIMARY, 0, 0, stats);
    trace(camera, RayType::Primary, false, 0, 0, 0, stats);
    const auto start = Clock::now();
    const FrameTargets& t = *targets_;
    if (outOfCorePrimary_) {
        pixelGeometricNormals_ = outOfCorePrimary_(camera, t, nearPlaneFor(sceneBounds_));
        glFinish();
        stats.gbufferMs += millisecondsSince(start);
        if (passCallback_) passCallback_();
        return;
    }
    const CameraFrame frame = makeCameraFrame(camera, t.width, t.height);
    const ShaderProgram& program = gbufferFromHitsProgram_;
    program.use();
    program.set("cameraPosition", frame.eye);
    program.set("cameraForward", frame.forward);
    program.set("nearPlane", nearPlaneFor(sceneBounds_));
    program.set("pixelSpread", 2.0f * frame.tanHalfFovY / float(t.height));
    program.set("textureSide", float(sceneGpu_->baseColorSide()));
    glBindFramebuffer(GL_FRAMEBUFFER, t.gbuffer.id());
    glViewport(0, 0, t.width, t.height);
    // Every pixel is written (misses with the clear values); depth is written through gl_FragDepth, which
    // needs the depth test enabled.
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDisable(GL_BLEND);
    sceneGpu_->bindForShading();
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, t.rays[0].origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, t.rays[0].direction.id());
    glBindTextureUnit(CHCRT_UNIT_HIT, t.hits[0].hit.id());
    drawFullscreenTriangle();
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glFinish();
    stats.gbufferMs += millisecondsSince(start);
    if (passCallback_) passCallback_();
}

void Renderer::rasterizeGBuffer(const Camera& camera, FrameStats& stats) {
    const auto start = Clock::now();
    const FrameTargets& t = *targets_;
    const CameraFrame frame = makeCameraFrame(camera, t.width, t.height);
    const glm::mat4 clipFromWorld = clipFromView(frame, nearPlaneFor(sceneBounds_)) * viewFromWorld(frame);

    glBindFramebuffer(GL_FRAMEBUFFER, t.gbuffer.id());
    glViewport(0, 0, t.width, t.height);
    const float zero[4] = {0, 0, 0, 0};
    const GLuint noTriangle[4] = {CHCRT_NO_HIT_ID, 0, 0, 0};
    glClearBufferfv(GL_COLOR, CHCRT_GBUFFER_OUT_POSITION, zero);
    glClearBufferfv(GL_COLOR, CHCRT_GBUFFER_OUT_NORMAL, zero);
    glClearBufferfv(GL_COLOR, CHCRT_GBUFFER_OUT_ALBEDO, zero);
    glClearBufferuiv(GL_COLOR, CHCRT_GBUFFER_OUT_TRIANGLE, noTriangle);
    const float farDepth = 0.0f; // reversed Z
    glClearBufferfv(GL_DEPTH, 0, &farDepth);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDisable(GL_CULL_FACE); // scenes are not closed: both faces are visible
    glDisable(GL_BLEND);

    gbufferProgram_.use();
    gbufferProgram_.set("clipFromWorld", clipFromWorld);
    gbufferProgram_.set("cameraPosition", frame.eye);
    gbufferProgram_.set("cameraForward", frame.forward);
    sceneGpu_->bindForShading();
    sceneGpu_->bindForTracing(); // the BVH triangle buffer maps BVH-order triangles to original ids
    stats.gbufferTriangles += sceneGpu_->drawTriangles(clipFromWorld, frustumCulling_);

    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glFinish();
    stats.gbufferMs += millisecondsSince(start);
    if (passCallback_) passCallback_();
}

void Renderer::generateRayPass(const Camera& camera, RayType type, int sampleIndex, FrameStats& stats) {
    generateRays(camera, rayProgramIndex(type), sampleIndex, 0, stats);
}

void Renderer::traceRayPass(const Camera& camera, RayType type, int sampleIndex, FrameStats& stats) {
    trace(camera, type, false, sampleIndex, 0, 0, stats);
    stats.cappedRays += readAndResetCappedRays();
}

void Renderer::generateRays(const Camera& camera, int rayProgram, int sampleIndex, int raySet, FrameStats& stats) {
    const auto start = Clock::now();
    const FrameTargets& t = *targets_;
    const CameraFrame frame = makeCameraFrame(camera, t.width, t.height);
    const bool pixelNormals = outOfCorePrimary_ && pixelGeometricNormals_ != 0;
    const ShaderProgram& program = pixelNormals ? pixelNormalRaygenPrograms_[rayProgram] : raygenPrograms_[rayProgram];
    program.use();
    // Halton index 0 is (0, 0): start at 1. The bounce shadow rays use a later, independent part of the sequence.
    const glm::vec2 haltonSample = halton2D(uint32_t(sampleIndex) + 1u);
    program.set("haltonSample", haltonSample);
    program.set("bounceHaltonSample", halton2D(uint32_t(sampleIndex) + 7920u));
    program.set("seed", settings_.seed);
    const float maxRotation = glm::radians(settings_.rotationDegrees);
    program.set("maxRotation", maxRotation);
    const float lengthFraction =
        rayProgram == CHCRT_RAY_AO ? settings_.aoLengthFraction : settings_.diffuseLengthFraction;
    const float rayLength = lengthFraction * sceneDiagonal_;
    program.set("rayLength", rayLength);
    program.set("offsetScale", settings_.originOffset);
    const PrimaryRayBasis basis = primaryRayBasis(frame, t.width, t.height);
    program.set("cameraPosition", basis.eye);
    program.set("cameraForward", basis.forward);
    program.set("cameraRight", basis.right);
    program.set("cameraUp", basis.up);
    program.set("viewportSize", glm::vec2(t.width, t.height));
    cameraRays_[size_t(raySet)] = rayProgram == CHCRT_RAY_PRIMARY ? std::optional(basis) : std::nullopt;
    if (basis.eye != originEye_) { // the origins' offsets scale with the distance to the eye
        originEye_ = basis.eye;
        ++originGeneration_;
    }
    lightSweeps_[size_t(raySet)] = std::nullopt;
    if (rayProgram == CHCRT_RAY_SHADOW) {
        const Aabb light = light_.bounds();
        lightSweeps_[size_t(raySet)] = TraceRequest::LightSweep{originGeneration_, light.lower, light.upper};
    }
    hemisphereRays_[size_t(raySet)] = std::nullopt;
    if (rayProgram == CHCRT_RAY_AO) {
        hemisphereRays_[size_t(raySet)] =
            TraceRequest::HemisphereRays{originGeneration_, t.gbufferNormal.id(), haltonSample, maxRotation, rayLength};
    }
    setLightUniforms(program, light_);

    glBindFramebuffer(GL_FRAMEBUFFER, t.rays[raySet].framebuffer.id());
    glViewport(0, 0, t.width, t.height);
    // The shader writes the active-ray mask (RayTextures::active) as depth: no test, just the write.
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    sceneGpu_->bindForShading();
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_POSITION, t.gbufferPosition.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_NORMAL, t.gbufferNormal.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_TRIANGLE, t.gbufferTriangle.id());
    if (pixelNormals) glBindTextureUnit(CHCRT_UNIT_PIXEL_GEOMETRIC_NORMAL, pixelGeometricNormals_);
    // Bounce shadow rays read the diffuse rays (set 0) and their hits (hit set 0).
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, t.rays[0].origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, t.rays[0].direction.id());
    glBindTextureUnit(CHCRT_UNIT_BOUNCE_HIT, t.hits[0].hit.id());
    drawFullscreenTriangle();
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    glFinish();
    stats.raygenMs += millisecondsSince(start);
    stats.raysGenerated += uint64_t(t.width) * t.height;
}

void Renderer::trace(const Camera& camera, RayType type, bool bounceShadow, int sampleIndex, int raySet,
                     int hitSet, FrameStats& stats) {
    TraceRequest request;
    request.rayType = type;
    request.anyHit = bounceShadow || isAnyHit(type);
    request.bounceShadow = bounceShadow;
    request.sampleIndex = sampleIndex;
    request.camera = camera;
    if (type == RayType::Primary && !bounceShadow) request.cameraRays = cameraRays_[size_t(raySet)];
    if (type == RayType::Shadow && !bounceShadow) request.lightSweep = lightSweeps_[size_t(raySet)];
    if (type == RayType::Ao) request.hemisphereRays = hemisphereRays_[size_t(raySet)];
    sceneGpu_->bindForTracing();
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, CHCRT_ATOMIC_BINDING_CAPPED_RAYS, cappedRayCounter_.id());
    glFinish();
    const auto start = Clock::now();
    TraceStats& traceStats = stats.trace[size_t(type)];
    activeTracer_->trace(request, targets_->rays[raySet], targets_->hits[hitSet], targets_->width, targets_->height,
                   traceStats);
    glFinish();
    traceStats.milliseconds += millisecondsSince(start);
    if (passCallback_) passCallback_();
}

void Renderer::accumulate(RayType type, int /*sampleIndex*/, FrameStats& stats) {
    const auto start = Clock::now();
    const FrameTargets& t = *targets_;
    const ShaderProgram* program = &accumulateShadow_;
    GLuint fbo = t.accumDirectFbo.id();
    int raySet = 0;
    if (type == RayType::Ao) {
        program = &accumulateAo_;
        fbo = t.accumAoFbo.id();
    } else if (type == RayType::Diffuse) {
        program = &accumulateDiffuse_;
        fbo = t.accumIndirectFbo.id();
        raySet = 1; // the bounce shadow rays
    }
    program->use();
    setLightUniforms(*program, light_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, t.width, t.height);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    sceneGpu_->bindForShading();
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_NORMAL, t.gbufferNormal.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_ALBEDO, t.gbufferAlbedo.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_TRIANGLE, t.gbufferTriangle.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, t.rays[raySet].origin.id());
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, t.rays[raySet].direction.id());
    glBindTextureUnit(CHCRT_UNIT_HIT, t.hits[raySet].hit.id());
    glBindTextureUnit(CHCRT_UNIT_BOUNCE_HIT, t.hits[0].hit.id());
    drawFullscreenTriangle();
    glDisable(GL_BLEND);
    glFinish();
    stats.shadeMs += millisecondsSince(start);
}

void Renderer::compose(FrameStats& stats) { compose(stats, 0); }

ImageRgba32f Renderer::readIndirectImage() {
    FrameStats scratch;
    std::function<void()> callback = std::move(passCallback_); // not a pass of the frame
    passCallback_ = nullptr;
    compose(scratch, 1);
    ImageRgba32f image = readHdrImage();
    compose(scratch, 0);
    passCallback_ = std::move(callback);
    return image;
}

void Renderer::compose(FrameStats& stats, int outputMode) {
    const auto start = Clock::now();
    const FrameTargets& t = *targets_;
    composeProgram_.use();
    setLightUniforms(composeProgram_, light_);
    composeProgram_.set("shadowsEnabled", int(settings_.effects.shadows));
    composeProgram_.set("aoEnabled", int(settings_.effects.ao));
    composeProgram_.set("diffuseEnabled", int(settings_.effects.diffuse));
    composeProgram_.set("skyAmbient", glm::vec3(0.85f, 0.92f, 1.0f) * settings_.skyAmbient);
    composeProgram_.set("backgroundColor", glm::vec3(0.55f, 0.7f, 0.9f));
    composeProgram_.set("exposure", settings_.exposure);
    composeProgram_.set("outputMode", outputMode); // 0: full shading, 1: indirect only (compose.frag.glsl)
    glBindFramebuffer(GL_FRAMEBUFFER, t.output.id());
    glViewport(0, 0, t.width, t.height);
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_POSITION, t.gbufferPosition.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_NORMAL, t.gbufferNormal.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_ALBEDO, t.gbufferAlbedo.id());
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_TRIANGLE, t.gbufferTriangle.id());
    glBindTextureUnit(CHCRT_UNIT_ACCUM_DIRECT, t.accumDirect.id());
    glBindTextureUnit(CHCRT_UNIT_ACCUM_AO, t.accumAo.id());
    glBindTextureUnit(CHCRT_UNIT_ACCUM_INDIRECT, t.accumIndirect.id());
    drawFullscreenTriangle();
    glFinish();
    stats.shadeMs += millisecondsSince(start);
    if (passCallback_) passCallback_();
}

uint64_t Renderer::readAndResetCappedRays() {
    uint32_t count = 0;
    glGetNamedBufferSubData(cappedRayCounter_.id(), 0, sizeof(count), &count);
    const uint32_t zero = 0;
    glNamedBufferSubData(cappedRayCounter_.id(), 0, sizeof(zero), &zero);
    return count;
}

ImageRgba32f Renderer::readDisplayImage() const {
    return readImageTexture(targets_->outputDisplay.id(), targets_->width, targets_->height);
}

ImageRgba32f Renderer::readHdrImage() const {
    return readImageTexture(targets_->outputHdr.id(), targets_->width, targets_->height);
}

std::vector<Ray> Renderer::readRays(int set) const {
    const int w = targets_->width, h = targets_->height;
    const std::vector<float> origins = readTexture<float>(targets_->rays[set].origin.id(), w, h, GL_RGBA, GL_FLOAT);
    const std::vector<float> directions =
        readTexture<float>(targets_->rays[set].direction.id(), w, h, GL_RGBA, GL_FLOAT);
    std::vector<Ray> rays(size_t(w) * h);
    for (size_t i = 0; i < rays.size(); ++i) {
        rays[i].origin = glm::vec3(origins[i * 4], origins[i * 4 + 1], origins[i * 4 + 2]);
        rays[i].tmin = origins[i * 4 + 3];
        rays[i].direction = glm::vec3(directions[i * 4], directions[i * 4 + 1], directions[i * 4 + 2]);
        rays[i].tmax = directions[i * 4 + 3];
    }
    return rays;
}

std::vector<Hit> Renderer::readHits(int set) const {
    const int w = targets_->width, h = targets_->height;
    const std::vector<uint32_t> data =
        readTexture<uint32_t>(targets_->hits[set].hit.id(), w, h, GL_RGBA_INTEGER, GL_UNSIGNED_INT);
    std::vector<Hit> hits(size_t(w) * h);
    for (size_t i = 0; i < hits.size(); ++i) {
        std::memcpy(&hits[i].t, &data[i * 4], sizeof(float));
        hits[i].triangleId = data[i * 4 + 1];
        std::memcpy(&hits[i].u, &data[i * 4 + 2], sizeof(float));
        std::memcpy(&hits[i].v, &data[i * 4 + 3], sizeof(float));
    }
    return hits;
}

std::vector<uint32_t> Renderer::readTraceSteps(int set) const {
    const int w = targets_->width, h = targets_->height;
    const std::vector<uint32_t> data =
        readTexture<uint32_t>(targets_->hits[set].cost.id(), w, h, GL_RGBA_INTEGER, GL_UNSIGNED_INT);
    std::vector<uint32_t> steps(size_t(w) * h);
    for (size_t i = 0; i < steps.size(); ++i) {
        const uint64_t sum = uint64_t(data[i * 4]) + data[i * 4 + 1] + data[i * 4 + 2];
        steps[i] = uint32_t(std::min<uint64_t>(sum, CHCRT_TRACE_STEPS_COUNT)) |
                   (data[i * 4 + 3] != 0 ? CHCRT_TRACE_STEPS_CAPPED : 0u);
    }
    return steps;
}

} // namespace chcrt
