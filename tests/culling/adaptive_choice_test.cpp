// The adaptive fallback's rule (culling/adaptive_choice.h), fed with synthetic trace times.
#include "culling/adaptive_choice.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

namespace chcrt::test {
namespace {

// Runs `traces` traces of fixed per-arm costs on ray set 0; returns the total time and counts the traces per arm.
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
    EXPECT_DOUBLE_EQ(t.estimate(), 10.0); // of two, the lower (noise only adds)
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
    EXPECT_EQ(t.count(), 7u);
}

TEST(AdaptiveChoice, MeasuresThePurePassFourTimesThenCullingThrice) {
    AdaptiveChoice choice(2, 8);
    EXPECT_EQ(choice.next(), AdaptiveChoice::kPureArm);
    choice.report(0, 99.0, true); // first pure pass: not counted (compiles)
    EXPECT_FALSE(choice.measured(0));
    EXPECT_EQ(choice.next(), AdaptiveChoice::kPureArm);
    choice.report(0, 15.0, true); // second: not counted either (still warming up)
    EXPECT_FALSE(choice.measured(0));
    EXPECT_EQ(choice.next(), AdaptiveChoice::kPureArm);
    choice.report(0, 10.0, true);
    EXPECT_DOUBLE_EQ(choice.pureTimes().estimate(), 10.0);
    EXPECT_EQ(choice.next(), AdaptiveChoice::kPureArm); // a baseline of kBaselineTraces counted traces
    choice.report(0, 11.0, true);
    EXPECT_DOUBLE_EQ(choice.pureTimes().estimate(), 10.0); // the lower of two
    EXPECT_EQ(choice.next(), 1u);
    choice.report(1, 50.0, false); // cold: not counted
    EXPECT_EQ(choice.next(), 1u);
    choice.report(1, 15.0, true); // culling's second trace: not counted either (still warming up)
    EXPECT_FALSE(choice.measured(1));
    EXPECT_EQ(choice.next(), 1u);
    choice.report(1, 12.0, true);
    EXPECT_DOUBLE_EQ(choice.relativeCost(1), 1.2);
    EXPECT_EQ(choice.next(), 1u); // culling (1.2x) loses, by less than kRemeasureBelow: measured again at once
    choice.report(1, 13.0, true);
    EXPECT_DOUBLE_EQ(choice.relativeCost(1), 1.2); // the lower of two
    EXPECT_EQ(choice.next(), AdaptiveChoice::kPureArm);
}

TEST(AdaptiveChoice, OneSlowedCullingTraceDoesNotKeepAWinningCullingOut) {
    // Culling at 0.7x of the pure pass, its first counted trace (after a cold one and a warm-up) slowed by another
    // process to 1.4x: measured again at once, it runs from the next trace on. Losing by more than kRemeasureBelow,
    // it waits for its probe interval.
    AdaptiveChoice choice(2, 8);
    const std::vector<double> culling = {50.0, 14.0, 14.0, 7.0, 7.0, 7.0};
    std::vector<uint32_t> order;
    size_t c = 0;
    for (int i = 0; i < 8; ++i) {
        const uint32_t arm = choice.next();
        order.push_back(arm);
        choice.report(arm, arm == 0 ? 10.0 : culling[std::min(c, culling.size() - 1)], arm == 0 || c > 0);
        c += arm == 1;
    }
    EXPECT_EQ(order, (std::vector<uint32_t>{0, 0, 0, 0, 1, 1, 1, 1}));
    AdaptiveChoice slow(2, 8);
    runArms(slow, 7, {10.0, 16.0}); // pure twice (not counted), twice, culling twice (not counted), culling at 1.6x
    EXPECT_EQ(slow.next(), AdaptiveChoice::kPureArm);
}

TEST(AdaptiveChoice, AProbeThatWinsIsMeasuredAgainAtOnce) {
    // Culling at 0.5x of the pure pass runs; a slowed period makes three of its traces 1.3x, and the pure pass takes
    // over (the median of the last five says 1.3x). Once the period is over, the first probe (after the interval
    // for 1.3x: 0.3 / 0.015 = 20 traces) measures 0.5x, and the arm is measured again at once until it takes over;
    // probed at its interval instead, each probe replaced one slowed value, and culling ran again after ~60 traces.
    AdaptiveChoice choice(2, 8, 0.015);
    runArms(choice, 20, {10.0, 5.0});
    ASSERT_EQ(choice.best(), 1u);
    for (int i = 0; i < 3; ++i) {
        const uint32_t arm = choice.next();
        choice.report(arm, arm == 0 ? 10.0 : 13.0, true);
    }
    ASSERT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    int traces = 0;
    while (choice.best() != 1u && traces < 200) traces += int(runArms(choice, 1, {10.0, 5.0}) > 0.0);
    EXPECT_LE(traces, 24);
}

TEST(AdaptiveChoice, AWinnerIsConfirmedAtOnceAndTakesOverOnTwoMeasurements) {
    AdaptiveChoice choice(2, 8);
    runArms(choice, 7, {10.0, 5.0}); // pure four times, culling thrice (measured once)
    EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm); // one measurement does not switch
    EXPECT_EQ(choice.next(), 1u);                       // but it is measured again at once
    runArms(choice, 1, {10.0, 5.0});
    EXPECT_EQ(choice.best(), 1u);
}

