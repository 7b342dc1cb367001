#include "app/viewer/viewer_session.h"

#include <cassert>
#include <utility>

namespace chcrt::app {

SceneLoader::~SceneLoader() {
    if (worker_.joinable()) worker_.join();
}

void SceneLoader::start(const CommonOptions& options, GpuUpload upload) {
    assert(!busy());
    finished_ = false;
    result_.reset();
    uploaded_ = {};
    error_ = nullptr;
    scene_ = options.scene;
    start_ = std::chrono::steady_clock::now();
    CommonOptions quiet = options;
    quiet.quiet = true; // the panel shows progress, not a terminal bar
    progress_ = std::make_shared<LoadProgressState>(); // the previous session keeps its own
    worker_ = std::thread([this, quiet, state = progress_, upload = std::move(upload)] {
        try {
            result_ = std::make_unique<SceneSession>(openSceneSession(quiet, makePanelProgress(state)));
            if (upload) {
                state->begin("Uploading to the GPU", 0);
                uploaded_ = upload(*result_);
                state->end();
            }
            state->markComplete();
        } catch (...) {
            error_ = std::current_exception();
        }
        finished_ = true;
    });
}

std::unique_ptr<SceneSession> SceneLoader::take() {
    assert(finished());
    worker_.join();
    finished_ = false;
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
    return std::move(result_);
}

double SceneLoader::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

} // namespace chcrt::app
