#include "app/viewer/viewer_app.h"

#include "app/methods.h"
#include "app/outofcore_report.h"
#include "app/report.h"
#include "app/viewer/residency_view.h"
#include "app/viewer/shaft_view.h"
#include "app/viewer/view_display.h"
#include "app/viewer/viewer_script.h"
#include "app/viewer/viewer_session.h"
#include "app/viewer/viewer_ui.h"
#include "app/viewer/viewer_window.h"
#include "app/viewer/walk_controller.h"
#include "culling/chcrt_tracer.h"
#include "renderer/core/error.h"
#include "renderer/gl/gl.h"
#include "renderer/outofcore/chs_file.h"
#include "renderer/outofcore/out_of_core_tracer.h"
#include "renderer/outofcore/primary_resolve.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>

namespace chcrt::app {
namespace {

// `--ls-cache ""` (no cache) in the viewer: a method switch's Line Space / N-tree build still goes through a cache
// directory, so that it runs on the worker (methodCacheBuild) while the window keeps drawing (issue #6), but a
// private temporary one, removed when the viewer exits: nothing outlives the session, as the flag asks.
class PrivateCacheDirectory {
public:
    PrivateCacheDirectory() = default;
    PrivateCacheDirectory(const PrivateCacheDirectory&) = delete;
    PrivateCacheDirectory& operator=(const PrivateCacheDirectory&) = delete;
    ~PrivateCacheDirectory() {
        std::error_code ignored;
        if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
    }
    void create() {
        std::filesystem::path base = std::filesystem::temp_directory_path();
        for (int attempt = 0; path_.empty(); ++attempt) {
            const std::filesystem::path candidate =
                base / ("chcrt-view-" + std::to_string(::getpid()) + "-" + std::to_string(attempt));
            if (std::filesystem::create_directory(candidate)) path_ = candidate; // false: it exists, try the next
        }
    }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

using Clock = std::chrono::steady_clock;
constexpr double kScriptSecondsPerFrame = 1.0 / 30.0; // fixed time step of scripted sessions
constexpr size_t kFrameHistory = 120;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The CHC+RT debug image a view mode shows: its own for the debug views; for `cost` the traversal steps summed
// over CHC+RT's subtree passes (CHC+RT writes no per-ray cost target); none otherwise.
ChcrtDebugImage chcrtDebugImageOf(ViewMode mode) {
    switch (mode) {
    case ViewMode::Overdraw: return ChcrtDebugImage::Overdraw;
    case ViewMode::Subtrees: return ChcrtDebugImage::Subtrees;
    case ViewMode::Batches: return ChcrtDebugImage::Batches;
    case ViewMode::Cost: return ChcrtDebugImage::Cost;
    default: return ChcrtDebugImage::None;
    }
}

int glfwKeyFor(const std::string& name) {
    if (name == "R") return GLFW_KEY_R;
    if (name == "F") return GLFW_KEY_F;
    if (name == "P") return GLFW_KEY_P;
    if (name == "V") return GLFW_KEY_V;
    if (name == "C") return GLFW_KEY_C;
    if (name == "F9") return GLFW_KEY_F9;
    if (name == "F12") return GLFW_KEY_F12;
    if (name == "+") return GLFW_KEY_EQUAL;
    if (name == "-") return GLFW_KEY_MINUS;
    if (name == "TAB") return GLFW_KEY_TAB;
    throw InputError("script: cannot press '" + name + "'");
}

bool sameCamera(const Camera& a, const Camera& b) {
    return a.eye == b.eye && a.target == b.target && a.up == b.up && a.fovYDegrees == b.fovYDegrees;
}

nlohmann::json statsToJson(const FrameStats& s) {
    nlohmann::json trace = nlohmann::json::object();
    for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
        const TraceStats& t = s.trace[size_t(type)];
        trace[toString(type)] = {{"passes", t.passes}, {"ms", t.milliseconds}};
    }
    return {{"gbuffer_ms", s.gbufferMs}, {"raygen_ms", s.raygenMs}, {"trace_ms", s.traceMs()},
            {"shade_ms", s.shadeMs},     {"renderer_ms", s.totalMs}, {"trace", trace},
            {"rays_generated", s.raysGenerated}, {"capped_rays", s.cappedRays}};
}

// One frame's CHC+RT counters: the difference of the tracer's running totals around the frame.
ViewerChcrtStats chcrtFrameStats(const ChcrtStats& before, const ChcrtStats& after) {
    ViewerChcrtStats f;
    f.traces = after.traces - before.traces;
    f.queries = after.queries - before.queries;
    f.queriesSkippedExtent = after.queriesSkippedExtent - before.queriesSkippedExtent;
    f.subtreesScheduled = after.subtreesScheduled - before.subtreesScheduled;
    f.shaderCalls = after.shaderCalls - before.shaderCalls;
    f.phase1Ms = after.phase1Ms - before.phase1Ms;
    f.phase2Ms = after.phase2Ms - before.phase2Ms;
    f.phase3Ms = after.phase3Ms - before.phase3Ms;
    f.fallbackMs = after.fallbackMs - before.fallbackMs;
    f.fallbackTraces = after.fallbackTraces - before.fallbackTraces;
    return f;
}

nlohmann::json chcrtStatsToJson(const ViewerChcrtStats& c) {
    return {{"traces", c.traces},         {"queries", c.queries},       {"subtrees_scheduled", c.subtreesScheduled},
            {"shader_calls", c.shaderCalls}, {"phase1_ms", c.phase1Ms}, {"phase2_ms", c.phase2Ms},
            {"phase3_ms", c.phase3Ms},     {"fallback_ms", c.fallbackMs}, {"fallback_traces", c.fallbackTraces},
            {"queries_skipped_extent", c.queriesSkippedExtent}};
}

// Whether the viewer's method `m` can trace a prepared scene out of core (the raster-only method has no tracer).
bool hasOutOfCoreForm(const std::string& m) { return m != kRasterOnlyMethod && findGpuMethod(m).outOfCoreForm; }

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

class Viewer {
public:
    explicit Viewer(const ViewOptions& options);
    ~Viewer();
    int run();

private:
    // Window input: keys are queued by the GLFW callback (chained through ImGui's) and handled between frames.
    static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
    static void onScroll(GLFWwindow* window, double x, double y);

    void finishLoading();
    void finishShaftPick();
    void startLoading(const std::string& scene);
    SceneLoader::GpuUpload workerUpload() const;
    std::string tracerKey() const; // method, always-cull and parameters a tracer is made for
    void applyMethod();
    bool prepareMethodCache();
    void handleInteractiveInput(double seconds);
    void handleKey(int key);
    void handleKeyOrThrow(int key);
    bool advanceScript();   // false when the script has ended
    void runStepActions(const ScriptStep& step);
    void runStepChecks(const ScriptStep& step);
    void checkExpectations(const nlohmann::json& expect);
    void updatePlayback();
    void renderIfNeeded();
    void drawWindow();
    void applyPanelActions(const ViewerActions& actions);

    void setCamera(const Camera& camera) {
        camera_ = camera;
        walk_.setCamera(camera);
    }
    void resetCamera() { setCamera(scene_->path.cameraAtFrame(0)); }
    void takeScreenshot(const std::string& file);
    void printCommandLine();
    void startRecording();
    void stopRecording(const std::string& file);
    void recordKeyframe();
    void notice(const std::string& text);
    void writeStatsJson() const;
    void renderShafts(FrameStats& stats);
    void renderResidency(FrameStats& stats);
    void renderShadedFrame(FrameStats& stats);
    std::vector<float> shownRgb() const;
    std::vector<uint8_t> residentSubtrees() const;
    void traceDebugRays(ChcrtTracer* chcrt, FrameStats& stats);
    void updateShaftPick(int w, int h);
    void sampleLoadProgress();