TEST(AdaptiveChoice, NearlyEqualArmsDoNotSwapOnNoise) {
    AdaptiveChoice choice(2, 8);
    runArms(choice, 6, {10.0, 10.3}); // pure runs
    ASSERT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    // Culling now measures 2 % cheaper than pure: within the switch margin, pure keeps running.
    runArms(choice, 200, {10.0, 9.8});
    EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    // 10 % cheaper: it takes over.
    runArms(choice, 200, {10.0, 9.0});
    EXPECT_EQ(choice.best(), 1u);
}

// The margin protects the pure pass, not a culling that stopped paying: once a running culling arm's estimate exceeds
// the pure pass's, the pure pass takes over (a culling that nearly ties must not stay on at up to 1.05x).
TEST(AdaptiveChoice, ACullingThatStopsPayingHandsBackToThePurePassAtOnce) {
    AdaptiveChoice choice(2, 8);
    runArms(choice, 12, {10.0, 9.0});
    ASSERT_EQ(choice.best(), 1u);
    runArms(choice, 2, {10.0, 10.3}); // 3 % slower: within the margin, but slower
    EXPECT_EQ(choice.best(), 1u);     // the median of the last five still says 0.9
    runArms(choice, 3, {10.0, 10.3});
    EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    std::vector<int> counts(2, 0);
    runArms(choice, 100, {10.0, 10.3}, &counts);
    EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    EXPECT_LE(counts[1], 100 / 8 + 1) << "the losing culling is only probed, once per interval of 8 traces";
}

TEST(AdaptiveChoice, ProbesOfLosingArmsCostAtMostTheBudget) {
    for (const std::vector<double>& ms : {std::vector<double>{10.0, 13.0}, std::vector<double>{10.0, 30.0},
                                          std::vector<double>{10.0, 10.5, 25.0, 11.0},
                                          std::vector<double>{14.0, 10.0, 11.0}}) {
        AdaptiveChoice choice(uint32_t(ms.size()), 8, 0.03);
        runArms(choice, 40, ms); // start-up: every arm measured that is explored
        const double best = *std::min_element(ms.begin(), ms.end());
        const int traces = 2000;
        const double total = runArms(choice, traces, ms);
        EXPECT_LE(total, 1.03 * best * traces) << ms.size() << " arms, " << ms[1];
        EXPECT_GT(total, best * traces) << "losers are still probed";
        EXPECT_EQ(choice.best(), uint32_t(std::min_element(ms.begin(), ms.end()) - ms.begin()));
    }
}

