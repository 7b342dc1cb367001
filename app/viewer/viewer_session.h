#pragma once
// Scene loading for the viewer on a worker thread (generation or file loading, then the BVH build), so the
// window keeps drawing and shows progress while a scene loads. GL upload happens afterwards on the main thread
// (a GL context is current on one thread only).
#include "app/session.h"
#include "app/viewer/background_job.h"

#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace chcrt::app {

class SceneLoader {
public:
    SceneLoader() = default;
    ~SceneLoader(); // waits for a running load
    SceneLoader(const SceneLoader&) = delete;
    SceneLoader& operator=(const SceneLoader&) = delete;

    // Starts loading `options.scene` (with its camera path). Requires !busy().
    void start(const CommonOptions& options);
    bool busy() const { return worker_.joinable(); }
    bool finished() const { return finished_.load(); }
    // The loaded session, after finished(); rethrows what the worker threw (InputError for bad scenes).
    std::unique_ptr<SceneSession> take();
    double elapsedSeconds() const;
    const std::string& scene() const { return scene_; }
    // The worker's progress (label and fraction of the current step); complete once finished.
    LoadProgressSnapshot progress() const { return progress_->snapshot(); }

private:
    std::thread worker_;
    std::atomic<bool> finished_{false};
    std::unique_ptr<SceneSession> result_;
    std::exception_ptr error_;
    std::string scene_;
    std::shared_ptr<LoadProgressState> progress_ = std::make_shared<LoadProgressState>();
    std::chrono::steady_clock::time_point start_;
};

} // namespace chcrt::app