    ViewOptions options_;
    ViewerSettings settings_;
    GpuSession gpu_;
    GLFWwindow* window_ = nullptr;
    GLFWwindow* uploadWindow_ = nullptr; // shares window_'s objects; scene uploads on the loading worker
    std::unique_ptr<SceneSession> scene_;
    std::unique_ptr<Tracer> tracer_;
    // Out of core, the first tracer of a loaded scene, made by the loading worker for premadeKey_ (tracerKey()).
    std::unique_ptr<Tracer> premadeTracer_;
    std::string premadeKey_;
    // tracer_ when it traces out of core (--out-of-core with a prepared scene, CHC+RT §5.4), else nullptr.
    outofcore::OutOfCoreTracer* outOfCore_ = nullptr;
    std::string activeMethod_;
    bool activeAlwaysCull_ = false;
    std::string activeParameters_;
    std::unique_ptr<ViewDisplay> display_;
    std::unique_ptr<ViewerPanel> panel_;
    SceneLoader loader_;
    // With `--ls-cache ""`: the session's private cache directory (below), removed after cacheJob_ has ended.
    PrivateCacheDirectory privateCache_;
    // A method switch's Line Space / N-tree build on a worker; declared after scene_ (whose BVH it reads) so that it
    // is destroyed (joined) first.
    BackgroundJob cacheJob_;
    std::string cacheWarmKey_; // method + parameters whose build is in the disk cache (or needs none)
    WalkController walk_;
    Camera camera_, renderedCamera_;
    bool dirty_ = true; // the view must be rendered again from scratch
    bool showPanel_ = true;
    bool playing_ = false;
    int pathFrame_ = 0;
    bool recording_ = false;
    CameraPath recorded_;
    Clock::time_point recordStart_;
    int recordedFrameStart_ = 0;
    int screenshotCount_ = 0;

    // Shafts view: the pending pick (internal pixel), the picked node and what it was computed for.
    std::optional<std::pair<int, int>> pendingPick_;
    std::optional<ShaftPick> shaftPick_;
    Camera pickCamera_;
    int pickWidth_ = 0, pickHeight_ = 0;
    std::pair<int, int> pickPixel_{0, 0};
    std::string pickParameters_; // N/D/T and scene the pick was computed with
    // The picked node's Line Space is built on a worker (a node of a big scene at a low cut depth holds many
    // triangles); the previous pick stays shown meanwhile. Declared after scene_, whose BVH it reads.
    BackgroundJob pickJob_;
    std::shared_ptr<std::optional<ShaftPick>> pickResult_;
    std::optional<ResidencyCounts> lastResidency_; // of the last residency-view frame (out of core)
    bool leftWasDown_ = false;
    nlohmann::json loadLog_ = nlohmann::json::array(); // samples of the loading worker's progress

    // Input
    std::vector<int> pressedKeys_;
    float scrollSteps_ = 0;
    bool looking_ = false;
    double lastCursorX_ = 0, lastCursorY_ = 0;

    // Script
    bool scripted_ = false;
    std::vector<ScriptStep> script_;
    size_t nextStep_ = 0;
    int framesLeft_ = 0;
    const ScriptStep* currentStep_ = nullptr;
    int failures_ = 0;
    int scriptFrame_ = 0;