TEST(AdaptiveChoice, ProbingCostsAtMostTheBudgetOnAShortRunWhereCullingLoses) {
    // 32 traces of one kind (8 frames at 4 spp), culling 1.05x to 1.3x slower at every height, the first trace of
    // each culling configuration not counted (it starts cold), the first measured one confirmed (it lost by less than
    // kRemeasureBelow): the pure pass runs, the other heights are not explored — within kExploreMargin (1.05x, 1.1x)
    // because the ledger cannot afford their cold traces. (A culling 1.3x as slow costs four of its traces — the cold
    // one, a warm-up and two measured —, within the budget from 40 traces on; one twice as slow three, from 100.)
    for (const auto& [slower, traces] : {std::pair{1.05, 32}, std::pair{1.1, 32}, std::pair{1.15, 32},
                                         std::pair{1.3, 40}, std::pair{2.0, 128}}) {
        AdaptiveChoice choice(4, 8, 0.015);
        std::vector<int> runs(4, 0);
        double total = 0.0;
        for (int i = 0; i < traces; ++i) {
            const uint32_t arm = choice.next();
            const double ms = arm == 0 ? 10.0 : 10.0 * slower;
            choice.report(arm, ms, arm == 0 || runs[arm] > 0);
            ++runs[arm];
            total += ms;
        }
        EXPECT_EQ(runs[2] + runs[3], 0) << slower;
        EXPECT_LE(total, 1.03 * 10.0 * traces) << slower;
    }
}

TEST(AdaptiveChoice, FurtherArmsAreMeasuredOnlyWhenCullingComesClose) {
    AdaptiveChoice close(4, 2);
    std::vector<uint32_t> order;
    for (int i = 0; i < 10; ++i) {
        order.push_back(close.next());
        close.report(order.back(), order.back() == 0 ? 10.0 : 8.0, true);
    }
    // The pure pass four times and the configured culling thrice (the first two traces of each are not counted;
    // culling wins), culling measured again (a winner is confirmed at once), then the other heights, each measured
    // again before the next is explored — as soon as the culling's savings since its start-up (which the ledger does
    // not book) cover what exploring may cost (kColdTraceCost: half a pure trace beyond it), here after two traces.
    EXPECT_EQ(order, (std::vector<uint32_t>{0, 0, 0, 0, 1, 1, 1, 1, 1, 2}));
    AdaptiveChoice far(4, 2);
    std::vector<int> runs(4, 0);
    runArms(far, 200, {10.0, 12.0, 12.0, 12.0}, &runs);
    EXPECT_EQ(runs[2] + runs[3], 0); // 1.2x: beyond the exploration margin
    EXPECT_GT(runs[1], 1);           // but re-probed
}

TEST(AdaptiveChoice, TheLedgerKeepsProbesWhereCullingTiesWithinTheBudget) {
    // Culling 1.05x of the pure pass at every height, each height's first trace cold at 1.5x: a short run explores
    // nothing beyond the configured height; a long one explores the others once the pure pass's time affords their
    // cold traces, and its probes stay within the budget throughout.
    AdaptiveChoice choice(4, 8, 0.015);
    std::vector<int> runs(4, 0);
    double total = 0.0;
    for (int i = 1; i <= 4000; ++i) {
        const uint32_t arm = choice.next();
        const double ms = arm == 0 ? 10.0 : (runs[arm] == 0 ? 15.0 : 10.5);
        choice.report(arm, ms, arm == 0 || runs[arm] > 0);
        ++runs[arm];
        total += ms;
        if (i == 32) {
            EXPECT_EQ(runs[2] + runs[3], 0);
        }
        // Beyond the budget: the configured culling's first two traces (exempt) and one trace's excess.
        EXPECT_LE(choice.excessMs(), 0.015 * choice.pureEquivalentMs() + 5.5 + 0.5) << i;
    }
    EXPECT_GT(runs[2], 1);
    EXPECT_GT(runs[3], 1);
    EXPECT_LE(total, 1.015 * 10.0 * 4000 + 10.0);
    EXPECT_DOUBLE_EQ(choice.pureEquivalentMs(), 10.0 * (4000 - 2)); // every trace but the pure pass's warm-up
}

