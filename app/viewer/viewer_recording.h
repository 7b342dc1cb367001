#pragma once
// Recording a walkthrough in the viewer (F9, or a script's recordStart / recordStop): camera keyframes at wall
// time, or at the fixed 1/30 s per frame of a scripted session, saved as a camera path (docs/cli.md) that
// `chcrt render --camera-path` replays. A keyframe is added only when the camera moved and time advanced.
#include "renderer/scene/camera_path.h"

#include <chrono>
#include <string>

namespace chcrt::app {

class PathRecorder {
public:
    static constexpr double kScriptSecondsPerFrame = 1.0 / 30.0; // fixed time step of scripted sessions

    // Starts a recording at `camera`; `scriptFrame`: the frame counter of a scripted session, else unused.
    void start(const Camera& camera, int scriptFrame);
    // The camera of a rendered frame (scripted: at scriptFrame, else at the wall time since start).
    void record(const Camera& camera, bool scripted, int scriptFrame);
    // Saves the path to `file` and ends the recording; InputError without one, or for an unwritable file.
    void stop(const std::string& file);
    bool recording() const { return recording_; }
    size_t keyframes() const { return path_.keyframes.size(); }

private:
    bool recording_ = false;
    CameraPath path_;
    std::chrono::steady_clock::time_point start_;
    int startFrame_ = 0;
};

} // namespace chcrt::app