    // Statistics
    ViewerStatus status_;
    std::deque<float> history_;
    nlohmann::json frameLog_ = nlohmann::json::array();
    int renderedFrames_ = 0;
};

Viewer::Viewer(const ViewOptions& options) : options_(options) {
    settings_.common = options.common;
    settings_.renderScale = options.renderScale;
    settings_.accumulate = !options.noAccumulate;
    applySettings(settings_, {{"method", options.method}, {"viewMode", options.viewMode}}); // validates all
    if (options.common.outOfCoreScene.enabled && !outofcore::isPreparedScenePath(options.common.scene)) {
        throw InputError("--out-of-core needs a prepared scene (--scene file.chs; see chcrt prepare)");
    }
    if (options.common.outOfCoreScene.enabled && !hasOutOfCoreForm(options.method)) {
        // As `chcrt render --out-of-core` (app/methods.cpp); the panel refuses such methods with a message.
        throw InputError("--out-of-core: method " + options.method + " has no out-of-core form; use --method chcrt, "
                         "chcrt-noadapt or chcrt-aggressive");
    }
    showPanel_ = !options.hidePanel;
    playing_ = options.play;
    if (!options.script.empty()) {
        script_ = loadViewerScript(options.script);
        scripted_ = true;
    }

    auto context = std::make_unique<GlfwWindowContext>(options.common.render.width, options.common.render.height,
                                                       options.common.glDebug);
    window_ = context->window();
    uploadWindow_ = context->uploadWindow();
    gpu_.context = std::move(context);
    glfwSetWindowUserPointer(window_, this);
    // Installed before ImGui's backend, which chains to them.
    glfwSetKeyCallback(window_, &Viewer::onKey);
    glfwSetScrollCallback(window_, &Viewer::onScroll);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini in the working directory
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    display_ = std::make_unique<ViewDisplay>();
    panel_ = std::make_unique<ViewerPanel>(options.common.scene);
    // Out of core the interactive viewer streams a cold cache over frames (at most 16 subtree uploads per trace;
    // incomplete frames are re-rendered until complete); scripts get complete, exact frames unless they ask.
    CommonOptions& c = settings_.common;
    if (!c.isGiven("--uploads-per-trace")) c.outOfCore.maxUploadsPerTrace = scripted_ ? 0 : 16;
    if (c.lineSpaceTracing.cacheDirectory.empty() && !c.outOfCoreScene.enabled) {
        privateCache_.create();
        c.lineSpaceTracing.cacheDirectory = privateCache_.path().string();
    }
    loader_.start(c, workerUpload());
}

std::string Viewer::tracerKey() const {
    return settings_.method + (settings_.chcrtAlwaysCull ? " always-cull " : " ") + methodParameters(settings_.common);
}

// Waits for a worker that reads the previous scene; what it made or threw no longer matters.
void endJobOfPreviousScene(BackgroundJob& job) {
    if (!job.busy()) return;
    try {
        job.take();
    } catch (const InputError&) {
    }
}

// Another scene, from the panel or a script: its own default camera.
void Viewer::startLoading(const std::string& scene) {
    CommonOptions o = settings_.common;
    o.scene = scene;
    o.cameraPath.clear();
    o.eye.clear();
    o.target.clear();
    loader_.start(o, workerUpload());
}

// The loading worker's last step: the scene's GPU upload on the hidden window's shared context (issue #6: the
// window never waits for long work). Without that context the upload runs in finishLoading, on this thread.
SceneLoader::GpuUpload Viewer::workerUpload() const {
    if (!uploadWindow_) return nullptr;
    // Out of core the method's tracer is made here as well: its GPU subtree cache is one large allocation (0.85 s
    // for 1 GiB on llvmpipe). Its GL objects are shared ones (buffers, textures, programs); those that are not
    // (queries, framebuffers, vertex arrays) are made on first use, on the main thread.
    const std::string method = settings_.method;
    const bool alwaysCull = settings_.chcrtAlwaysCull;
    const std::string key = tracerKey();
    return [window = uploadWindow_, method, alwaysCull, key](const SceneSession& session) {
        glfwMakeContextCurrent(window);
        struct Release { // also when the upload throws (GlError: a buffer beyond the texture-buffer limit)
            ~Release() {
                glFinish(); // complete before the main thread binds the objects (GL 4.5 §5.3, shared objects)
                glfwMakeContextCurrent(nullptr);
            }
        } release;
        SceneLoader::Uploaded uploaded;
        uploaded.scene = std::make_unique<SceneGpu>(session.scene, session.bvh);
        const bool outOfCore =
            session.options.outOfCoreScene.enabled && outofcore::isPreparedScenePath(session.options.scene);
        if (outOfCore && hasOutOfCoreForm(method)) {
            uploaded.tracer = makeTracer(method, session, alwaysCull);
            uploaded.tracerKey = key;
        }
        return uploaded;
    };
}

Viewer::~Viewer() {
    tracer_.reset();
    display_.reset();
    gpu_.renderer.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    // gpu_.context (the window) goes last, with the members.
}

void Viewer::onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
    auto* self = static_cast<Viewer*>(glfwGetWindowUserPointer(window));
    if (action == GLFW_PRESS || action == GLFW_REPEAT) self->pressedKeys_.push_back(key);
}

void Viewer::onScroll(GLFWwindow* window, double /*x*/, double y) {
    static_cast<Viewer*>(glfwGetWindowUserPointer(window))->scrollSteps_ += float(y);
}

int Viewer::run() {
    auto last = Clock::now();
    bool idle = false;
    while (!glfwWindowShouldClose(window_)) {
        // An interactive viewer with nothing to render sleeps until input arrives (or 50 ms pass, for the panel).
        if (idle) glfwWaitEventsTimeout(0.05);
        else glfwPollEvents();
        const auto start = Clock::now();
        const double seconds = std::chrono::duration<double>(start - last).count();
        last = start;
        if (loader_.busy()) sampleLoadProgress();
        const bool loaded = loader_.busy() && loader_.finished();
        if (loaded) finishLoading();
        if (scripted_) {
            if (!advanceScript()) break;
        } else if (scene_) {
            handleInteractiveInput(seconds);
        }
        const int renderedBefore = renderedFrames_;
        if (scene_ && gpu_.renderer && !(scripted_ && loader_.busy())) { // scripts wait for a loading scene
            updatePlayback();
            renderIfNeeded();
        }
        drawWindow();
        status_.frameMs = millisecondsSince(start);
        // The whole iteration of a rendered frame: input, render, display, panel and buffer swap.
        const bool rendered = renderedFrames_ != renderedBefore;
        if (rendered) frameLog_.back()["loop_ms"] = status_.frameMs;
        // The graph shows rendered frames; the iteration that uploaded a scene would flatten it.
        if (rendered && !loaded) {
            history_.push_back(float(status_.frameMs));
            if (history_.size() > kFrameHistory) history_.pop_front();
        }
        if (pickJob_.busy() && pickJob_.finished()) { // the shafts view's new pick: show it
            finishShaftPick();
            dirty_ = true;
        }
        idle = !scripted_ && !rendered && !loader_.busy() && !cacheJob_.busy() && !pickJob_.busy() && !playing_ &&
               !looking_;
    }
    writeStatsJson();
    if (scripted_) {
        std::vector<double> frameMs, rendererMs;
        for (const auto& f : frameLog_) {
            frameMs.push_back(f.value("loop_ms", f["frame_ms"].get<double>()));
            rendererMs.push_back(f["renderer_ms"].get<double>());
        }
        std::printf("view: %d frames rendered, median frame %.2f ms (renderer %.2f ms)%s\n", renderedFrames_,
                    median(frameMs), median(rendererMs), failures_ ? ", expectations FAILED" : "");
    }
    return failures_ ? kExitCheckFailed : kExitOk;
}

void Viewer::finishLoading() {
    const bool first = !scene_;
    std::unique_ptr<SceneSession> loaded;
    try {
        loaded = loader_.take();
    } catch (const std::runtime_error& e) { // InputError, or GlError from the GPU upload
        if (first) throw; // nothing to show: a bad --scene is a usage error
        notice(std::string("cannot load the scene: ") + e.what());
        return;
    }
    const double loadSeconds = loader_.elapsedSeconds();
    SceneLoader::Uploaded uploadedGpu = loader_.takeUploaded();
    std::unique_ptr<SceneGpu> uploadedScene = std::move(uploadedGpu.scene);
    premadeTracer_ = std::move(uploadedGpu.tracer);
    premadeKey_ = uploadedGpu.tracerKey;
    const bool uploaded = uploadedScene != nullptr;
    sampleLoadProgress(); // the worker has finished: complete, 100 %
    endJobOfPreviousScene(pickJob_); // it reads the previous scene's BVH
    shaftPick_.reset();   // a node of the previous scene: the new one starts with the centre pixel
    pickParameters_.clear();
    const auto uploadStart = Clock::now();
    // The scene is on the GPU already (uploaded by the worker, unless there is no shared context); the renderer's
    // and the method's programs are made here, on the drawing context.
    endJobOfPreviousScene(cacheJob_); // it reads the previous scene's BVH (its result stays in the disk cache)
    cacheWarmKey_.clear();
    tracer_.reset();
    outOfCore_ = nullptr;
    gpu_.renderer.reset();
    scene_ = std::move(loaded);
    // --out-of-core applies to prepared scenes; another scene loaded from the panel is traced in core. A scene
    // that is not in core (docs/outofcore.md) renders as `chcrt render --out-of-core` does: traced primary
    // visibility resolved through the out-of-core tracer, no diffuse effect.
    scene_->options.outOfCoreScene.enabled =
        options_.common.outOfCoreScene.enabled && outofcore::isPreparedScenePath(scene_->options.scene);
    settings_.sceneNotInCore = !scene_->sceneInCore;
    int w = 1, h = 1;
    int fbWidth = 1, fbHeight = 1;
    glfwGetFramebufferSize(window_, &fbWidth, &fbHeight);
    internalSize(settings_, std::max(fbWidth, 1), std::max(fbHeight, 1), w, h);
    gpu_.renderer = std::make_unique<Renderer>(scene_->scene, scene_->bvh, scene_->light,
                                               toRenderSettings(settings_, w, h, 0), std::move(uploadedScene));
    activeMethod_.clear();
    applyMethod();
    premadeTracer_.reset(); // not taken (the method changed during the load): freed here, with its context current
    pathFrame_ = 0;
    resetCamera();
    if (first && !options_.common.frames.empty()) { // --frames: where the path starts
        pathFrame_ = selectFrames(options_.common, scene_->path, "0").front();
        setCamera(scene_->path.cameraAtFrame(pathFrame_));
    }
    walk_ = WalkController(camera_, scene_->scene.bounds());
    gpu_.renderer->warmUp(camera_);
    status_.sceneName = settings_.common.scene = loader_.scene();
    status_.triangles = sceneTriangles(*scene_);
    dirty_ = true;
    char text[160];
    std::snprintf(text, sizeof(text), "loaded %s: %llu triangles, %.2f s loading + BVH%s (worker thread), %.2f s "
                  "renderer set-up (main thread)", loader_.scene().c_str(),
                  static_cast<unsigned long long>(status_.triangles), loadSeconds,
                  uploaded ? " + GPU upload" : "", millisecondsSince(uploadStart) / 1000.0);
    notice(text);
}

void Viewer::applyMethod() {
    if (settings_.method == activeMethod_ && !activeMethod_.empty() && settings_.chcrtAlwaysCull == activeAlwaysCull_ &&
        methodParameters(settings_.common) == activeParameters_) {
        return;
    }
    const std::string previous = activeMethod_;
    const bool outOfCore = scene_->options.outOfCoreScene.enabled;
    const std::string& m = settings_.method;
    const bool tracesOutOfCore = hasOutOfCoreForm(m) || (m == kRasterOnlyMethod && scene_->sceneInCore);
    if (outOfCore && !tracesOutOfCore && !previous.empty()) {
        // Refused before the current tracer is destroyed: its GPU cache (and CHC+RT fronts) stay as they are.
        notice("method " + m + " has no out-of-core form (pure BVH and Line Space tracing need the whole scene on "
               "the GPU); keeping " + previous);
        settings_.method = previous;
        if (settings_.chcrtAlwaysCull == activeAlwaysCull_ && methodParameters(settings_.common) == activeParameters_) {
            return;
        }
    }
    // Methods read their parameters from the session's options (app/methods.cpp).
    copyMethodParameters(settings_.common, scene_->options);
    if (!prepareMethodCache()) return; // building on the worker: the current tracer keeps rendering meanwhile
    activeParameters_ = methodParameters(settings_.common);
    gpu_.renderer->useTracer(nullptr);
    gpu_.renderer->setOutOfCorePrimary({}); // it points into the out-of-core tracer destroyed next
    outOfCore_ = nullptr;
    tracer_.reset(); // first: an out-of-core tracer's GPU cache is freed before the next one is allocated
    const auto create = [&](const std::string& method) {
        if (method == kRasterOnlyMethod) {
            // Its traced primary rays use the renderer's pure BVH, which holds nothing out of core.
            if (!scene_->sceneInCore) throw InputError("method raster needs the scene in core; use chcrt");
            return std::unique_ptr<Tracer>();
        }
        if (premadeTracer_ && method == settings_.method && premadeKey_ == tracerKey()) {
            return std::move(premadeTracer_); // made by the loading worker (workerUpload)
        }
        return makeTracer(method, *scene_, settings_.chcrtAlwaysCull); // nullptr for "bvh": the renderer's own
    };
    try {
        tracer_ = create(settings_.method);
    } catch (const InputError& error) {
        // Refused methods (no out-of-core form) or parameters (e.g. a visibility threshold for exact CHC+RT): in
        // core back to pure BVH; out of core back to the previous method, else chcrt with default parameters.
        const std::string fallback = !outOfCore ? "bvh" : !previous.empty() && previous != settings_.method ? previous
                                                                                                        : "chcrt";
        notice(std::string("method ") + settings_.method + ": " + error.what() + "; using " + fallback);
        settings_.method = fallback;
        if (outOfCore) {
            try {
                tracer_ = create(fallback);
            } catch (const InputError&) { // the parameters are refused: chcrt with its defaults (budget errors propagate)
                copyMethodParameters(CommonOptions{}, settings_.common);
                copyMethodParameters(settings_.common, scene_->options);
                activeParameters_ = methodParameters(settings_.common);
                settings_.method = "chcrt";
                tracer_ = create("chcrt");
            }
        }
    }
    outOfCore_ = dynamic_cast<outofcore::OutOfCoreTracer*>(tracer_.get());
    // Not in core: the G-buffer is resolved through this tracer's recorded primary subtrees (as chcrt render).
    if (outOfCore_ && !scene_->sceneInCore) installOutOfCorePrimary(*gpu_.renderer, *outOfCore_);
    gpu_.renderer->useTracer(tracer_.get());
    activeMethod_ = settings_.method;
    activeAlwaysCull_ = settings_.chcrtAlwaysCull;
}

// True when the method's Line Spaces / N-tree are in the disk cache (or it needs none): makeTracer then only loads
// them. Otherwise their build runs on cacheJob_ and this returns false until it has finished (a change of method
// or parameters meanwhile starts the next build once it is done). Scripts wait for the build in place, so that
// their frames and screenshots show the method they switched to.
bool Viewer::prepareMethodCache() {
    const std::string key = settings_.method + " " + methodParameters(settings_.common);
    if (key == cacheWarmKey_) return true;
    if (cacheJob_.busy()) {
        if (!cacheJob_.finished() && !scripted_) return false;
        const std::string built = cacheJob_.name();
        try {
            cacheJob_.take();
        } catch (const InputError& error) { // e.g. an unwritable --ls-cache: makeTracer reports it again
            notice(std::string("building for ") + built + ": " + error.what());
        }
        if (built == key) {
            cacheWarmKey_ = key;
            return true;
        }
    }
    std::function<void(Progress&)> job =
        settings_.method == kRasterOnlyMethod ? nullptr : methodCacheBuild(settings_.method, *scene_);
    if (!job) {
        cacheWarmKey_ = key;
        return true;
    }
    cacheJob_.start(key, std::move(job));
    notice("building the Line Spaces of " + settings_.method + " on a worker thread into " +
           scene_->options.lineSpaceTracing.cacheDirectory +
           (privateCache_.path().empty() ? "" : " (private to this session: --ls-cache \"\")"));
    if (!scripted_) return false;
    return prepareMethodCache(); // waits for it
}

void Viewer::handleInteractiveInput(double seconds) {
    const ImGuiIO& io = ImGui::GetIO();
    std::vector<int> keys = std::move(pressedKeys_);
    pressedKeys_.clear();
    WalkInput input;
    if (!io.WantCaptureKeyboard) {
        for (int key : keys) handleKey(key);
        auto held = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS; };
        input.forward = held(GLFW_KEY_W);
        input.back = held(GLFW_KEY_S);
        input.left = held(GLFW_KEY_A);
        input.right = held(GLFW_KEY_D);
        input.up = held(GLFW_KEY_E);
        input.down = held(GLFW_KEY_Q);
        input.fast = held(GLFW_KEY_LEFT_SHIFT) || held(GLFW_KEY_RIGHT_SHIFT);
    }
    double x = 0, y = 0;
    glfwGetCursorPos(window_, &x, &y);
    const bool rightHeld = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    if (rightHeld && (looking_ || !io.WantCaptureMouse)) {
        if (looking_) input.lookPixels = glm::vec2(float(x - lastCursorX_), float(y - lastCursorY_));
        looking_ = true;
    } else {
        looking_ = false;
    }
    lastCursorX_ = x;
    lastCursorY_ = y;
    // Left click in the view: pick the pixel for the shafts view (window coordinates → internal image).
    const bool leftDown = glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (leftDown && !leftWasDown_ && !io.WantCaptureMouse && display_->width() > 0) {
        int windowWidth = 1, windowHeight = 1;
        glfwGetWindowSize(window_, &windowWidth, &windowHeight);
        const int px = std::clamp(int(x / std::max(windowWidth, 1) * display_->width()), 0, display_->width() - 1);
        const int py = std::clamp(int(y / std::max(windowHeight, 1) * display_->height()), 0, display_->height() - 1);
        pendingPick_ = std::make_pair(px, py);
        dirty_ = true;
    }
    leftWasDown_ = leftDown;
    if (!io.WantCaptureMouse) input.scrollSteps = scrollSteps_;
    scrollSteps_ = 0;
    if (input.any()) {
        playing_ = false; // the user takes over from the path
        if (walk_.update(input, std::min(seconds, 0.25))) camera_ = walk_.camera();
    }
}