// A ray kind of `sets` ray sets traced in turn, as the tracer runs it: `traces` traces, pure passes of `pureMs`; a
// culled trace of a set without hints yet is cold (`firstColdMs` the very first, compiling, then `coldMs`), reported
// not counted, and gives the set hints; other culled traces take `culledMs(arm)`. `reportHints` false: the choice is
// not told which sets have hints.
struct KindRun {
    int culled = 0, cold = 0;
    double total = 0.0;
};
KindRun runKind(AdaptiveChoice& choice, uint32_t sets, int traces, double pureMs, double firstColdMs, double coldMs,
                const std::function<double(uint32_t)>& culledMs, bool reportHints = true) {
    std::vector<bool> hinted(sets, false);
    KindRun run;
    for (int i = 0; i < traces; ++i) {
        const uint32_t set = uint32_t(i) % sets;
        const RaySetHints hints{hinted[set], uint32_t(std::count(hinted.begin(), hinted.end(), true))};
        const uint32_t arm = choice.next(set, reportHints ? hints : RaySetHints{});
        double ms = pureMs;
        bool counted = true;
        if (arm != AdaptiveChoice::kPureArm) {
            ++run.culled;
            if (!hinted[set]) {
                ms = run.cold++ == 0 ? firstColdMs : coldMs;
                counted = false;
                hinted[set] = true;
            } else {
                ms = culledMs(arm);
            }
        }
        choice.report(arm, ms, counted, set);
        run.total += ms;
    }
    return run;
}

// A shadow kind at 16 spp through 8 frames x 4 runs (the interior's near path): 512 traces of 16 ray sets, pure
// passes of 5 ms, culling 2.5 ms (other heights 2.6 ms) on a set that has hints, a cold trace 6.5 ms (the very first
// 17 ms); the first measured culling traces are slowed by another process to `slowed` times the pure pass. Returns the
// culled traces; `total` the time.
int runSlowedShadowKind(const std::vector<double>& slowed, double& total) {
    AdaptiveChoice choice(4, 8, 0.015);
    size_t measuredTraces = 0;
    const KindRun run = runKind(choice, 16, 512, 5.0, 17.0, 6.5, [&](uint32_t arm) {
        const size_t i = measuredTraces++;
        return i < slowed.size() ? slowed[i] * 5.0 : (arm == 1 ? 2.5 : 2.6);
    });
    total = run.total;
    return run.culled;
}

TEST(AdaptiveChoice, SlowedFirstMeasurementsAfterACostlyStartDoNotKeepCullingOut) {
    // Two measurements slowed to 1.23x and 1.05x after the start-up (seen on the interior's near shadow rays): with
    // every set seeded, the start-up booked in the ledger and the configured culling's probes left to it, no probe
    // was affordable again and the pure pass ran the rest of the run (47 of 512 traces culled). With kSeedSets the
    // start-up is three cold traces, and culling takes over again (465 culled).
    double total = 0.0;
    EXPECT_GE(runSlowedShadowKind({1.23, 1.05}, total), 512 * 3 / 4);
    EXPECT_LE(total, 0.65 * 5.0 * 512);
    // Eight slowed over two frames of a loaded machine (culling's estimate then stands above the pure pass's):
    // culling takes over again within the run (317 of 512 traced; 358 with every set seeded at the start, whose
    // probes need not wait for a seeded set), which needs both the start-up left out of the ledger and the
    // configured culling probed by its interval alone (each alone: 105 or 88 culled).
    EXPECT_GE(runSlowedShadowKind({1.41, 0.85, 1.67, 1.0, 1.85, 1.2, 1.2, 1.2}, total), 512 * 3 / 5);
    EXPECT_LE(total, 0.75 * 5.0 * 512);
}

// An AO kind of 20 ray sets over `views` traces of each set (the castle's street view, 8 runs after a warm-up):
// pure passes of 10 ms, culling `culling` times that on a set that has hints, 1.6x on a cold trace (the very first 3x,
// compiling). `reportHints` false: the choice is not told which sets have hints (every set may be seeded). Returns the
// culled traces and the cold ones; `total` the time.
std::pair<int, int> runAoKind(double culling, int views, bool reportHints, double& total) {
    AdaptiveChoice choice(4, 8);
    const KindRun run = runKind(choice, 20, 20 * views, 10.0, 30.0, 16.0, [&](uint32_t) { return culling * 10.0; },
                                reportHints);
    total = run.total;
    return {run.culled, run.cold};
}

