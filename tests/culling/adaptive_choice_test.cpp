// The adaptive fallback's rule (culling/adaptive_choice.h), fed with synthetic trace times.
#include "culling/adaptive_choice.h"

#include <gtest/gtest.h>

namespace chcrt::test {
namespace {

// Runs `traces` traces with the given costs; returns how many culled.
int run(AdaptiveChoice& choice, int traces, double cullMs, double fullMs) {
    int culled = 0;
    for (int i = 0; i < traces; ++i) {
        if (choice.shouldCull()) {
            choice.culled(cullMs, true);
            ++culled;
        } else {
            choice.tracedFull(fullMs);
        }
    }
    return culled;
}

TEST(RecentTimes, MedianOfTheLastThree) {
    RecentTimes t;
    EXPECT_FALSE(t.known());
    t.add(10.0);
    EXPECT_TRUE(t.known());
    EXPECT_DOUBLE_EQ(t.estimate(), 10.0);
    t.add(20.0);
    EXPECT_DOUBLE_EQ(t.estimate(), 15.0);
    t.add(100.0); // one outlier does not move the median
    EXPECT_DOUBLE_EQ(t.estimate(), 20.0);
    t.add(30.0); // 20, 100, 30: the oldest (10) is gone
    EXPECT_DOUBLE_EQ(t.estimate(), 30.0);
    t.add(1.0);
    t.add(2.0); // 1, 2 and 30
    EXPECT_DOUBLE_EQ(t.estimate(), 2.0);
}

TEST(AdaptiveChoice, StartsCullingThenMeasuresThePurePassTwice) {
    AdaptiveChoice choice(8);
    EXPECT_TRUE(choice.shouldCull());
    choice.culled(50.0, false); // cold: not counted
    EXPECT_TRUE(choice.shouldCull());
    choice.culled(12.0, true);
    EXPECT_FALSE(choice.shouldCull());
    choice.tracedFull(99.0); // first pure pass: not counted
    EXPECT_FALSE(choice.fullTimes().known());
    EXPECT_FALSE(choice.shouldCull());
    choice.tracedFull(10.0);
    EXPECT_DOUBLE_EQ(choice.fullTimes().estimate(), 10.0);
    EXPECT_FALSE(choice.shouldCull()); // culling (12) loses
}

TEST(AdaptiveChoice, LosingCullingIsProbedLessAndLessOften) {
    AdaptiveChoice choice(8);
    run(choice, 4, 13.0, 10.0); // start-up
    // Probes after 8, 16, 32, then every 64 traces: few culled traces over a long walkthrough.
    const int culled = run(choice, 8 + 16 + 32 + 64 * 4, 13.0, 10.0);
    EXPECT_EQ(culled, 3 + 4);
    EXPECT_EQ(choice.probeInterval(), 64u);
}

TEST(AdaptiveChoice, WinningCullingStillRemeasuresThePurePass) {
    AdaptiveChoice choice(8);
    run(choice, 4, 8.0, 10.0);
    const int culled = run(choice, 80, 8.0, 10.0);
    EXPECT_EQ(culled, 70); // 7 of every 8 traces cull
    EXPECT_EQ(choice.probeInterval(), 8u);
}

TEST(AdaptiveChoice, OneSlowPurePassDoesNotSwitchToCulling) {
    AdaptiveChoice choice(8);
    run(choice, 5, 13.0, 10.0); // the pure pass measured at 10 three times, no probe due yet
    ASSERT_FALSE(choice.shouldCull());
    choice.tracedFull(40.0); // slowed down by another process
    EXPECT_FALSE(choice.shouldCull());
    EXPECT_DOUBLE_EQ(choice.fullTimes().estimate(), 10.0);
}

TEST(AdaptiveChoice, FollowsAViewWhereCullingStartsToPay) {
    AdaptiveChoice choice(8);
    run(choice, 40, 13.0, 10.0);
    run(choice, 80, 5.0, 10.0); // the next probe wins; two more measurements move the median
    EXPECT_EQ(run(choice, 16, 5.0, 10.0), 14);
}

} // namespace
} // namespace chcrt::test