void Viewer::handleKey(int key) {
    try {
        handleKeyOrThrow(key);
    } catch (const InputError& e) {
        if (scripted_) throw; // a script's error ends it (exit 2)
        notice(e.what());     // an unwritable screenshot or path must not end an interactive session
    }
}

void Viewer::handleKeyOrThrow(int key) {
    switch (key) {
    case GLFW_KEY_R: resetCamera(); pathFrame_ = 0; playing_ = false; break;
    case GLFW_KEY_F: walk_.frameScene(); camera_ = walk_.camera(); playing_ = false; break;
    case GLFW_KEY_P: playing_ = !playing_; break;
    case GLFW_KEY_V: {
        const auto& modes = allViewModes();
        const size_t next = (size_t(settings_.viewMode) + 1) % modes.size();
        settings_.viewMode = modes[next];
        dirty_ = true;
        break;
    }
    case GLFW_KEY_C: printCommandLine(); break;
    case GLFW_KEY_F9:
        if (recording_) stopRecording(options_.recordFile);
        else startRecording();
        break;
    case GLFW_KEY_F12: {
        char name[64];
        std::snprintf(name, sizeof(name), "chcrt_view_%04d.png", screenshotCount_++);
        takeScreenshot(name);
        break;
    }
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: walk_.setSpeed(walk_.speed() * WalkController::kSpeedStep); break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: walk_.setSpeed(walk_.speed() / WalkController::kSpeedStep); break;
    case GLFW_KEY_TAB: showPanel_ = !showPanel_; break;
    case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window_, GLFW_TRUE); break;
    default: break;
    }
}

