// The process's resident memory, open descriptors and threads as read from /proc (the soak runs' samples).
#include "renderer/core/process_resources.h"

#include <gtest/gtest.h>

#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <thread>

namespace chcrt {
namespace {

TEST(ProcessResources, FollowMemoryDescriptorsAndThreads) {
    const ProcessResources before = sampleProcessResources();
    ASSERT_GT(before.residentBytes, 0u);
    ASSERT_GT(before.openFiles, 0); // at least stdin/stdout/stderr
    ASSERT_GE(before.threads, 1);

    constexpr size_t kBytes = size_t(64) << 20;
    std::unique_ptr<char[]> block(new char[kBytes]);
    std::memset(block.get(), 1, kBytes); // touched: resident
    FILE* file = std::fopen("/proc/self/stat", "r");
    ASSERT_NE(file, nullptr);
    std::mutex mutex;
    std::condition_variable done;
    bool stop = false;
    std::thread thread([&] {
        std::unique_lock lock(mutex);
        done.wait(lock, [&] { return stop; });
    });
    const ProcessResources during = sampleProcessResources();
    EXPECT_GE(during.residentBytes, before.residentBytes + kBytes * 9 / 10);
    EXPECT_GE(during.residentAnonBytes, before.residentAnonBytes + kBytes * 9 / 10); // a heap block: anonymous
    EXPECT_GE(during.heapInUseBytes, before.heapInUseBytes + kBytes);
    EXPECT_LT(during.residentFileBytes, before.residentFileBytes + kBytes / 10);
    // VmRSS is the sum of the two parts (RssAnon + RssFile + RssShmem, one read of /proc/self/status).
    EXPECT_NEAR(double(during.residentAnonBytes + during.residentFileBytes), double(during.residentBytes), 1 << 20);
    EXPECT_EQ(during.openFiles, before.openFiles + 1);
    EXPECT_EQ(during.threads, before.threads + 1);
    {
        const std::lock_guard lock(mutex);
        stop = true;
    }
    done.notify_all();
    thread.join();
    std::fclose(file);
    volatile char keep = block[kBytes / 2];
    (void)keep;
    block.reset();
    const ProcessResources after = sampleProcessResources();
    EXPECT_LT(after.heapInUseBytes, during.heapInUseBytes - kBytes / 2);
    EXPECT_EQ(after.openFiles, before.openFiles);
    EXPECT_EQ(after.threads, before.threads);
}

} // namespace
} // namespace chcrt
