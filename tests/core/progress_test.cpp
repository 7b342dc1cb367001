#include "renderer/core/progress.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>
#include <vector>

namespace chcrt {
namespace {

// A temporary file whose descriptor stands in for stderr.
class CapturedOutput {
public:
    CapturedOutput() {
        path_ = std::filesystem::temp_directory_path() /
                ("chcrt_progress_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++) + ".txt");
        fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC, 0600);
    }
    ~CapturedOutput() {
        ::close(fd_);
        std::filesystem::remove(path_);
    }
    int fd() const { return fd_; }
    std::string text() const {
        std::ifstream in(path_, std::ios::binary);
        std::ostringstream out;
        out << in.rdbuf();
        return out.str();
    }
    // Waits (up to 5 s) until the output contains `expected` (anything, by default); true if it does. Waiting
    // for content rather than sleeping keeps the tests deterministic on a loaded machine.
    bool waitForOutput(const std::string& expected = "") const {
        for (int i = 0; i < 500; ++i) {
            const std::string current = text();
            if (!current.empty() && current.find(expected) != std::string::npos) {
                return true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }

private:
    static inline int counter_ = 0;
    std::filesystem::path path_;
    int fd_ = -1;
};

// A clock that moves only when a test sets it, and counts how often the bar looked at it: the bar's helper thread
// reads it once per redraw, so a test can wait for redraws that happened instead of sleeping for them.
class FixedClock {
public:
    void set(double seconds) { nanoseconds_ = int64_t(seconds * 1e9); }
    int reads() const { return reads_; }
    std::function<std::chrono::steady_clock::time_point()> function() {
        return [this] {
            ++reads_;
            return std::chrono::steady_clock::time_point(std::chrono::nanoseconds(nanoseconds_.load()));
        };
    }
    // Waits (up to 5 s) until the clock has been read `count` more times than now; true if it was.
    bool waitForReads(int count) const {
        const int target = reads_ + count;
        for (int i = 0; i < 5000 && reads_ < target; ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        return reads_ >= target;
    }

private:
    std::atomic<int64_t> nanoseconds_{0};
    std::atomic<int> reads_{0};
};

TerminalProgressOptions immediateOptions(int fd, FixedClock& clock) {
    TerminalProgressOptions options;
    options.fd = fd;
    options.requireTty = false;
    options.delaySeconds = 0.0;
    options.redrawSeconds = 0.005;
    options.now = clock.function();
    return options;
}

// A bar that must not exist (disabled, or stderr is not a terminal: a regular file is not): nothing is written, and
// the step is not even timed (no helper thread looks at the clock), so no amount of waiting could make it draw.
TEST(Progress, DisabledAndNonTtyBarsWriteNothingAndTimeNothing) {
    for (const bool disabled : {true, false}) {
        CapturedOutput output;
        FixedClock clock;
        TerminalProgressOptions options = immediateOptions(output.fd(), clock);
        options.requireTty = !disabled;
        {
            auto progress = makeTerminalProgress(!disabled, options);
            progress->begin("no bar", 100);
            progress->update(50);
            clock.set(10.0);
            progress->end();
        }
        EXPECT_EQ(clock.reads(), 0) << (disabled ? "disabled" : "not a tty");
        EXPECT_EQ(output.text(), "") << (disabled ? "disabled" : "not a tty");
    }
}

// A step draws nothing before it has lasted delaySeconds, however many redraws looked: one that ends earlier leaves
// no trace, a longer one draws once the delay is reached.
TEST(Progress, StepsDrawOnlyOnceTheyHaveLastedTheDelay) {
    CapturedOutput output;
    FixedClock clock;
    TerminalProgressOptions options = immediateOptions(output.fd(), clock);
    options.delaySeconds = 60.0;
    auto progress = makeTerminalProgress(true, options);
    progress->begin("short", 100);
    progress->update(100);
    clock.set(59.9);
    ASSERT_TRUE(clock.waitForReads(5)); // five redraws saw 59.9 s
    progress->end();
    EXPECT_EQ(output.text(), "");

    clock.set(100.0);
    progress->begin("long", 100);
    progress->update(40);
    clock.set(159.9);
    ASSERT_TRUE(clock.waitForReads(5));
    EXPECT_EQ(output.text(), "");
    clock.set(160.0);
    ASSERT_TRUE(output.waitForOutput("\rlong [") && output.waitForOutput(" 40% 40/100 1:00")) << output.text();
    progress->end();
}

TEST(Progress, DrawsBarWithPercentElapsedAndEtaAndFinishesLine) {
    CapturedOutput output;
    FixedClock clock;
    auto progress = makeTerminalProgress(true, immediateOptions(output.fd(), clock));
    progress->begin("Building BVH", 200);
    clock.set(10.0);
    progress->update(100);
    // Half done after 10 s: 10 s to go.
    ASSERT_TRUE(output.waitForOutput(" 50% 100/200 0:10 ETA 0:10")) << output.text();
    const std::string during = output.text();
    EXPECT_EQ(during.front(), '\r');
    EXPECT_NE(during.find("\rBuilding BVH [############............]  50% 100/200 0:10 ETA 0:10"), std::string::npos)
        << during;
    EXPECT_EQ(during.find('\n'), std::string::npos) << "line finished before end()";
    clock.set(30.0);
    progress->update(150);
    ASSERT_TRUE(output.waitForOutput(" 75% 150/200 0:30 ETA 0:10")) << output.text();
    clock.set(41.0);
    progress->update(200);
    progress->end();
    const std::string after = output.text();
    EXPECT_EQ(after.back(), '\n');
    // The final line, without an ETA (padded with spaces where it is shorter than the line it overwrites).
    const std::string lastLine = after.substr(after.rfind('\r'));
    const std::string expected = "\rBuilding BVH [########################] 100% 200/200 0:41";
    EXPECT_EQ(lastLine.substr(0, expected.size()), expected) << lastLine;
    EXPECT_EQ(lastLine.find_first_not_of(' ', expected.size()), lastLine.size() - 1) << lastLine;
}

// A step of items made of units (frames of shader passes) moves with every unit but names the item being worked
// on, not the units: 30 of 4 x 16 passes done is frame 8 of 16.
TEST(Progress, ItemStepsNameTheItemBeingWorkedOn) {
    CapturedOutput output;
    FixedClock clock;
    auto progress = makeTerminalProgress(true, immediateOptions(output.fd(), clock));
    progress->beginItems("Rendering", 16, 4, "frame");
    clock.set(10.0);
    progress->update(30);
    ASSERT_TRUE(output.waitForOutput(" 46% frame 8/16 0:10")) << output.text();
    EXPECT_EQ(output.text().find("30/64"), std::string::npos) << output.text();
    progress->update(64);
    progress->end();
    const std::string after = output.text();
    EXPECT_NE(after.substr(after.rfind('\r')).find("100% frame 16/16"), std::string::npos) << after;
}

TEST(Progress, UnknownTotalShowsCountAndElapsedTime) {
    CapturedOutput output;
    FixedClock clock;
    auto progress = makeTerminalProgress(true, immediateOptions(output.fd(), clock));
    progress->begin("Loading", 0);
    clock.set(7.5);
    progress->update(1234);
    ASSERT_TRUE(output.waitForOutput(" 1234 0:07")) << output.text();
    clock.set(3725.0);
    ASSERT_TRUE(output.waitForOutput(" 1234 1:02:05")) << output.text(); // h:mm:ss from an hour on
    progress->end();
    const std::string text = output.text();
    EXPECT_NE(text.find("\rLoading "), std::string::npos) << text;
    EXPECT_EQ(text.find('%'), std::string::npos) << text;
}

TEST(Progress, ConcurrentUpdatesKeepTheMaximum) {
    CapturedOutput output;
    FixedClock clock;
    auto progress = makeTerminalProgress(true, immediateOptions(output.fd(), clock));
    progress->begin("parallel", 4000);
    std::vector<std::thread> workers;
    for (int w = 0; w < 4; ++w) {
        workers.emplace_back([&progress, w] {
            for (uint64_t i = 0; i < 1000; ++i) {
                progress->update(i * 4 + uint64_t(w) + 1); // the largest value, 4000, comes from worker 3
            }
        });
    }
    for (std::thread& worker : workers) {
        worker.join();
    }
    progress->update(10); // a late, smaller report must not move the bar back
    ASSERT_TRUE(output.waitForOutput());
    progress->end();
    const std::string text = output.text();
    const std::string lastLine = text.substr(text.rfind('\r'));
    EXPECT_NE(lastLine.find("100% 4000/4000"), std::string::npos) << lastLine;
}

} // namespace
} // namespace chcrt
