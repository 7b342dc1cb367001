#include "app/viewer/background_job.h"

#include "renderer/core/error.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace chcrt::app {
namespace {

// The job runs on another thread while the caller keeps polling (what the viewer's frame loop does), its progress
// is visible meanwhile, and take() returns once it has finished.
TEST(BackgroundJob, RunsOnAWorkerWhileTheCallerPollsItsProgress) {
    BackgroundJob job;
    EXPECT_FALSE(job.busy());
    std::atomic<bool> release{false};
    std::atomic<bool> halfway{false};
    const std::thread::id caller = std::this_thread::get_id();
    std::thread::id worker;
    job.start("bvh+ls N6", [&](Progress& progress) {
        worker = std::this_thread::get_id();
        progress.begin("Building Line Spaces", 10);
        progress.update(5);
        halfway = true;
        while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        progress.update(10);
        progress.end();
    });
    EXPECT_TRUE(job.busy());
    EXPECT_EQ(job.name(), "bvh+ls N6");
    while (!halfway) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_FALSE(job.finished()); // blocked until released: the caller was not
    const LoadProgressSnapshot mid = job.progress();
    EXPECT_EQ(mid.label, "Building Line Spaces");
    EXPECT_DOUBLE_EQ(mid.fraction(), 0.5);
    EXPECT_FALSE(mid.complete);
    release = true;
    while (!job.finished()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    job.take();
    EXPECT_FALSE(job.busy());
    EXPECT_NE(worker, caller);
    EXPECT_TRUE(job.progress().complete);
}

TEST(BackgroundJob, TakeRethrowsWhatTheJobThrewAndTheJobCanStartAgain) {
    BackgroundJob job;
    job.start("bad", [](Progress&) { throw InputError("cache directory not writable"); });
    EXPECT_THROW(job.take(), InputError); // take() waits for a job that may still run
    EXPECT_FALSE(job.busy());
    bool ran = false;
    job.start("good", [&](Progress&) { ran = true; });
    EXPECT_NO_THROW(job.take());
    EXPECT_TRUE(ran);
}

} // namespace
} // namespace chcrt::app