TEST(AdaptiveChoice, ALosingCullingSeedsFewRaySetsWithHints) {
    // Culling at 1.1x: kSeedSets cold traces, then measurements and probes on the seeded sets only; the run costs
    // the probe budget and the seeds over pure passes (2.9 % in all). Told nothing of hints, the choice seeds every
    // set and costs 9.6 % more than pure passes.
    double total = 0.0;
    const auto [culled, cold] = runAoKind(1.1, 9, true, total);
    EXPECT_EQ(cold, int(AdaptiveChoice::kSeedSets));
    EXPECT_LE(total, 1.03 * 10.0 * 180 + 20.0 + 2 * 6.0);
    EXPECT_LE(culled, 180 / 7); // the seeds, two measurements, then a probe of each culling arm per view
    double unseeded = 0.0;
    EXPECT_EQ(runAoKind(1.1, 9, false, unseeded).second, 20); // control: every set seeded
    EXPECT_GT(unseeded, 1.05 * 10.0 * 180);
    // Culling at 0.5x: measured in the third view, it takes over and seeds every other set then.
    const auto [culledWinning, coldWinning] = runAoKind(0.5, 9, true, total);
    EXPECT_EQ(coldWinning, 20);
    EXPECT_GE(culledWinning, 180 - 20 - 17 - 8);
    EXPECT_LE(total, 0.75 * 10.0 * 180);
}

TEST(AdaptiveChoice, CostsAreComparedOnTheSameRaySet) {
    // Two ray sets of very different cost, traced alternately; culling is 1.2x the pure pass on each. Compared by
    // absolute time, a culling trace of the cheap set beat the pure pass of the expensive one.
    AdaptiveChoice choice(2, 8, 0.03);
    const double pure[2] = {5.0, 20.0};
    int culled = 0;
    for (int i = 0; i < 400; ++i) {
        const uint32_t set = uint32_t(i % 2);
        const uint32_t arm = choice.next(set);
        choice.report(arm, arm == 0 ? pure[set] : 1.2 * pure[set], true, set);
        culled += arm != 0;
        EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm) << "trace " << i;
    }
    EXPECT_NEAR(choice.relativeCost(1), 1.2, 1e-9);
    // The start-up and two measurements, then only probes: every 8 traces (the floor; 0.2 / 0.03 = 7).
    EXPECT_LE(culled, 400 / 9 + 3);
}

TEST(AdaptiveChoice, CullingIsMeasuredOnlyOnSetsThePurePassWasMeasuredOn) {
    AdaptiveChoice choice(2, 8);
    choice.report(0, 99.0, true, 0); // not counted
    choice.report(0, 15.0, true, 0); // not counted
    choice.report(0, 10.0, true, 1);
    EXPECT_EQ(choice.next(1), AdaptiveChoice::kPureArm); // one counted pure trace is not yet a baseline
    choice.report(0, 11.0, true, 3);
    choice.report(1, 50.0, false, 1); // culling's two warm-up traces
    choice.report(1, 15.0, true, 1);
    EXPECT_EQ(choice.next(2), AdaptiveChoice::kPureArm); // set 2 has no pure time yet
    EXPECT_EQ(choice.next(1), 1u);
    choice.report(1, 30.0, true, 2); // a culling trace of a set without a baseline is not counted
    EXPECT_FALSE(choice.measured(1));
    choice.report(1, 12.0, true, 1);
    EXPECT_DOUBLE_EQ(choice.relativeCost(1), 1.2);
}

