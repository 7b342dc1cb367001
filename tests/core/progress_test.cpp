#include "renderer/core/progress.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
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

TerminalProgressOptions immediateOptions(int fd) {
    TerminalProgressOptions options;
    options.fd = fd;
    options.requireTty = false;
    options.delaySeconds = 0.0;
    options.redrawSeconds = 0.005;
    return options;
}

TEST(Progress, NullProgressAcceptsEverything) {
    Progress& progress = nullProgress();
    progress.begin("nothing", 10);
    progress.update(5);
    progress.end();
    EXPECT_EQ(&progress, &nullProgress());
}

TEST(Progress, DisabledWritesNothing) {
    CapturedOutput output;
    {
        auto progress = makeTerminalProgress(false, immediateOptions(output.fd()));
        progress->begin("disabled", 100);
        progress->update(50);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        progress->end();
    }
    EXPECT_EQ(output.text(), "");
}

TEST(Progress, NonTtyWritesNothing) {
    CapturedOutput output;
    TerminalProgressOptions options = immediateOptions(output.fd());
    options.requireTty = true; // a regular file is not a terminal
    {
        auto progress = makeTerminalProgress(true, options);
        progress->begin("not a tty", 100);
        progress->update(50);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        progress->end();
    }
    EXPECT_EQ(output.text(), "");
}

TEST(Progress, ShortStepWritesNothing) {
    CapturedOutput output;
    TerminalProgressOptions options = immediateOptions(output.fd());
    options.delaySeconds = 60.0;
    {
        auto progress = makeTerminalProgress(true, options);
        progress->begin("short", 100);
        progress->update(100);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        progress->end();
    }
    EXPECT_EQ(output.text(), "");
}

TEST(Progress, DrawsBarWithPercentAndFinishesLine) {
    CapturedOutput output;
    auto progress = makeTerminalProgress(true, immediateOptions(output.fd()));
    progress->begin("Building BVH", 200);
    progress->update(100);
    ASSERT_TRUE(output.waitForOutput(" 50% 100/200")) << output.text();
    const std::string during = output.text();
    EXPECT_EQ(during.front(), '\r');
    EXPECT_NE(during.find("Building BVH ["), std::string::npos) << during;
    EXPECT_NE(during.find(" 50% 100/200"), std::string::npos) << during;
    EXPECT_NE(during.find("ETA"), std::string::npos) << during;
    EXPECT_EQ(during.find('\n'), std::string::npos) << "line finished before end()";
    progress->update(200);
    progress->end();
    const std::string after = output.text();
    EXPECT_EQ(after.back(), '\n');
    EXPECT_NE(after.find("100% 200/200"), std::string::npos) << after;
}

TEST(Progress, UnknownTotalShowsCount) {
    CapturedOutput output;
    auto progress = makeTerminalProgress(true, immediateOptions(output.fd()));
    progress->begin("Loading", 0);
    progress->update(1234);
    ASSERT_TRUE(output.waitForOutput(" 1234 ")) << output.text();
    progress->end();
    const std::string text = output.text();
    EXPECT_NE(text.find("Loading "), std::string::npos) << text;
    EXPECT_NE(text.find(" 1234 0:0"), std::string::npos) << text; // count, then elapsed m:ss
    EXPECT_EQ(text.find('%'), std::string::npos) << text;
}

TEST(Progress, ConcurrentUpdatesKeepTheMaximum) {
    CapturedOutput output;
    auto progress = makeTerminalProgress(true, immediateOptions(output.fd()));
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
