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
//    {"expect": {"cappedRays": 0, "minRaysGenerated": 1, "tracePasses": {"shadow": 1},
//                "accumulatedFrames": 1, "imageSize": [64, 36], "method": "bvh", "viewMode": "cost",
//                "primary": "traced", "shaftNodePicked": true, "loadProgress": 1.0}}]
// An unmet expectation ends the session with exit code 4 (after the remaining steps are skipped).
#include "app/viewer/walk_controller.h"
#include "renderer/scene/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
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
    std::optional<nlohmann::json> expect;
};

// Keys a script may press (the viewer's key bindings, viewer_app.h).
inline constexpr const char* kPressableKeys[] = {"R", "F", "P", "V", "C", "F9", "F12", "+", "-", "TAB"};

// Throws InputError naming the step (0-based) and key for malformed scripts.
std::vector<ScriptStep> parseViewerScript(const std::string& jsonText, const std::string& nameForErrors);
std::vector<ScriptStep> loadViewerScript(const std::filesystem::path& file);

} // namespace chcrt::app