bool Viewer::advanceScript() {
    pressedKeys_.clear(); // scripted sessions ignore real input
    scrollSteps_ = 0;
    if (loader_.busy() || !scene_) return true; // wait for the scene
    while (framesLeft_ == 0) {
        if (currentStep_) { // the step's frames are done: its checks see their result
            runStepChecks(*currentStep_);
            currentStep_ = nullptr;
        }
        if (nextStep_ >= script_.size() || failures_ > 0) return false;
        currentStep_ = &script_[nextStep_++];
        runStepActions(*currentStep_);
        framesLeft_ = currentStep_->frames;
        if (loader_.busy()) return true;
    }
    --framesLeft_;
    ++scriptFrame_;
    if (currentStep_->held.any() && walk_.update(currentStep_->held, kScriptSecondsPerFrame)) {
        playing_ = false;
        camera_ = walk_.camera();
    }
    return true;
}

void Viewer::runStepActions(const ScriptStep& step) {
    if (!step.loadScene.empty()) startLoading(step.loadScene);
    if (step.resize) glfwSetWindowSize(window_, step.resize->first, step.resize->second);
    if (step.set) {
        applySettings(settings_, *step.set);
        dirty_ = true;
    }
    if (step.camera) {
        setCamera(*step.camera);
        playing_ = false;
    }
    if (step.pathFrame) {
        if (*step.pathFrame >= scene_->path.frameCount()) {
            throw InputError("script: pathFrame " + std::to_string(*step.pathFrame) + " is past the path's end (" +
                             std::to_string(scene_->path.frameCount()) + " frames)");
        }
        pathFrame_ = *step.pathFrame;
        setCamera(scene_->path.cameraAtFrame(pathFrame_));
    }
    if (step.play) playing_ = *step.play;
    if (step.pick) {
        pendingPick_ = *step.pick;
        dirty_ = true;
    }
    if (step.scrollSteps != 0) walk_.update(WalkInput{.scrollSteps = step.scrollSteps}, 0.0);
    if (step.action == "reset") handleKey(GLFW_KEY_R);
    else if (step.action == "frameScene") handleKey(GLFW_KEY_F);
    else if (step.action == "copyCommandLine") printCommandLine();
    else if (step.action == "recordStart") startRecording();
    if (!step.recordStop.empty()) stopRecording(step.recordStop);
    for (const std::string& key : step.presses) handleKey(glfwKeyFor(key));
    // A step with no frames has its checks now (they see the last rendered frame).
}

void Viewer::runStepChecks(const ScriptStep& step) {
    if (!step.screenshot.empty()) takeScreenshot(step.screenshot);
    if (step.expect) checkExpectations(*step.expect);
}

void Viewer::checkExpectations(const nlohmann::json& expect) {
    const FrameStats& s = status_.stats;
    auto fail = [&](const std::string& what) {
        std::fprintf(stderr, "chcrt: view script: expectation failed (step %zu): %s\n", nextStep_ - 1, what.c_str());
        ++failures_;
    };
    for (const auto& [key, value] : expect.items()) {
        if (key == "cappedRays") {
            if (s.cappedRays != value.get<uint64_t>()) fail("cappedRays = " + std::to_string(s.cappedRays));
        } else if (key == "minRaysGenerated") {
            if (s.raysGenerated < value.get<uint64_t>()) fail("raysGenerated = " + std::to_string(s.raysGenerated));
        } else if (key == "tracePasses") {
            for (const auto& [type, passes] : value.items()) {
                const uint64_t actual = s.trace[size_t(parseRayType(type))].passes;
                if (actual != passes.get<uint64_t>()) fail(type + " passes = " + std::to_string(actual));
            }
        } else if (key == "accumulatedFrames") {
            if (display_->accumulatedFrames() != value.get<int>()) {
                fail("accumulatedFrames = " + std::to_string(display_->accumulatedFrames()));
            }
        } else if (key == "imageSize") {
            const auto size = value.get<std::vector<int>>();
            if (size.size() != 2 || size[0] != display_->width() || size[1] != display_->height()) {
                fail("imageSize = " + std::to_string(display_->width()) + "x" + std::to_string(display_->height()));
            }
        } else if (key == "method") {
            if (activeMethod_ != value.get<std::string>()) fail("method = " + activeMethod_);
        } else if (key == "primary") {
            const char* actual = toString(gpu_.renderer->settings().primaryVisibility);
            if (value.get<std::string>() != actual) fail(std::string("primary = ") + actual);
        } else if (key == "viewMode") {
            if (toString(settings_.viewMode) != value.get<std::string>()) {
                fail(std::string("viewMode = ") + toString(settings_.viewMode));
            }
        } else if (key == "playing") {
            if (playing_ != value.get<bool>()) fail(std::string("playing = ") + (playing_ ? "true" : "false"));
        } else if (key == "scene") {
            if (status_.sceneName != value.get<std::string>()) fail("scene = " + status_.sceneName);
        } else if (key == "pathFrame") {
            if (pathFrame_ != value.get<int>()) fail("pathFrame = " + std::to_string(pathFrame_));
        } else if (key == "shaftNodePicked") {
            if (shaftPick_.has_value() != value.get<bool>()) fail(std::string("shaftNodePicked = ") + (shaftPick_ ? "true" : "false"));
        } else if (key == "outOfCore") { // the method traces through the GPU subtree cache
            if ((outOfCore_ != nullptr) != value.get<bool>()) fail(std::string("outOfCore = ") + (outOfCore_ ? "true" : "false"));
        } else if (key == "loadProgress") {
            const double actual = loader_.progress().fraction();
            if (std::abs(actual - value.get<double>()) > 1e-9) fail("loadProgress = " + std::to_string(actual));
        } else {
            throw InputError("script: unknown expectation '" + key + "'");
        }
    }
}

