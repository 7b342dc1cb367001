#include "app/viewer/background_job.h"

#include "renderer/core/error.h"

#include <cassert>
#include <utility>

namespace chcrt::app {
namespace {

// Progress written into a state the panel reads. Scene loading keeps one with its session (later steps on the main
// thread report to the same state); a BackgroundJob gives its job one.
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

std::unique_ptr<Progress> makePanelProgress(std::shared_ptr<LoadProgressState> state) {
    return std::make_unique<PanelProgress>(std::move(state));
}

BackgroundJob::~BackgroundJob() {
    if (worker_.joinable()) worker_.join();
}

void BackgroundJob::start(std::string name, std::function<void(Progress&)> job) {
    assert(!busy());
    finished_ = false;
    error_ = nullptr;
    name_ = std::move(name);
    start_ = std::chrono::steady_clock::now();
    progress_ = std::make_shared<LoadProgressState>();
    worker_ = std::thread([this, job = std::move(job), state = progress_] {
        try {
            PanelProgress progress(state);
            job(progress);
            state->markComplete();
        } catch (...) {
            error_ = std::current_exception();
        }
        finished_ = true;
    });
}

void BackgroundJob::take() {
    if (worker_.joinable()) worker_.join();
    finished_ = false;
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

double BackgroundJob::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void discardJob(BackgroundJob& job) {
    if (!job.busy()) return;
    try {
        job.take();
    } catch (const InputError&) {
    }
}

} // namespace chcrt::app
