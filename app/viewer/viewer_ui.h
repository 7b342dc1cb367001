#pragma once
// The viewer's ImGui panel: statistics (frame time, its split per pass, rays/s, a frame-time graph), the live
// settings (method, view mode, effects, sampling, exposure, render scale) and camera-path controls. It edits
// ViewerSettings in place and reports button presses as actions; the app applies them between frames.
#include "app/parameters.h"
#include "app/viewer/residency_view.h"
#include "app/viewer/viewer_settings.h"
#include "culling/outofcore/out_of_core_tracer.h"
#include "renderer/render/renderer.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace chcrt::app {

// CHC+RT counters of the last frame (all its traces), when the method is a CHC+RT one.
struct ViewerChcrtStats {
    uint64_t traces = 0, queries = 0, subtreesScheduled = 0, shaderCalls = 0, fallbackTraces = 0;
    uint64_t queriesSkippedExtent = 0; // pairs found invisible by the ray extent without a query
    uint64_t heightSum = 0;            // termination heights of the traces that culled (the adaptive choice's picks)
    double phase1Ms = 0, phase2Ms = 0, phase3Ms = 0, fallbackMs = 0;
    uint64_t culledTraces() const { return traces - fallbackTraces; }
    double meanHeight() const { return culledTraces() ? double(heightSum) / double(culledTraces()) : 0.0; }
};

// Out of core (CHC+RT §5.4, Table 3's columns) for the last frame: the frame's counters (difference of the
// tracer's snapshots around it) and the budgets; residency counts when the residency view drew the frame.
struct ViewerOutOfCoreStatus {
    outofcore::OutOfCoreStats frame;
    double gpuCacheMb = 0, hostCacheMb = 0;
    size_t fileSubtrees = 0;
    bool sceneInCore = false; // --load-in-core: the G-buffer is the in-core one, only tracing is out of core
    std::optional<ResidencyCounts> residency;
    std::optional<LodCounts> lod; // when the lod view drew the frame
};

struct ViewerStatus {
    bool frameRendered = false; // a frame of the scene was rendered: the statistics below are of it
    FrameStats stats;          // of the last rendered frame
    std::optional<ViewerChcrtStats> chcrt;
    std::optional<ViewerOutOfCoreStatus> outOfCore;
    double frameMs = 0;        // wall time of the last rendered frame's loop iteration (render + panel + swap)
    std::vector<float> frameHistoryMs;
    int accumulatedFrames = 0;
    int internalWidth = 0, internalHeight = 0;
    std::string sceneName;
    uint64_t triangles = 0;
    bool loading = false;
    std::string loadingScene;
    double loadingSeconds = 0;
    std::string loadingStep;        // the worker's current step (Progress label)
    int loadingStepNumber = 0;
    double loadingFraction = -1;    // of the current step, in [0, 1]; negative: unknown amount of work
    // Shafts view: the picked Line Space node (a line of text each), empty before a pick.
    std::vector<std::string> shaftInfo;
    Camera camera;
    float speed = 0;
    int pathFrame = 0, pathFrames = 1;
    bool playing = false;
    bool recording = false;
    size_t recordedKeyframes = 0;
    std::string message; // last notice: screenshot written, command line copied, errors
    std::string frameError; // the last frame failed on its input (shown until a frame renders)
};

struct ViewerActions {
    bool settingsChanged = false;
    bool reset = false, frameScene = false, togglePlay = false, toggleRecord = false;
    bool screenshot = false, copyCommandLine = false;
    std::optional<int> pathFrame;
    std::string loadScene; // non-empty: load this scene
};

class ViewerPanel {
public:
    explicit ViewerPanel(std::string sceneField) : sceneField_(std::move(sceneField)) {}
    // Draws the panel (between ImGui::NewFrame and ImGui::Render).
    ViewerActions draw(ViewerSettings& settings, const ViewerStatus& status);
    // The size the last draw gave the frame-time graph (0 × 0 when it drew none): tests/viewer/viewer_panel_test.cpp.
    std::pair<float, float> graphSize() const { return graphSize_; }

private:
    void drawStatistics(const ViewerStatus& status);
    void drawOutOfCore(const ViewerOutOfCoreStatus& outOfCore);
    void drawSettings(ViewerSettings& settings, const ViewerStatus& status, ViewerActions& actions);
    void drawPrimaryVisibility(const ViewerSettings& settings, nlohmann::json& changes);
    void drawMethodParameters(ViewerSettings& settings, const ViewerStatus& status, nlohmann::json& changes);
    void drawEffects(const ViewerSettings& settings, nlohmann::json& changes);
    void drawParameter(const Parameter& parameter, const CommonOptions& shown, nlohmann::json& changes);
    void drawCamera(const ViewerStatus& status, ViewerActions& actions);
    static constexpr float kPanelWidth = 380.0f, kMinPanelWidth = 240.0f, kMinPanelHeight = 120.0f;
    static constexpr float kPanelMargin = 8.0f, kGraphHeight = 50.0f;
    std::string sceneField_;
    std::pair<float, float> graphSize_{0.0f, 0.0f};
    float width_ = kPanelWidth; // the panel's width (the user may resize it) and top edge, of the last draw
    float top_ = kPanelMargin;
};

} // namespace chcrt::app
