#include "app/viewer/viewer_app.h"

#include "app/methods.h"
#include "app/report.h"
#include "app/resource_log.h"
#include "app/viewer/residency_view.h"
#include "app/viewer/shaft_picker.h"
#include "app/viewer/view_display.h"
#include "app/viewer/view_frames.h"
#include "app/viewer/viewer_input.h"
#include "app/viewer/viewer_method.h"
#include "app/viewer/viewer_recording.h"
#include "app/viewer/viewer_script.h"
#include "app/viewer/viewer_session.h"
#include "app/viewer/viewer_stats.h"
#include "app/viewer/viewer_ui.h"
#include "app/viewer/viewer_window.h"
#include "app/viewer/walk_controller.h"
#include "culling/chcrt_tracer.h"
#include "culling/outofcore/out_of_core_tracer.h"
#include "culling/outofcore/primary_resolve.h"
#include "renderer/core/error.h"
#include "renderer/core/statistics.h"
#include "renderer/core/timing.h"
#include "renderer/gl/gl.h"
#include "renderer/outofcore/chs_file.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <cstdio>

namespace chcrt::app {
namespace {

using Clock = std::chrono::steady_clock;


// The window's back buffer as drawn (panel included), rows top to bottom.
ImageRgba32f readWindow(int width, int height) {
    std::vector<uint8_t> bytes(size_t(width) * size_t(height) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
    ImageRgba32f image;
    image.width = width;
    image.height = height;
    image.pixels.resize(bytes.size());
    for (int y = 0; y < height; ++y) {
        const uint8_t* row = bytes.data() + size_t(height - 1 - y) * size_t(width) * 4;
        for (size_t i = 0; i < size_t(width) * 4; ++i) {
            image.pixels[size_t(y) * size_t(width) * 4 + i] = i % 4 == 3 ? 1.0f : float(row[i]) / 255.0f;
        }
    }
    return image;
}

bool sameCamera(const Camera& a, const Camera& b) {
    return a.eye == b.eye && a.target == b.target && a.up == b.up && a.fovYDegrees == b.fovYDegrees;
}


// The viewer: its window and the loop that loads scenes, takes input (or runs a script), renders the current view
// mode and draws the panel. What it coordinates lives in the classes it holds: the method's tracer
// (MethodSwitcher), the window's input (WindowInput), the script (ScriptRunner), the shafts view's pick
// (ShaftPicker), walkthrough recording (PathRecorder) and the statistics (ViewerLog).
class Viewer {
public:
    explicit Viewer(const ViewOptions& options);
    ~Viewer();
    int run();

private:
    bool scripted() const { return script_.has_value(); }
    void openWindow();
    void startLoading(const std::string& scene);
    SceneLoader::GpuUpload workerUpload() const;
    void finishLoading();
    void installScene(std::unique_ptr<SceneSession> loaded, std::unique_ptr<SceneGpu> uploaded);
    void sampleLoadProgress();

    void handleInteractiveInput(double seconds);
    void handleKey(int key);
    void handleKeyOrThrow(int key);
    bool advanceScript(); // false when the script has ended
    void runStepActions(const ScriptStep& step);
    void runStepChecks(const ScriptStep& step);
    ScriptObservation observe() const;
    void updatePlayback();

    void renderIfNeeded();
    void renderFrame(int w, int h);
    void frameFailed(const std::string& error);
    void prepareDebugImage(ChcrtTracer* chcrt);
    void renderView(ChcrtTracer* chcrt, Clock::time_point start, FrameStats& stats,
                    std::optional<ResidencyCounts>& residency, std::optional<LodCounts>& lod);
    void renderShafts(FrameStats& stats);
    // The residency and lod views (residency_view.h): the shaded frame tinted per pixel by what `colour` says of its
    // primary hit's subtree; the shaded frame with a note where there is no out-of-core scene.
    void renderWorkingSetView(FrameStats& stats,
                              const std::function<void(outofcore::OutOfCoreTracer&, std::vector<float>&)>& colour);

    void drawWindow();
    void updatePanelStatus();
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
    void notice(const std::string& text);
    // A failure the session survives (a scene that does not load, an unwritable screenshot): in the panel, and on
    // stderr, where errors go, not on stdout with the notices.
    void reportError(const std::string& text);
    void writeSummary();

    ViewOptions options_;
    ViewerSettings settings_;
    GpuSession gpu_; // the window's context: destroyed last
    GLFWwindow* window_ = nullptr;
    GLFWwindow* uploadWindow_ = nullptr; // shares window_'s objects; scene uploads on the loading worker
    std::unique_ptr<WindowInput> input_;
    std::unique_ptr<SceneSession> scene_;
    std::unique_ptr<ViewDisplay> display_;
    std::unique_ptr<ViewerPanel> panel_;
    SceneLoader loader_;
    // After scene_: their workers read the scene's BVH, so they are destroyed (joined) first.
    MethodSwitcher methods_;
    ShaftPicker shafts_;
    WalkController walk_;
    Camera camera_, renderedCamera_;
    bool dirty_ = true; // the view must be rendered again from scratch
    bool showPanel_ = true;
    bool playing_ = false;
    int pathFrame_ = 0;
    PathRecorder recorder_;
    int screenshotCount_ = 0;
    std::optional<ScriptRunner> script_;
    ViewerStatus status_;
    // The last frame failed on its input (an out-of-core read): no new attempt until the view changes (dirty_).
    bool frameFailed_ = false;
    static constexpr double kWaitingRedrawsPerSecond = 30.0;
    int loadRedraws_ = 0; // window redraws while the current load ran (the "loaded" line)
    std::string windowScreenshot_; // a script's window screenshot, taken by the next drawWindow
    ViewerLog log_;
    ResourceLog resourceLog_; // --resource-log
};

Viewer::Viewer(const ViewOptions& options)
    : options_(options), methods_([this](const std::string& text) { notice(text); }, !options.script.empty()),
      shafts_([this](const std::string& text, bool onlyIfNew) {
          if (!onlyIfNew || status_.message != text) notice(text);
      }, !options.script.empty()),
      log_(!options.common.statsJson.empty(), !options.script.empty()) {
    settings_.common = options.common;
    settings_.renderScale = options.renderScale;
    settings_.accumulate = !options.noAccumulate;
    applySettings(settings_, {{"method", options.method}, {"viewMode", options.viewMode}}); // validates all
    if (options.common.outOfCoreScene.enabled) {
        if (!outofcore::isPreparedScenePath(options.common.scene)) {
            throw InputError("--out-of-core needs a prepared scene (--scene file.chs; see chcrt prepare)");
        }
        const MethodInfo* method = viewerMethod(settings_);
        if (!method || !method->outOfCoreForm) {
            // As `chcrt render --out-of-core` (app/methods.cpp); the panel refuses such methods with a message.
            throw InputError("--out-of-core: method " + options.method + " has no out-of-core form; use --method "
                             "chcrt, chcrt-noadapt or chcrt-aggressive");
        }
    }
    showPanel_ = !options.hidePanel;
    playing_ = options.play;
    if (!options.script.empty()) {
        script_.emplace(loadViewerScript(options.script));
        log_.reserveTimes(script_->totalFrames());
    }
    if (!options.resourceLog.empty()) resourceLog_ = ResourceLog(options.resourceLog, options.resourceEvery);
    openWindow();
    // Out of core the interactive viewer streams a cold cache over frames (at most 16 subtree uploads per trace;
    // incomplete frames are re-rendered until complete); scripts get complete, exact frames unless they ask.
    CommonOptions& c = settings_.common;
    if (!c.isGiven("--uploads-per-trace")) c.outOfCore.maxUploadsPerTrace = scripted() ? 0 : 16;
    if (c.lineSpaceTracing.cacheDirectory.empty() && !c.outOfCoreScene.enabled) {
        c.lineSpaceTracing.cacheDirectory = methods_.usePrivateCache().string();
    }
    loader_.start(c, workerUpload());
}

void Viewer::openWindow() {
    auto context = std::make_unique<GlfwWindowContext>(options_.common.render.width, options_.common.render.height,
                                                       options_.common.glDebug);
    window_ = context->window();
    uploadWindow_ = context->uploadWindow();
    gpu_.context = std::move(context);
    input_ = std::make_unique<WindowInput>(window_); // before ImGui's backend, which chains to its callbacks
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini in the working directory
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    display_ = std::make_unique<ViewDisplay>();
    panel_ = std::make_unique<ViewerPanel>(options_.common.scene);
}

Viewer::~Viewer() {
    methods_.releaseTracer();
    methods_.dropPremade();
    display_.reset();
    gpu_.renderer.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    // gpu_.context (the window) goes last, with the members.
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
    const std::string key = MethodSwitcher::tracerKey(settings_);
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
        if (outOfCore && method != kRasterOnlyMethod && findGpuMethod(method).outOfCoreForm) {
            uploaded.tracer = makeTracer(method, session, alwaysCull);
            uploaded.tracerKey = key;
        }
        return uploaded;
    };
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
        if (scripted()) {
            if (!advanceScript()) break;
        } else if (scene_) {
            handleInteractiveInput(seconds);
        }
        const int renderedBefore = log_.renderedFrames();
        if (scene_ && gpu_.renderer && !(scripted() && loader_.busy())) { // scripts wait for a loading scene
            updatePlayback();
            renderIfNeeded();
        }
        drawWindow();
        // The whole iteration of a rendered frame: input, render, display, panel and buffer swap. Iterations that
        // render nothing (a complete view, a load) are not frames: the panel's fps is of the last rendered frame.
        const double loopMs = millisecondsSince(start);
        const bool rendered = log_.renderedFrames() != renderedBefore;
        if (rendered) {
            status_.frameMs = loopMs;
            log_.setLoopMs(loopMs);
            if (uint64_t(log_.renderedFrames()) % kReleaseFreedMemoryEvery == 0) releaseFreedMemory();
            resourceLog_.frameDone(uint64_t(log_.renderedFrames() - 1), false,
                                   {{"method", methods_.activeMethod()}, {"scene", status_.sceneName}});
        }
        // The graph shows rendered frames; the iteration that uploaded a scene would flatten it.
        if (rendered && !loaded) log_.addToHistory(float(loopMs));
        if (shafts_.takeFinished()) dirty_ = true; // the shafts view's new pick: show it
        const bool background = loader_.busy() || methods_.cacheJob().busy() || shafts_.busy();
        if (loader_.busy()) ++loadRedraws_;
        idle = !scripted() && !rendered && !background && !playing_ && !input_->looking();
        // While a worker loads a scene or builds structures and the loop renders nothing, the window (spinner,
        // progress) is redrawn at most kWaitingRedrawsPerSecond times a second. Unthrottled it was redrawn ~270 times
        // a second, and on a machine of few cores that drawing (llvmpipe) took the CPU the worker needed: docs/
        // benchmarks.md, "Viewer scene loading".
        if (!rendered && background) {
            const double left = 1.0 / kWaitingRedrawsPerSecond - millisecondsSince(start) / 1000.0;
            if (left > 0) glfwWaitEventsTimeout(left);
        }
    }
    writeSummary();
    return script_ && script_->failures() ? kExitCheckFailed : kExitOk;
}

// --stats-json, and a scripted session's one-line summary.
void Viewer::writeSummary() {
    if (!options_.common.statsJson.empty()) log_.write(options_.common.statsJson);
    if (log_.renderedFrames() > 0) resourceLog_.frameDone(uint64_t(log_.renderedFrames() - 1), true);
    if (!scripted()) return;
    std::printf("view: %d frames rendered%s, median frame %.2f ms (renderer %.2f ms)%s\n", log_.renderedFrames(),
                log_.failedFrames() ? (", " + std::to_string(log_.failedFrames()) + " failed").c_str() : "",
                log_.medianLoopMs(), log_.medianRendererMs(), script_->failures() ? ", expectations FAILED" : "");
}

void Viewer::finishLoading() {
    std::unique_ptr<SceneSession> loaded;
    try {
        loaded = loader_.take();
    } catch (const std::runtime_error& e) { // InputError, or GlError from the GPU upload
        if (!scene_) throw; // nothing to show: a bad --scene is a usage error
        reportError(std::string("cannot load the scene: ") + e.what());
        return;
    }
    const double loadSeconds = loader_.elapsedSeconds();
    SceneLoader::Uploaded uploaded = loader_.takeUploaded();
    methods_.offerPremade(std::move(uploaded.tracer), uploaded.tracerKey);
    const bool uploadedByWorker = uploaded.scene != nullptr;
    sampleLoadProgress(); // the worker has finished: complete, 100 %
    const auto uploadStart = Clock::now();
    installScene(std::move(loaded), std::move(uploaded.scene));
    char timings[200]; // the numbers only: the scene's name, of any length, is appended whole
    std::snprintf(timings, sizeof(timings), ": %llu triangles, %.2f s loading + BVH%s (worker thread, %d window "
                  "redraws meanwhile), %.2f s renderer set-up (main thread)",
                  static_cast<unsigned long long>(status_.triangles), loadSeconds, uploadedByWorker ? " + GPU upload" : "",
                  loadRedraws_, millisecondsSince(uploadStart) / 1000.0);
    loadRedraws_ = 0;
    notice("loaded " + loader_.scene() + timings);
}

// The scene is on the GPU already (uploaded by the worker, unless there is no shared context); the renderer's and
// the method's programs are made here, on the drawing context.
void Viewer::installScene(std::unique_ptr<SceneSession> loaded, std::unique_ptr<SceneGpu> uploaded) {
    const bool first = !scene_;
    shafts_.sceneChanged();  // its worker reads the previous scene's BVH
    methods_.sceneChanged(); // likewise; frees the tracer before the renderer
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
    setPreferredTraceStage(options_.common.shaderStage); // --shader-stage
    gpu_.renderer = std::make_unique<Renderer>(scene_->scene, scene_->bvh, scene_->light,
                                               toRenderSettings(settings_, w, h, 0), std::move(uploaded));
    methods_.apply(settings_, *scene_, *gpu_.renderer);
    methods_.dropPremade(); // not taken (the method changed during the load): freed here, with its context current
    pathFrame_ = 0;
    resetCamera();
    if (first && !options_.common.frames.empty()) { // --frames: where the path starts
        pathFrame_ = selectFrames(options_.common, scene_->path, "0").front();
        setCamera(scene_->path.cameraAtFrame(pathFrame_));
    }
    walk_ = WalkController(camera_, scene_->scene.bounds());
    try {
        gpu_.renderer->warmUp(camera_);
    } catch (const InputError& e) { // an out-of-core read failed: as a failed frame, and the first frame tries again
        frameFailed(e.what());
    }
    status_.sceneName = settings_.common.scene = loader_.scene();
    status_.triangles = sceneTriangles(*scene_);
    dirty_ = true;
}

void Viewer::sampleLoadProgress() {
    const LoadProgressSnapshot p = loader_.progress();
    status_.loadingStep = p.label;
    status_.loadingStepNumber = p.step;
    status_.loadingFraction = p.fraction();
    log_.sampleLoad(p, loader_.scene(), loader_.elapsedSeconds());
}

void Viewer::handleInteractiveInput(double seconds) {
    const ImGuiIO& io = ImGui::GetIO();
    const InteractiveInput input = input_->poll(io.WantCaptureKeyboard, io.WantCaptureMouse);
    for (int key : input.keys) handleKey(key);
    // Left click in the view: pick the pixel for the shafts view (window coordinates → internal image).
    if (input.click && display_->width() > 0) {
        const int px = std::clamp(int(input.click->first * display_->width()), 0, display_->width() - 1);
        const int py = std::clamp(int(input.click->second * display_->height()), 0, display_->height() - 1);
        shafts_.requestPick(px, py);
        dirty_ = true;
    }
    if (input.walk.any()) {
        playing_ = false; // the user takes over from the path
        if (walk_.update(input.walk, std::min(seconds, 0.25))) camera_ = walk_.camera();
    }
}

void Viewer::handleKey(int key) {
    try {
        handleKeyOrThrow(key);
    } catch (const InputError& e) {
        if (scripted()) throw; // a script's error ends it (exit 2)
        reportError(e.what()); // an unwritable screenshot or path must not end an interactive session
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
        if (recorder_.recording()) stopRecording(options_.recordFile);
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
    input_->clear(); // scripted sessions ignore real input
    if (loader_.busy() || !scene_) return true; // wait for the scene
    const ScriptRunner::Advance advance = script_->advance([this](const ScriptStep& s) { runStepActions(s); },
                                                           [this](const ScriptStep& s) { runStepChecks(s); },
                                                           [this] { return loader_.busy(); });
    if (advance == ScriptRunner::Advance::Ended) return false;
    if (advance == ScriptRunner::Advance::Waiting) return true;
    const ScriptStep& step = *script_->current();
    if (step.held.any() && walk_.update(step.held, PathRecorder::kScriptSecondsPerFrame)) {
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
        shafts_.requestPick(step.pick->first, step.pick->second);
        dirty_ = true;
    }
    if (step.scrollSteps != 0) walk_.update(WalkInput{.scrollSteps = step.scrollSteps}, 0.0);
    if (step.action == "reset") handleKey(GLFW_KEY_R);
    else if (step.action == "frameScene") handleKey(GLFW_KEY_F);
    else if (step.action == "copyCommandLine") printCommandLine();
    else if (step.action == "recordStart") startRecording();
    if (!step.recordStop.empty()) stopRecording(step.recordStop);
    for (const std::string& key : step.presses) handleKey(keyCodeFor(key));
    // A step with no frames has its checks now (they see the last rendered frame).
}

void Viewer::runStepChecks(const ScriptStep& step) {
    if (!step.screenshot.empty()) takeScreenshot(step.screenshot);
    if (!step.windowScreenshot.empty()) windowScreenshot_ = step.windowScreenshot; // drawWindow takes it
    if (!step.expect) return;
    for (const std::string& what : unmetExpectations(*step.expect, observe())) {
        std::fprintf(stderr, "chcrt: view script: expectation failed (step %zu): %s\n", script_->currentIndex(),
                     what.c_str());
        script_->fail();
    }
}

ScriptObservation Viewer::observe() const {
    ScriptObservation seen;
    const FrameStats& s = status_.stats;
    seen.cappedRays = s.cappedRays;
    seen.raysGenerated = s.raysGenerated;
    for (size_t t = 0; t < s.trace.size(); ++t) seen.tracePasses[t] = s.trace[t].passes;
    seen.accumulatedFrames = display_->accumulatedFrames();
    seen.width = display_->width();
    seen.height = display_->height();
    seen.method = methods_.activeMethod();
    seen.primary = toString(gpu_.renderer->settings().primaryVisibility);
    seen.viewMode = toString(settings_.viewMode);
    seen.playing = playing_;
    seen.scene = status_.sceneName;
    seen.pathFrame = pathFrame_;
    seen.shaftNodePicked = shafts_.pick().has_value();
    seen.outOfCore = methods_.outOfCore() != nullptr;
    seen.loadProgress = loader_.progress().fraction();
    seen.failedFrames = log_.failedFrames();
    seen.frameFailed = frameFailed_;
    return seen;
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
    if (methods_.changed(settings_)) {
        methods_.apply(settings_, *scene_, *gpu_.renderer);
        // While the method's Line Spaces build on the worker the previous tracer stays: its view keeps refining.
        if (!methods_.cacheJob().busy()) dirty_ = true;
    }
    const bool shaded = settings_.viewMode == ViewMode::Shaded;
    const bool refine = shaded && settings_.accumulate && methods_.activeMethod() != kRasterOnlyMethod &&
                        display_->accumulatedFrames() < settings_.maxAccumulatedFrames;
    // The view is complete, or its last frame failed and nothing changed since: only the window is redrawn.
    if (!dirty_ && (!refine || frameFailed_)) return;
    if (dirty_ || !settings_.accumulate) display_->resetAccumulation();
    try {
        renderFrame(w, h);
    } catch (const InputError& e) {
        frameFailed(e.what());
        return;
    }
    frameFailed_ = false;
    status_.frameError.clear();
}

// A frame that failed on its input (a prepared scene's subtree that cannot be read: an I/O error, a file truncated
// or overwritten while it is rendered; the message names the file and subtree): the panel and stderr say so, the
// window keeps the last complete image, nothing of the frame is logged or can be saved as a screenshot, and the
// session goes on. The view is tried again when it changes (camera, settings, another scene).
void Viewer::frameFailed(const std::string& error) {
    frameFailed_ = true;
    dirty_ = false;
    renderedCamera_ = camera_;
    status_.frameError = error;
    log_.addFailure(error);
    reportError("frame not rendered: " + error);
}

// Renders the view mode, updates the frame's statistics and logs the frame.
void Viewer::renderFrame(int w, int h) {
    const auto start = Clock::now();
    Renderer& renderer = *gpu_.renderer;
    renderer.setSettings(toRenderSettings(settings_, w, h, display_->accumulatedFrames()));
    ChcrtTracer* chcrt = methods_.chcrt();
    outofcore::OutOfCoreTracer* outOfCore = methods_.outOfCore();
    prepareDebugImage(chcrt);
    const ChcrtStats chcrtBefore = chcrt ? chcrt->totalStats() : ChcrtStats{};
    const outofcore::OutOfCoreStats outOfCoreBefore = outOfCore ? outOfCore->snapshot() : outofcore::OutOfCoreStats{};
    FrameStats stats;
    std::optional<ResidencyCounts> residency;
    std::optional<LodCounts> lod;
    renderView(chcrt, start, stats, residency, lod);
    if (outOfCore) { // read ahead (--prefetch-frames): the next frames of a playing path, else the fronts only
        std::vector<Camera> next;
        const size_t ahead = playing_ ? outOfCore->options().prefetchFrames : 0;
        for (int f = pathFrame_; f < scene_->path.frameCount() && next.size() < ahead; ++f) {
            next.push_back(scene_->path.cameraAtFrame(f));
        }
        outOfCore->prefetchAfterFrame(camera_, next, w, h);
    }
    status_.chcrt.reset();
    if (chcrt) status_.chcrt = chcrtFrameStats(chcrtBefore, chcrt->totalStats());
    status_.outOfCore.reset();
    if (outOfCore) status_.outOfCore = outOfCoreFrameStatus(*outOfCore, outOfCoreBefore, scene_->sceneInCore, residency, lod);
    if (settings_.viewMode != ViewMode::Shafts && settings_.viewMode != ViewMode::Residency &&
        settings_.viewMode != ViewMode::Lod) { // those have shown theirs
        showTracedView(renderer, *display_, chcrt, settings_, scene_->scene.bounds(), w, h);
    }
    checkGlErrors("viewer frame");
    // Out of core the upload limit may leave subtrees for later: the frame is rendered again until complete.
    dirty_ = status_.outOfCore && status_.outOfCore->frame.cachePostponed > 0;
    renderedCamera_ = camera_;
    status_.stats = stats;
    status_.frameRendered = true;
    if (recorder_.recording()) recorder_.record(camera_, scripted(), script_ ? script_->frame() : 0);
    FrameRecord record;
    record.stats = &stats;
    record.method = methods_.activeMethod();
    record.viewMode = toString(settings_.viewMode);
    record.primary = toString(renderer.settings().primaryVisibility);
    record.chcrt = status_.chcrt;
    record.alwaysCull = methods_.activeAlwaysCull();
    record.outOfCore = outOfCore;
    record.outOfCoreStatus = status_.outOfCore;
    record.sceneInCore = scene_->sceneInCore;
    record.residency = residency;
    record.lod = lod;
    record.shafts = settings_.viewMode == ViewMode::Shafts && shafts_.pick() ? &*shafts_.pick() : nullptr;
    record.width = w;
    record.height = h;
    record.accumulatedFrames = display_->accumulatedFrames();
    record.frameMs = millisecondsSince(start); // render + visualisation (loop_ms adds panel and swap)
    log_.addFrame(record);
}

// CHC+RT methods: debug images on only in their view modes and the cost view (instrumented shader variants are
// slower; a debug image also turns the adaptive fallback off, so `chcrt`'s cost view shows what culling costs).
void Viewer::prepareDebugImage(ChcrtTracer* chcrt) {
    if (!chcrt) return;
    if (!methods_.outOfCore()) { // out of core: set around the chosen rays' trace only (traceChosenRays)
        const ChcrtDebugImage kind = chcrtDebugImageOf(settings_.viewMode);
        if (chcrt->debugImageKind() != kind) chcrt->setDebugImage(kind);
    } else if (chcrt->debugImageKind() != ChcrtDebugImage::None) {
        // The out-of-core G-buffer's primary rays record their subtrees in the debug image (PrimaryResolve),
        // which no other debug image may occupy while they are traced.
        chcrt->setDebugImage(ChcrtDebugImage::None);
    }
}

void Viewer::renderView(ChcrtTracer* chcrt, Clock::time_point start, FrameStats& stats,
                        std::optional<ResidencyCounts>& residency, std::optional<LodCounts>& lod) {
    Renderer& renderer = *gpu_.renderer;
    switch (settings_.viewMode) {
    case ViewMode::Shafts:
        renderShafts(stats);
        stats.totalMs = millisecondsSince(start);
        return;
    case ViewMode::Residency: {
        std::vector<uint8_t> before; // the cache's residency before the frame
        if (methods_.outOfCore()) before = residentSubtrees(*methods_.outOfCore());
        renderWorkingSetView(stats, [&](outofcore::OutOfCoreTracer& t, std::vector<float>& rgb) {
            residency = colourResidency(t.primaryResolve().lastPixelSubtrees(), before, display_->width(),
                                        display_->height(), rgb);
        });
        stats.totalMs = millisecondsSince(start);
        return;
    }
    case ViewMode::Lod:
        renderWorkingSetView(stats, [&](outofcore::OutOfCoreTracer& t, std::vector<float>& rgb) {
            lod = colourLod(t.primaryResolve().lastPixelSubtrees(), subtreeLevels(t), display_->width(),
                            display_->height(), rgb);
        });
        stats.totalMs = millisecondsSince(start);
        return;
    case ViewMode::Shaded:
        stats = renderer.renderFrame(camera_);
        if (settings_.accumulate) display_->accumulate(renderer.targets());
        else display_->showSingleFrame();
        return;
    default:
        renderer.renderGBuffer(camera_, stats);
        if (settings_.viewMode == ViewMode::Cost || isChcrtDebugMode(settings_.viewMode)) {
            traceChosenRays(renderer, chcrt, methods_.outOfCore(), settings_, camera_, stats);
        }
        stats.totalMs = millisecondsSince(start);
        return;
    }
}

// The residency and lod views (out of core): the shaded frame (one frame, no refinement) tinted per pixel by where
// its primary hit came from — a subtree resident in the GPU cache before the frame or one uploaded during it; the
// subtree itself or one of its LOD proxies.
void Viewer::renderWorkingSetView(
    FrameStats& stats, const std::function<void(outofcore::OutOfCoreTracer&, std::vector<float>&)>& colour) {
    outofcore::OutOfCoreTracer* outOfCore = methods_.outOfCore();
    const bool available = outOfCore && !scene_->sceneInCore;
    showShadedFrame(*gpu_.renderer, *display_, settings_, scene_->scene.bounds(), camera_, stats);
    if (!available) { // the shaded frame, with a note
        const std::string text = std::string("the ") + toString(settings_.viewMode) +
                                 " view needs --out-of-core with a prepared scene not loaded in core "
                                 "(--load-in-core off)";
        if (status_.message != text) notice(text);
        return;
    }
    std::vector<float> rgb = displayedRgb(*display_);
    colour(*outOfCore, rgb);
    display_->showImage(rgb);
}

// The shafts view: the picked Line Space node's shafts over the shaded frame, with the N/D/T of the method's
// Line Spaces (the panel's values).
void Viewer::renderShafts(FrameStats& stats) {
    const int w = display_->width(), h = display_->height();
    showShadedFrame(*gpu_.renderer, *display_, settings_, scene_->scene.bounds(), camera_, stats);
    const CommonOptions shown = shownParameters(settings_, status_.triangles);
    shafts_.update(scene_->bvh, scene_->sceneInCore, camera_, w, h, shown.lineSpace);
    std::vector<float> rgb = displayedRgb(*display_);
    if (shafts_.pick()) drawShafts(*shafts_.pick(), camera_, w, h, rgb);
    display_->showImage(rgb);
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
    updatePanelStatus();
    if (showPanel_ || !scene_) {
        const ViewerActions actions = panel_->draw(settings_, status_);
        if (!scripted() && scene_) applyPanelActions(actions);
    }
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (!windowScreenshot_.empty()) {
        writeImage(windowScreenshot_, readWindow(fbWidth, fbHeight), /*alreadyDisplayEncoded=*/true);
        notice("wrote " + windowScreenshot_);
        windowScreenshot_.clear();
    }
    glfwSwapBuffers(window_);
}

void Viewer::updatePanelStatus() {
    status_.loading = loader_.busy();
    status_.loadingScene = loader_.scene();
    status_.loadingSeconds = loader_.elapsedSeconds();
    const BackgroundJob& cacheJob = methods_.cacheJob();
    if (!loader_.busy() && cacheJob.busy()) { // a method's Line Space / N-tree build, shown like a loading step
        const LoadProgressSnapshot p = cacheJob.progress();
        status_.loading = true;
        status_.loadingScene = "Line Spaces for " + settings_.method;
        status_.loadingSeconds = cacheJob.elapsedSeconds();
        status_.loadingStep = p.label;
        status_.loadingStepNumber = p.step;
        status_.loadingFraction = p.fraction();
    }
    if (!showPanel_ && scene_) return;
    status_.frameHistoryMs.assign(log_.history().begin(), log_.history().end());
    status_.accumulatedFrames = display_->accumulatedFrames();
    status_.internalWidth = display_->width();
    status_.internalHeight = display_->height();
    status_.shaftInfo = shafts_.info();
    status_.camera = camera_;
    status_.speed = walk_.speed();
    status_.pathFrame = pathFrame_;
    status_.pathFrames = scene_ ? scene_->path.frameCount() : 1;
    status_.playing = playing_;
    status_.recording = recorder_.recording();
    status_.recordedKeyframes = recorder_.keyframes();
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
    if (frameFailed_) { // the window shows an older frame than the view asked for
        reportError("screenshot " + file + " not written: the last frame failed (" + status_.frameError + ")");
        return;
    }
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
    recorder_.start(camera_, script_ ? script_->frame() : 0);
    notice("recording");
}

void Viewer::stopRecording(const std::string& file) {
    recorder_.stop(file);
    notice("saved " + std::to_string(recorder_.keyframes()) + " keyframes to " + file);
}

void Viewer::notice(const std::string& text) {
    status_.message = text;
    if (scripted()) std::printf("view: %s\n", text.c_str());
}

void Viewer::reportError(const std::string& text) {
    status_.message = text;
    std::fprintf(stderr, "view: error: %s\n", text.c_str());
}

} // namespace

int runViewer(const ViewOptions& options) {
    Viewer viewer(options);
    return viewer.run();
}

} // namespace chcrt::app