void Viewer::updatePlayback() {
    if (!playing_) return;
    const int count = scene_->path.frameCount();
    if (pathFrame_ >= count) {
        playing_ = false;
        return;
    }
    setCamera(scene_->path.cameraAtFrame(pathFrame_));
    if (++pathFrame_ >= count) playing_ = false; // stops on the last frame
}

void Viewer::renderIfNeeded() {
    Renderer& renderer = *gpu_.renderer;
    int fbWidth = 0, fbHeight = 0;
    glfwGetFramebufferSize(window_, &fbWidth, &fbHeight);
    if (fbWidth < 1 || fbHeight < 1) return; // minimised
    int w = 1, h = 1;
    internalSize(settings_, fbWidth, fbHeight, w, h);
    if (w != display_->width() || h != display_->height()) {
        display_->resize(w, h);
        dirty_ = true;
    }
    if (!sameCamera(camera_, renderedCamera_)) dirty_ = true;
    if (settings_.method != activeMethod_ || settings_.chcrtAlwaysCull != activeAlwaysCull_ ||
        methodParameters(settings_.common) != activeParameters_) {
        applyMethod();
        // While the method's Line Spaces build on the worker the previous tracer stays: its view keeps refining.
        if (!cacheJob_.busy()) dirty_ = true;
    }
    const bool shaded = settings_.viewMode == ViewMode::Shaded;
    const bool refine = shaded && settings_.accumulate && activeMethod_ != kRasterOnlyMethod &&
                        display_->accumulatedFrames() < settings_.maxAccumulatedFrames;
    if (!dirty_ && !refine) return; // the view is complete: only the window is redrawn
    if (dirty_ || !settings_.accumulate) display_->resetAccumulation();

    const auto start = Clock::now();
    renderer.setSettings(toRenderSettings(settings_, w, h, display_->accumulatedFrames()));
    // CHC+RT methods: debug images on only in their view modes and the cost view (instrumented shader variants
    // are slower; a debug image also turns the adaptive fallback off, so `chcrt`'s cost view shows what culling
    // costs), and the frame's CHC+RT counters as the difference of the tracer's running totals.
    ChcrtTracer* chcrt = outOfCore_ ? &outOfCore_->chcrt() : dynamic_cast<ChcrtTracer*>(tracer_.get());
    const bool debugView = isChcrtDebugMode(settings_.viewMode);
    const bool costView = settings_.viewMode == ViewMode::Cost;
    if (chcrt && !outOfCore_) { // out of core: set around the chosen rays' trace only (traceDebugRays)
        const ChcrtDebugImage kind = chcrtDebugImageOf(settings_.viewMode);
        if (chcrt->debugImageKind() != kind) chcrt->setDebugImage(kind);
    }
    if (outOfCore_ && chcrt->debugImageKind() != ChcrtDebugImage::None) {
        // The out-of-core G-buffer's primary rays record their subtrees in the debug image (PrimaryResolve),
        // which no other debug image may occupy while they are traced.
        chcrt->setDebugImage(ChcrtDebugImage::None);
    }
    const ChcrtStats chcrtBefore = chcrt ? chcrt->totalStats() : ChcrtStats{};
    const outofcore::OutOfCoreStats outOfCoreBefore = outOfCore_ ? outOfCore_->snapshot() : outofcore::OutOfCoreStats{};
    FrameStats stats;
    const bool shafts = settings_.viewMode == ViewMode::Shafts;
    const bool residency = settings_.viewMode == ViewMode::Residency;
    std::optional<ResidencyCounts> residencyCounts;
    if (shafts) {
        renderShafts(stats);
        stats.totalMs = millisecondsSince(start);
    } else if (residency) {
        renderResidency(stats);
        if (outOfCore_ && !scene_->sceneInCore) residencyCounts = lastResidency_;
        stats.totalMs = millisecondsSince(start);
    } else if (shaded) {
        stats = renderer.renderFrame(camera_);
        if (settings_.accumulate) display_->accumulate(renderer.targets());
        else display_->showSingleFrame();
    } else {
        renderer.renderGBuffer(camera_, stats);
        if (costView || debugView) traceDebugRays(chcrt, stats);
        stats.totalMs = millisecondsSince(start);
    }
    status_.chcrt.reset();
    if (chcrt) status_.chcrt = chcrtFrameStats(chcrtBefore, chcrt->totalStats());
    status_.outOfCore.reset();
    bool streaming = false;
    if (outOfCore_) {
        ViewerOutOfCoreStatus o;
        o.frame = outofcore::OutOfCoreStats::difference(outOfCore_->snapshot(), outOfCoreBefore);
        streaming = o.frame.cachePostponed > 0; // the upload limit left subtrees for later: render again
        o.gpuCacheMb = double(outOfCore_->options().gpuCacheBytes) / double(1u << 20);
        o.hostCacheMb = double(outOfCore_->options().hostCacheBytes) / double(1u << 20);
        o.fileSubtrees = outOfCore_->file().subtrees().size();
        o.sceneInCore = scene_->sceneInCore;
        o.residency = residencyCounts;
        status_.outOfCore = o;
    }
    if (shafts || residency) {
        // renderShafts / renderResidency have shown their image
    } else if (debugView) {
        const bool ready = chcrt && chcrt->debugTexture() != 0 && chcrt->debugWidth() == w && chcrt->debugHeight() == h;
        display_->showImage(ready ? colorizeChcrtDebugImage(chcrt->debugImageKind(), chcrt->readDebugImage(), w, h)
                                  : std::vector<float>(size_t(w) * h * 3, 0.0f));
    } else {
        // CHC+RT's cost view: its cost debug image on the pure tracer's heat map and scale.
        const bool cullingCost = costView && chcrt && chcrt->debugImageKind() == ChcrtDebugImage::Cost &&
                                 chcrt->debugTexture() != 0 && chcrt->debugWidth() == w && chcrt->debugHeight() == h;
        if (cullingCost) glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT); // the image stores, read as a texture
        display_->visualize(renderer.targets(), settings_, scene_->scene.bounds(), renderer.targets().hits[0],
                            cullingCost ? chcrt->debugTexture() : 0);
    }
    checkGlErrors("viewer frame");
    dirty_ = streaming;
    renderedCamera_ = camera_;
    status_.stats = stats;
    ++renderedFrames_;
    if (recording_) recordKeyframe();
    nlohmann::json entry = statsToJson(stats);
    entry["frame"] = renderedFrames_ - 1;
    entry["method"] = activeMethod_;
    entry["view_mode"] = toString(settings_.viewMode);
    entry["primary"] = toString(renderer.settings().primaryVisibility);
    if (status_.chcrt) {
        entry["chcrt"] = chcrtStatsToJson(*status_.chcrt);
        entry["chcrt"]["always_cull"] = activeAlwaysCull_;
    }
    if (outOfCore_) {
        entry["outofcore"] = outOfCoreStatsJson(status_.outOfCore->frame, 1.0, *outOfCore_);
        entry["outofcore"]["scene_in_core"] = scene_->sceneInCore;
    }
    if (residencyCounts) {
        const ResidencyCounts& c = *residencyCounts;
        entry["residency"] = {{"hit_pixels", c.hitPixels}, {"resident_pixels", c.residentPixels},
                              {"uploaded_pixels", c.uploadedPixels}, {"visible_subtrees", c.visibleSubtrees}};
    }
    if (shafts && shaftPick_) {
        const ShaftPick& p = *shaftPick_;
        entry["shafts"] = {{"pixel", {p.pixelX, p.pixelY}}, {"space", p.space},     {"spaces", p.spaceCount},
                           {"bvh_node", p.bvhNode},         {"triangles", p.subtreeTriangles},
                           {"n", p.n}, {"depth", p.depth},  {"t", p.triangleThreshold},
                           {"shafts", p.shafts},            {"filled", p.filled}, {"fill_rate", p.fillRate()},
                           {"build_ms", p.buildMs}};
    }
    entry["width"] = w;
    entry["height"] = h;
    entry["accumulated_frames"] = display_->accumulatedFrames();
    entry["frame_ms"] = millisecondsSince(start); // render + visualisation (loop_ms adds panel and swap)
    frameLog_.push_back(std::move(entry));
}

