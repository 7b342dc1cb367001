// The adaptive fallback's rule (culling/adaptive_choice.h), fed with synthetic trace times.
#include "culling/adaptive_choice.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

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

// Runs `traces` traces of fixed per-arm costs; returns the total time and counts the traces per arm.
double runArms(AdaptiveChoice& choice, int traces, const std::vector<double>& ms, std::vector<int>* counts = nullptr) {
    double total = 0.0;
    for (int i = 0; i < traces; ++i) {
        const uint32_t arm = choice.next();
        choice.report(arm, ms[arm], true);
        total += ms[arm];
        if (counts) ++(*counts)[arm];
    }
    return total;
}

TEST(RecentTimes, MedianOfTheLastFive) {
    RecentTimes t;
    EXPECT_FALSE(t.known());
    t.add(10.0);
    EXPECT_TRUE(t.known());
    EXPECT_DOUBLE_EQ(t.estimate(), 10.0);
    t.add(20.0);
    EXPECT_DOUBLE_EQ(t.estimate(), 15.0);
    t.add(100.0); // one outlier does not move the median
    EXPECT_DOUBLE_EQ(t.estimate(), 20.0);
    t.add(30.0); // 10, 20, 30, 100: the mean of the middle two
    EXPECT_DOUBLE_EQ(t.estimate(), 25.0);
    t.add(1.0);  // 1, 10, 20, 30, 100
    EXPECT_DOUBLE_EQ(t.estimate(), 20.0);
    t.add(2.0);  // 20, 100, 30, 1, 2: the oldest (10) is gone
    EXPECT_DOUBLE_EQ(t.estimate(), 20.0);
    t.add(3.0);  // 100, 30, 1, 2, 3
    EXPECT_DOUBLE_EQ(t.estimate(), 3.0);
}

TEST(AdaptiveChoice, NearlyEqualArmsDoNotSwapOnNoise) {
    AdaptiveChoice choice(2, 8);
    runArms(choice, 4, {10.0, 10.3}); // pure runs
    ASSERT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    // Culling now measures 2 % cheaper than pure: within the switch margin, pure keeps running.
    runArms(choice, 200, {10.0, 9.8});
    EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    // 10 % cheaper: it takes over.
    runArms(choice, 200, {10.0, 9.0});
    EXPECT_EQ(choice.best(), 1u);
}

TEST(AdaptiveChoice, StartsCullingThenMeasuresThePurePassTwice) {
    AdaptiveChoice choice(2, 8);
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

TEST(AdaptiveChoice, ProbesOfLosingArmsCostAtMostTheBudget) {
    for (const std::vector<double>& ms : {std::vector<double>{10.0, 13.0}, std::vector<double>{10.0, 30.0},
                                          std::vector<double>{10.0, 12.0, 25.0, 11.0},
                                          std::vector<double>{14.0, 10.0, 11.0}}) {
        AdaptiveChoice choice(uint32_t(ms.size()), 8, 0.03);
        runArms(choice, 40, ms); // start-up: every arm measured
        const double best = *std::min_element(ms.begin(), ms.end());
        const int traces = 2000;
        const double total = runArms(choice, traces, ms);
        EXPECT_LE(total, 1.03 * best * traces) << ms.size() << " arms, " << ms[1];
        EXPECT_GT(total, best * traces) << "losers are still probed";
        EXPECT_EQ(choice.best(), uint32_t(std::min_element(ms.begin(), ms.end()) - ms.begin()));
    }
}

TEST(AdaptiveChoice, ASlowerLoserWaitsLonger) {
    AdaptiveChoice choice(3, 8, 0.03);
    runArms(choice, 24, {10.0, 12.0, 30.0});
    EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    // Two losers: arm 1 (1.2x) every 2 * 0.2 / 0.03 = 14 traces, arm 2 (3x) every 2 * 2 / 0.03 = 134.
    EXPECT_EQ(choice.probeInterval(1), 14u);
    EXPECT_EQ(choice.probeInterval(2), 134u);
    std::vector<int> counts(3, 0);
    runArms(choice, 1340, {10.0, 12.0, 30.0}, &counts);
    // A loser runs after waiting a whole interval: once every interval + 1 traces.
    EXPECT_NEAR(counts[1], 1340 / 15, 2);
    EXPECT_NEAR(counts[2], 1340 / 135, 1);
}

TEST(AdaptiveChoice, TheIntervalHasAFloorAndACeiling) {
    AdaptiveChoice close(2, 8, 0.03);
    runArms(close, 4, {10.0, 10.1});
    EXPECT_EQ(close.probeInterval(1), 8u); // 0.01 / 0.03 rounds up to 1: the floor
    AdaptiveChoice far(2, 8, 0.03);
    runArms(far, 4, {1.0, 100.0});
    EXPECT_EQ(far.probeInterval(1), AdaptiveChoice::kMaxProbeInterval);
}

TEST(AdaptiveChoice, FurtherArmsAreMeasuredAfterTwoProbeIntervals) {
    AdaptiveChoice choice(4, 2);
    std::vector<uint32_t> order;
    for (int i = 0; i < 7; ++i) {
        order.push_back(choice.next());
        choice.report(order.back(), 10.0, true);
    }
    // The configured culling, the pure pass twice (its first trace is not counted), culling (best by the order of
    // arms) until 2 * 2 traces have run, then the other heights.
    EXPECT_EQ(order, (std::vector<uint32_t>{1, 0, 0, 1, 2, 3, 1}));
}

TEST(AdaptiveChoice, WinningCullingStillRemeasuresThePurePass) {
    AdaptiveChoice choice(2, 8);
    runArms(choice, 4, {10.0, 8.0});
    std::vector<int> counts(2, 0);
    runArms(choice, 90, {10.0, 8.0}, &counts);
    EXPECT_EQ(choice.probeInterval(0), 9u); // 0.25 / 0.03
    EXPECT_EQ(counts[0], 9);               // once every 9 + 1 traces
}

TEST(AdaptiveChoice, OneSlowPurePassDoesNotSwitchToCulling) {
    AdaptiveChoice choice(2, 8);
    run(choice, 5, 13.0, 10.0); // the pure pass measured at 10 three times, no probe due yet
    ASSERT_FALSE(choice.shouldCull());
    choice.tracedFull(40.0); // slowed down by another process
    EXPECT_FALSE(choice.shouldCull());
    EXPECT_DOUBLE_EQ(choice.fullTimes().estimate(), 10.0);
}

TEST(AdaptiveChoice, FollowsAViewWhereCullingStartsToPay) {
    AdaptiveChoice choice(2, 8);
    run(choice, 40, 13.0, 10.0);
    run(choice, 80, 5.0, 10.0); // the next probe wins; two more measurements move the median
    // Culling at half the pure time: the pure pass is re-measured every 1.0 / 0.03 = 34 traces.
    EXPECT_EQ(choice.best(), 1u);
    EXPECT_EQ(choice.probeInterval(AdaptiveChoice::kPureArm), 34u);
    std::vector<int> counts(2, 0);
    runArms(choice, 68, {10.0, 5.0}, &counts);
    EXPECT_EQ(counts[0], 2);
}

} // namespace
} // namespace chcrt::test
