#pragma once
// Scripted viewer sessions (`chcrt view --script FILE`) for tests and benchmarks: a JSON list of steps, run in
// order, each optionally followed by a number of rendered frames. Scripts run with a fixed time step of 1/30 s
// per frame and ignore real input, so a session is deterministic.
//
//   [{"frames": 3},                                   render 3 frames
//    {"key": "W", "frames": 5},                       hold W for 5 frames ("keys": ["W", "SHIFT"] holds several)
//    {"mouse": [40, 0], "frames": 2},                 mouse look: pixels per frame, right button held
//    {"scroll": 2},                                   speed × 1.25^2 (negative: slower)
//    {"set": {"method": "bvh", "viewMode": "cost"}},  any viewer setting (viewer_settings.h: applySettings)
//    {"camera": {"eye": [0,2,0], "target": [0,2,-5], "fov": 60}},
//    {"pathFrame": 10}, {"play": true},               jump to / play the camera path (one path frame per frame)
//    {"action": "reset" | "frameScene" | "copyCommandLine" | "recordStart"},
//    {"press": "F"},                                  a key press as the window gets it (R F P V C F9 F12 + - TAB)
//    {"recordStop": "walk.json"},                     save the recorded walkthrough
//    {"resize": [320, 200]},                          window size in screen coordinates
//    {"pick": [120, 80]},                             pick the pixel (internal image, top-left origin) for the
//                                                     shafts view, like a left click in the window
//    {"loadScene": "city:5k"},                        background load; the script waits until it is ready
//    {"screenshot": "a.png"},                         the current view (internal resolution, no panel)
//    {"windowScreenshot": "w.png"},                   the whole window as drawn, panel included (window size)
//    {"expect": {"cappedRays": 0, "minRaysGenerated": 1, "tracePasses": {"shadow": 1},
//                "accumulatedFrames": 1, "imageSize": [64, 36], "method": "bvh", "viewMode": "cost",
//                "primary": "traced", "shaftNodePicked": true, "loadProgress": 1.0, "failedFrames": 0,
//                "frameFailed": false}}]
// An unmet expectation ends the session with exit code 4 (after the remaining steps are skipped).
#include "app/viewer/walk_controller.h"
#include "renderer/render/render_settings.h"
#include "renderer/scene/scene.h"

#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace chcrt::app {

struct ScriptStep {
    int frames = 0;                   // frames rendered after the step's actions
    WalkInput held;                   // keys held and mouse motion, per frame
    float scrollSteps = 0;            // applied once
    std::optional<nlohmann::json> set;
    std::optional<Camera> camera;
    std::optional<int> pathFrame;
    std::optional<bool> play;
    std::string action;               // reset, frameScene, copyCommandLine, recordStart
    std::vector<std::string> presses; // key presses handled like the window's (kPressableKeys)
    std::string recordStop;           // file to save the recorded path to
    std::optional<std::pair<int, int>> resize;
    std::optional<std::pair<int, int>> pick; // pixel of the internal image (rows top to bottom), like a left click
    std::string loadScene;
    std::string screenshot;
    std::string windowScreenshot;
    std::optional<nlohmann::json> expect;
};

// Keys a script may press (the viewer's key bindings, viewer_app.h).
inline constexpr const char* kPressableKeys[] = {"R", "F", "P", "V", "C", "F9", "F12", "+", "-", "TAB"};

// Throws InputError naming the step (0-based) and key for malformed scripts.
std::vector<ScriptStep> parseViewerScript(const std::string& jsonText, const std::string& nameForErrors);
std::vector<ScriptStep> loadViewerScript(const std::filesystem::path& file);

// What a step's "expect" can check: the viewer's state after the step's frames.
struct ScriptObservation {
    uint64_t cappedRays = 0, raysGenerated = 0;
    std::array<uint64_t, 4> tracePasses{}; // per RayType (render_settings.h), of the last rendered frame
    int accumulatedFrames = 0;
    int width = 0, height = 0;             // internal image
    std::string method, primary, viewMode, scene;
    bool playing = false;
    int pathFrame = 0;
    bool shaftNodePicked = false;
    bool outOfCore = false;                // the method traces through the GPU subtree cache
    double loadProgress = 0;
    int failedFrames = 0;                  // frames that failed on their input (an out-of-core read) so far
    bool frameFailed = false;              // the last frame tried failed (the window shows an older one)
};
// The unmet expectations of `expect`, one line each ("accumulatedFrames = 1"); InputError for unknown keys.
std::vector<std::string> unmetExpectations(const nlohmann::json& expect, const ScriptObservation& seen);

// Steps a script one rendered frame at a time: a step's actions run when it begins, its checks once its frames are
// rendered (at once for a step without frames), then the next step begins.
class ScriptRunner {
public:
    enum class Advance { Frame, Waiting, Ended };
    explicit ScriptRunner(std::vector<ScriptStep> steps) : steps_(std::move(steps)) {}
    // Moves to the next frame to render. `waiting()` true after a step's actions (a scene loads) stops there until
    // the next call; Ended once every step ran or an expectation failed (fail()).
    Advance advance(const std::function<void(const ScriptStep&)>& actions,
                    const std::function<void(const ScriptStep&)>& checks, const std::function<bool()>& waiting);
    const ScriptStep* current() const { return current_; } // the step whose frames render
    size_t currentIndex() const { return next_ - 1; }      // 0-based, for messages
    int frame() const { return frame_; }                   // frames advanced so far
    size_t totalFrames() const;                            // frames of all steps (fewer if an expectation fails)
    void fail() { ++failures_; }
    int failures() const { return failures_; }

private:
    std::vector<ScriptStep> steps_;
    size_t next_ = 0;
    int framesLeft_ = 0;
    const ScriptStep* current_ = nullptr;
    int failures_ = 0;
    int frame_ = 0;
};

} // namespace chcrt::app
