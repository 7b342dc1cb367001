#pragma once
// Scene loading for the viewer on a worker thread (generation or file loading, then the BVH build), so the
// window keeps drawing and shows progress while a scene loads. GL upload happens afterwards on the main thread
// (a GL context is current on one thread only).
#include "app/session.h"

#include <atomic>
#include <chrono>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace chcrt::app {

// What the loading worker reports through Progress (openSceneSession's steps: loading or generating the scene,
// then building the BVH), read by the panel on the main thread.
struct LoadProgressSnapshot {
    std::string label;    // the current step ("Building BVH", "Generating city ...", "Loading file.gltf")
    uint64_t done = 0;
    uint64_t total = 0;   // 0: the step does not know its amount of work (shown as a spinner)
    int step = 0;         // steps begun so far (1-based once loading started)
    bool complete = false; // every step has ended and the scene is ready for the GL upload
    // Fraction of the current step in [0, 1]; 1 when complete; negative when unknown.
    double fraction() const {
        if (complete) return 1.0;
        return total ? std::min(1.0, double(done) / double(total)) : -1.0;
    }
};

class LoadProgressState {
public:
    void begin(const std::string& label, uint64_t total);
    void update(uint64_t done) { done_.store(done, std::memory_order_relaxed); }
    void end();
    void reset();
    void markComplete();
    LoadProgressSnapshot snapshot() const;

private:
    mutable std::mutex mutex_;
    std::string label_;
    uint64_t total_ = 0;
    int step_ = 0;
    bool complete_ = false;
    std::atomic<uint64_t> done_{0};
};

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