void Viewer::drawWindow() {
    int fbWidth = 0, fbHeight = 0;
    glfwGetFramebufferSize(window_, &fbWidth, &fbHeight);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fbWidth, fbHeight);
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    if (scene_ && display_->width() > 0) display_->blitToWindow(fbWidth, fbHeight);

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    status_.loading = loader_.busy();
    status_.loadingScene = loader_.scene();
    status_.loadingSeconds = loader_.elapsedSeconds();
    if (!loader_.busy() && cacheJob_.busy()) { // a method's Line Space / N-tree build, shown like a loading step
        const LoadProgressSnapshot p = cacheJob_.progress();
        status_.loading = true;
        status_.loadingScene = "Line Spaces for " + settings_.method;
        status_.loadingSeconds = cacheJob_.elapsedSeconds();
        status_.loadingStep = p.label;
        status_.loadingStepNumber = p.step;
        status_.loadingFraction = p.fraction();
    }
    if (showPanel_ || !scene_) {
        status_.frameHistoryMs.assign(history_.begin(), history_.end());
        status_.accumulatedFrames = display_->accumulatedFrames();
        status_.internalWidth = display_->width();
        status_.internalHeight = display_->height();
        status_.camera = camera_;
        status_.speed = walk_.speed();
        status_.pathFrame = pathFrame_;
        status_.pathFrames = scene_ ? scene_->path.frameCount() : 1;
        status_.playing = playing_;
        status_.recording = recording_;
        status_.recordedKeyframes = recorded_.keyframes.size();
        const ViewerActions actions = panel_->draw(settings_, status_);
        if (!scripted_ && scene_) applyPanelActions(actions);
    }
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(window_);
}

void Viewer::applyPanelActions(const ViewerActions& a) {
    if (a.settingsChanged) dirty_ = true;
    if (a.reset) handleKey(GLFW_KEY_R);
    if (a.frameScene) handleKey(GLFW_KEY_F);
    if (a.togglePlay) playing_ = !playing_;
    if (a.pathFrame) {
        pathFrame_ = *a.pathFrame;
        playing_ = false;
        setCamera(scene_->path.cameraAtFrame(pathFrame_));
    }
    if (a.toggleRecord) handleKey(GLFW_KEY_F9);
    if (a.screenshot) handleKey(GLFW_KEY_F12);
    if (a.copyCommandLine) printCommandLine();
    if (!a.loadScene.empty() && !loader_.busy()) startLoading(a.loadScene);
}

void Viewer::takeScreenshot(const std::string& file) {
    writeImage(file, display_->readImage());
    notice("wrote " + file);
}

void Viewer::printCommandLine() {
    const std::string render = renderCommandLine(settings_, camera_, display_->width(), display_->height());
    const std::string bench = benchCommandLine(settings_, camera_, display_->width(), display_->height());
    std::printf("%s\n%s\n", render.c_str(), bench.c_str());
    std::fflush(stdout);
    glfwSetClipboardString(window_, render.c_str());
    notice("copied: " + render);
}

void Viewer::startRecording() {
    recording_ = true;
    recorded_ = CameraPath{};
    recorded_.name = "recorded";
    recorded_.fps = 30.0;
    recorded_.fovYDegrees = camera_.fovYDegrees;
    recordStart_ = Clock::now();
    recordedFrameStart_ = scriptFrame_;
    recordKeyframe();
    notice("recording");
}

void Viewer::recordKeyframe() {
    // Scripted sessions advance 1/30 s per frame; interactive ones record wall time.
    const double t = scripted_ ? (scriptFrame_ - recordedFrameStart_) * kScriptSecondsPerFrame
                               : std::chrono::duration<double>(Clock::now() - recordStart_).count();
    if (!recorded_.keyframes.empty()) {
        const CameraKeyframe& last = recorded_.keyframes.back();
        if (t <= last.t || (last.eye == camera_.eye && last.target == camera_.target)) return;
    }
    recorded_.keyframes.push_back(CameraKeyframe{t, camera_.eye, camera_.target, camera_.up});
}

void Viewer::stopRecording(const std::string& file) {
    if (!recording_) throw InputError("recordStop without a recording (start one with recordStart or F9)");
    recording_ = false;
    saveCameraPath(recorded_, file);
    notice("saved " + std::to_string(recorded_.keyframes.size()) + " keyframes to " + file);
}

void Viewer::notice(const std::string& text) {
    status_.message = text;
    if (scripted_) std::printf("view: %s\n", text.c_str());
}

void Viewer::writeStatsJson() const {
    if (options_.common.statsJson.empty()) return;
    writeJsonFile(options_.common.statsJson, nlohmann::json{{"frames", frameLog_}, {"loading", loadLog_}});
}

void Viewer::sampleLoadProgress() {
    const LoadProgressSnapshot p = loader_.progress();
    status_.loadingStep = p.label;
    status_.loadingStepNumber = p.step;
    status_.loadingFraction = p.fraction();
    nlohmann::json sample = {{"scene", loader_.scene()}, {"step", p.step},   {"label", p.label},
                             {"done", p.done},           {"total", p.total}, {"fraction", p.fraction()},
                             {"complete", p.complete}};
    if (!loadLog_.empty()) { // one sample per change
        nlohmann::json last = loadLog_.back();
        last.erase("seconds");
        if (last == sample) return;
    }
    sample["seconds"] = loader_.elapsedSeconds();
    loadLog_.push_back(std::move(sample));
}

// The cost and CHC+RT debug views: the chosen ray set traced after the G-buffer (the debug image shows only
// it, not the G-buffer's traced primary rays). Out of core the tracer records the primary rays' subtrees in
// the debug image for the G-buffer resolve: the chosen image (for `cost`, CHC+RT's cost image) is selected here
// and the recording paused for this one trace (each image's shader variants are compiled once and kept).
void Viewer::traceDebugRays(ChcrtTracer* chcrt, FrameStats& stats) {
    Renderer& renderer = *gpu_.renderer;
    const ChcrtDebugImage kind = chcrtDebugImageOf(settings_.viewMode);
    if (chcrt && kind != ChcrtDebugImage::None) {
        if (outOfCore_) chcrt->setDebugImage(kind);
        chcrt->clearDebugImage();
    }
    if (outOfCore_) outOfCore_->setRecordPrimarySubtrees(false);
    try {
        renderer.generateRayPass(camera_, settings_.costRayType, 0, stats);
        renderer.traceRayPass(camera_, settings_.costRayType, 0, stats);
    } catch (...) {
        if (outOfCore_) outOfCore_->setRecordPrimarySubtrees(true);
        throw;
    }
    if (outOfCore_) outOfCore_->setRecordPrimarySubtrees(true);
}

