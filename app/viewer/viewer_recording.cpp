#include "app/viewer/viewer_recording.h"

#include "renderer/core/error.h"

namespace chcrt::app {

void PathRecorder::start(const Camera& camera, int scriptFrame) {
    recording_ = true;
    path_ = CameraPath{};
    path_.name = "recorded";
    path_.fps = 30.0;
    path_.fovYDegrees = camera.fovYDegrees;
    start_ = std::chrono::steady_clock::now();
    startFrame_ = scriptFrame;
    path_.keyframes.push_back(CameraKeyframe{0.0, camera.eye, camera.target, camera.up});
}

void PathRecorder::record(const Camera& camera, bool scripted, int scriptFrame) {
    // Scripted sessions advance 1/30 s per frame; interactive ones record wall time.
    const double t = scripted ? (scriptFrame - startFrame_) * kScriptSecondsPerFrame
                              : std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (!path_.keyframes.empty()) {
        const CameraKeyframe& last = path_.keyframes.back();
        if (t <= last.t || (last.eye == camera.eye && last.target == camera.target)) return;
    }
    path_.keyframes.push_back(CameraKeyframe{t, camera.eye, camera.target, camera.up});
}

void PathRecorder::stop(const std::string& file) {
    if (!recording_) throw InputError("recordStop without a recording (start one with recordStart or F9)");
    recording_ = false;
    saveCameraPath(path_, file);
}

} // namespace chcrt::app
