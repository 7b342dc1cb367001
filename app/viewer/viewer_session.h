#pragma once
// Scene loading for the viewer on a worker thread (generation or file loading, the BVH build, then the GPU upload
// on a context that shares objects with the window's), so the window keeps drawing and shows progress while a
// scene loads.
#include "app/session.h"
#include "app/viewer/background_job.h"
#include "renderer/render/scene_gpu.h"
#include "renderer/render/tracer.h"

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

    // What the worker's GPU step made: the scene's buffers and, for a scene traced out of core, the method's tracer
    // (its GPU cache is a large allocation), made for `tracerKey` (method and parameters when the load started).
    struct Uploaded {
        std::unique_ptr<SceneGpu> scene;
        std::unique_ptr<Tracer> tracer;
        std::string tracerKey;
    };
    // Uploads a loaded session's scene and BVH to the GPU; runs on the worker after the BVH build, as the step
    // "Uploading to the GPU" (the viewer makes its shared upload context current around it).
    using GpuUpload = std::function<Uploaded(const SceneSession&)>;
    // Starts loading `options.scene` (with its camera path), then `upload` when given. Requires !busy().
    void start(const CommonOptions& options, GpuUpload upload = nullptr);
    bool busy() const { return worker_.joinable(); }
    bool finished() const { return finished_.load(); }
    // The loaded session, after finished(); rethrows what the worker threw (InputError for bad scenes).
    std::unique_ptr<SceneSession> take();
    // What the worker uploaded (empty without an upload function), after take().
    Uploaded takeUploaded() { return std::move(uploaded_); }
    double elapsedSeconds() const;
    const std::string& scene() const { return scene_; }
    // The worker's progress (label and fraction of the current step); complete once finished.
    LoadProgressSnapshot progress() const { return progress_->snapshot(); }

private:
    std::thread worker_;
    std::atomic<bool> finished_{false};
    std::unique_ptr<SceneSession> result_;
    Uploaded uploaded_;
    std::exception_ptr error_;
    std::string scene_;
    std::shared_ptr<LoadProgressState> progress_ = std::make_shared<LoadProgressState>();
    std::chrono::steady_clock::time_point start_;
};

} // namespace chcrt::app
