#include "app/viewer/viewer_session.h"

#include <algorithm>
#include <cassert>

namespace chcrt::app {
namespace {

// The Progress the worker's openSceneSession reports to; it stays with the session (later steps on the main
// thread, e.g. Line Space builds, report to the same state).
class PanelProgress final : public Progress {
public:
    explicit PanelProgress(std::shared_ptr<LoadProgressState> state) : state_(std::move(state)) {}
    void begin(const std::string& label, uint64_t total) override { state_->begin(label, total); }
    void update(uint64_t done) override { state_->update(done); }
    void end() override { state_->end(); }

private:
    std::shared_ptr<LoadProgressState> state_;
};

} // namespace

void LoadProgressState::begin(const std::string& label, uint64_t total) {
    std::lock_guard<std::mutex> lock(mutex_);
    label_ = label;
    total_ = total;
    ++step_;
    complete_ = false;
    done_.store(0, std::memory_order_relaxed);
}

void LoadProgressState::end() {
    std::lock_guard<std::mutex> lock(mutex_);
    done_.store(total_, std::memory_order_relaxed); // a step that ends is done (100 % of it)
}

void LoadProgressState::reset() {
    std::lock_guard<std::mutex> lock(mutex_);
    label_.clear();
    total_ = 0;
    step_ = 0;
    complete_ = false;
    done_.store(0, std::memory_order_relaxed);
}

void LoadProgressState::markComplete() {
    std::lock_guard<std::mutex> lock(mutex_);
    complete_ = true;
    done_.store(total_, std::memory_order_relaxed);
}

LoadProgressSnapshot LoadProgressState::snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return LoadProgressSnapshot{label_, done_.load(std::memory_order_relaxed), total_, step_, complete_};
}

SceneLoader::~SceneLoader() {
    if (worker_.joinable()) worker_.join();
}

void SceneLoader::start(const CommonOptions& options) {
    assert(!busy());
    finished_ = false;
    result_.reset();
    error_ = nullptr;
    scene_ = options.scene;
    start_ = std::chrono::steady_clock::now();
    CommonOptions quiet = options;
    quiet.quiet = true; // the panel shows progress, not a terminal bar
    progress_ = std::make_shared<LoadProgressState>(); // the previous session keeps its own
    worker_ = std::thread([this, quiet, state = progress_] {
        try {
            result_ = std::make_unique<SceneSession>(openSceneSession(quiet, std::make_unique<PanelProgress>(state)));
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