TEST(AdaptiveChoice, CullingIsCostedAgainstTheLowestRecentPureTime) {
    // Slow pure traces (noise only adds) must not make a losing culling look like a win: against the median (14 ms)
    // culling at 12 ms would count as 0.86x and take over; against the lowest (10 ms) it is 1.2x.
    AdaptiveChoice choice(2, 8);
    choice.report(0, 99.0, true); // warm-up
    choice.report(0, 99.0, true); // warm-up
    for (double ms : {10.0, 14.0, 14.0}) choice.report(0, ms, true);
    choice.report(1, 99.0, true); // warm-up
    choice.report(1, 99.0, true); // warm-up
    choice.report(1, 12.0, true);
    choice.report(1, 12.0, true);
    EXPECT_DOUBLE_EQ(choice.relativeCost(1), 1.2);
    EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm);
}

TEST(AdaptiveChoice, ASlowerLoserWaitsLonger) {
    // Culling wins (10 ms against 12): the pure pass and a slower height are the losers, and the ledger, holding the
    // savings, lets the intervals alone space their probes.
    AdaptiveChoice choice(3, 8, 0.03);
    runArms(choice, 24, {12.0, 10.0, 30.0});
    EXPECT_EQ(choice.best(), 1u);
    // Relative to the winner, the pure pass is 1.2x: every 2 * 0.2 / 0.03 = 13.3 -> 14 traces; arm 2 (3x) every
    // 2 * 2 / 0.03 = 134.
    EXPECT_EQ(choice.probeInterval(0), 14u);
    EXPECT_EQ(choice.probeInterval(2), 134u);
    std::vector<int> counts(3, 0);
    runArms(choice, 1350, {12.0, 10.0, 30.0}, &counts);
    // A loser runs after waiting a whole interval: once every interval + 1 traces.
    EXPECT_NEAR(counts[0], 1350 / 15, 3);
    EXPECT_NEAR(counts[2], 1350 / 135, 1);
}

TEST(AdaptiveChoice, TheIntervalHasAFloorAndACeiling) {
    AdaptiveChoice close(2, 8, 0.03);
    runArms(close, 7, {10.0, 10.1});
    EXPECT_EQ(close.probeInterval(1), 8u); // 0.01 / 0.03 rounds up to 1: the floor
    AdaptiveChoice far(2, 8, 0.03);
    runArms(far, 7, {1.0, 100.0});
    EXPECT_EQ(far.probeInterval(1), AdaptiveChoice::kMaxProbeInterval);
}

TEST(AdaptiveChoice, WinningCullingStillRemeasuresThePurePass) {
    AdaptiveChoice choice(2, 8);
    runArms(choice, 8, {10.0, 8.0});
    ASSERT_EQ(choice.best(), 1u);
    std::vector<int> counts(2, 0);
    runArms(choice, 90, {10.0, 8.0}, &counts);
    EXPECT_EQ(choice.probeInterval(0), 9u); // 0.25 / 0.03
    EXPECT_EQ(counts[0], 9);               // once every 9 + 1 traces
}

TEST(AdaptiveChoice, OneSlowPurePassDoesNotSwitchToCulling) {
    AdaptiveChoice choice(2, 8);
    runArms(choice, 6, {10.0, 13.0}); // the pure pass measured at 10 several times
    ASSERT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    choice.report(0, 40.0, true); // slowed down by another process
    EXPECT_EQ(choice.best(), AdaptiveChoice::kPureArm);
    EXPECT_DOUBLE_EQ(choice.pureTimes().estimate(), 10.0);
}

TEST(AdaptiveChoice, FollowsAViewWhereCullingStartsToPay) {
    AdaptiveChoice choice(2, 8);
    runArms(choice, 40, {10.0, 13.0});
    runArms(choice, 80, {10.0, 5.0}); // the next probe wins, is confirmed at once and takes over
    // Culling at half the pure time: the pure pass is re-measured every 1.0 / 0.03 = 34 traces.
    EXPECT_EQ(choice.best(), 1u);
    EXPECT_EQ(choice.probeInterval(AdaptiveChoice::kPureArm), 34u);
    std::vector<int> counts(2, 0);
    runArms(choice, 70, {10.0, 5.0}, &counts);
    EXPECT_EQ(counts[0], 2);
}

} // namespace
} // namespace chcrt::test