// One shaded frame shown without refinement: the base image of the views drawn over it (residency, shafts).
void Viewer::renderShadedFrame(FrameStats& stats) {
    Renderer& renderer = *gpu_.renderer;
    stats = renderer.renderFrame(camera_);
    display_->showSingleFrame();
    ViewerSettings shadedSettings = settings_;
    shadedSettings.viewMode = ViewMode::Shaded;
    display_->visualize(renderer.targets(), shadedSettings, scene_->scene.bounds(), renderer.targets().hits[0]);
}

// The displayed image as RGB in [0, 1], for the views that colour it on the CPU.
std::vector<float> Viewer::shownRgb() const {
    const ImageRgba32f image = display_->readImage();
    const size_t pixels = size_t(image.width) * size_t(image.height);
    std::vector<float> rgb(pixels * 3);
    for (size_t i = 0; i < pixels; ++i) {
        for (int k = 0; k < 3; ++k) rgb[i * 3 + size_t(k)] = std::clamp(image.pixels[i * 4 + size_t(k)], 0.0f, 1.0f);
    }
    return rgb;
}

// Subtrees resident in the GPU cache now (by file subtree index).
std::vector<uint8_t> Viewer::residentSubtrees() const {
    std::vector<uint8_t> resident(outOfCore_->file().subtrees().size(), 0);
    const outofcore::GpuSubtreeCache& cache = outOfCore_->cache();
    for (uint32_t slot = 0; slot < cache.slotCount(); ++slot) {
        const uint32_t subtree = cache.slotSubtree(slot);
        if (subtree < resident.size()) resident[subtree] = 1;
    }
    return resident;
}

// The residency view (out of core): the shaded frame (one frame, no refinement) tinted by where each pixel's
// primary hit came from: a subtree resident in the GPU cache before the frame, or one uploaded during it.
void Viewer::renderResidency(FrameStats& stats) {
    const int w = display_->width(), h = display_->height();
    const bool available = outOfCore_ && !scene_->sceneInCore;
    lastResidency_.reset();
    const std::vector<uint8_t> before = available ? residentSubtrees() : std::vector<uint8_t>{};
    renderShadedFrame(stats);
    if (!available) { // the shaded frame, with a note
        const std::string text = "the residency view needs --out-of-core with a prepared scene not loaded in core "
                                 "(--load-in-core off)";
        if (status_.message != text) notice(text);
        return;
    }
    std::vector<float> rgb = shownRgb();
    lastResidency_ = colourResidency(outOfCore_->primaryResolve().lastPixelSubtrees(), before, w, h, rgb);
    display_->showImage(rgb);
}

// (Re)computes the picked Line Space node: on a new pick (at the current camera), or when N/D/T change (the same
// pixel of the camera it was picked with). Without any pick the centre pixel is picked.
void Viewer::updateShaftPick(int w, int h) {
    const ls::LineSpaceParams c = shownParameters(settings_, status_.triangles).lineSpace; // the method's N/D/T
    if (!scene_->sceneInCore) { // the node's Line Space is built from the in-core BVH
        shaftPick_.reset();
        status_.shaftInfo = {"the shafts view needs the scene in core (out of core only subtrees are on the GPU)"};
        if (status_.message != status_.shaftInfo.back()) notice(status_.shaftInfo.back());
        return;
    }
    const std::string parameters =
        std::to_string(c.n) + "/" + std::to_string(c.depth) + "/" + std::to_string(c.triangleThreshold);
    if (pickJob_.busy()) {
        if (!pickJob_.finished() && !scripted_) return; // the previous pick stays shown meanwhile
        finishShaftPick(); // scripts wait for it in place
    }
    if (!pendingPick_ && !shaftPick_ && pickParameters_.empty()) pendingPick_ = std::make_pair(w / 2, h / 2);
    if (pendingPick_) {
        pickCamera_ = camera_;
        pickWidth_ = w;
        pickHeight_ = h;
        pickPixel_ = *pendingPick_;
    } else if (parameters == pickParameters_) {
        return;
    }
    pendingPick_.reset();
    pickParameters_ = parameters;
    pickResult_ = std::make_shared<std::optional<ShaftPick>>();
    pickJob_.start("Line Space of the picked node",
                   [result = pickResult_, &bvh = scene_->bvh, camera = pickCamera_, w = pickWidth_, h = pickHeight_,
                    pixel = pickPixel_, n = c.n, depth = c.depth, t = c.triangleThreshold](Progress& progress) {
                       progress.begin("Line Space of the picked node", 0);
                       *result = pickLineSpaceNode(bvh, camera, w, h, pixel.first, pixel.second, n, depth, t);
                       progress.end();
                   });
    status_.shaftInfo = {"pixel " + std::to_string(pickPixel_.first) + ", " + std::to_string(pickPixel_.second) +
                         ": building the Line Space of its node ..."};
    if (scripted_) finishShaftPick();
}

// Takes the finished pick job's node and describes it in the panel.
void Viewer::finishShaftPick() {
    try {
        pickJob_.take();
    } catch (const InputError& error) {
        shaftPick_.reset();
        status_.shaftInfo = {std::string("shafts: ") + error.what()};
        notice(status_.shaftInfo.back());
        return;
    }
    shaftPick_ = std::move(*pickResult_);
    const std::pair<int, int> pixel = pickPixel_;
    status_.shaftInfo.clear();
    if (!shaftPick_) {
        status_.shaftInfo.push_back("pixel " + std::to_string(pixel.first) + ", " + std::to_string(pixel.second) +
                                    ": no hit (click on geometry)");
        notice(status_.shaftInfo.back());
        return;
    }
    const ShaftPick& p = *shaftPick_;
    char line[200];
    std::snprintf(line, sizeof(line), "node %u of %u (BVH node %u, %u triangles), N=%u D=%u T=%u", p.space,
                  p.spaceCount, p.bvhNode, p.subtreeTriangles, p.n, p.depth, p.triangleThreshold);
    status_.shaftInfo.push_back(line);
    std::snprintf(line, sizeof(line), "%llu shafts, %llu filled: fill rate %.1f %%", (unsigned long long)p.shafts,
                  (unsigned long long)p.filled, 100.0 * p.fillRate());
    status_.shaftInfo.push_back(line);
    std::snprintf(line, sizeof(line), "picked pixel %d, %d (triangle %u); built in %.0f ms (worker thread)", p.pixelX,
                  p.pixelY, p.triangleId, p.buildMs);
    status_.shaftInfo.push_back(line);
    std::snprintf(line, sizeof(line), "shafts: node %u, %llu shafts, fill rate %.1f %%", p.space,
                  (unsigned long long)p.shafts, 100.0 * p.fillRate());
    notice(line);
}

void Viewer::renderShafts(FrameStats& stats) {
    const int w = display_->width(), h = display_->height();
    renderShadedFrame(stats);
    updateShaftPick(w, h);
    std::vector<float> rgb = shownRgb();
    if (shaftPick_) drawShafts(*shaftPick_, camera_, w, h, rgb);
    display_->showImage(rgb);
}

} // namespace

int runViewer(const ViewOptions& options) {
    Viewer viewer(options);
    return viewer.run();
}

int runView(const ViewOptions& options, const std::vector<std::string>& /*arguments*/) {
    return runViewer(options);
}

} // namespace chcrt::app
