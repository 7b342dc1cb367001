#pragma once
// Work on a worker thread whose Progress the viewer's panel shows: the state both threads share, and a job runner
// (scene loading uses the state through SceneLoader, viewer_session.h).
#include "renderer/core/progress.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
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

// The Progress a worker reports to; it writes into a state the panel reads.
std::unique_ptr<Progress> makePanelProgress(std::shared_ptr<LoadProgressState> state);

// One function run on a worker thread with panel progress, polled each frame: a method switch's Line Space or
// N-tree build (methodCacheBuild), which can take minutes, while the current tracer keeps rendering (issue #6: the
// viewer never blocks for more than a frame on long work).
class BackgroundJob {
public:
    BackgroundJob() = default;
    ~BackgroundJob(); // waits for a running job
    BackgroundJob(const BackgroundJob&) = delete;
    BackgroundJob& operator=(const BackgroundJob&) = delete;

    // Starts `job` under a name (what it is for, e.g. the method and parameters). Requires !busy().
    void start(std::string name, std::function<void(Progress&)> job);
    bool busy() const { return worker_.joinable(); }
    bool finished() const { return finished_.load(); }
    // Waits for the job (if it still runs), then rethrows what it threw. Afterwards !busy().
    void take();
    const std::string& name() const { return name_; }
    double elapsedSeconds() const;
    LoadProgressSnapshot progress() const { return progress_->snapshot(); }

private:
    std::thread worker_;
    std::atomic<bool> finished_{false};
    std::exception_ptr error_;
    std::string name_;
    std::shared_ptr<LoadProgressState> progress_ = std::make_shared<LoadProgressState>();
    std::chrono::steady_clock::time_point start_;
};

// Waits for a job whose result no longer matters (it reads a scene that is being replaced): what it made or threw
// (InputError) is dropped.
void discardJob(BackgroundJob& job);

} // namespace chcrt::app
