#ifndef CHCRT_CULLING_ADAPTIVE_CHOICE_H
#define CHCRT_CULLING_ADAPTIVE_CHOICE_H
// The adaptive choice of the CHC+RT tracer (ours, not in the paper; culling/README.md "Adaptive choice"): for one
// kind of rays, choose among ways of tracing — arm 0 is one pure full-screen pass, arms 1..n are culling
// configurations (termination heights, query modes) — from measured wall times, so that the tracer picks its own
// height and falls back to the pure pass where culling does not pay.
//
// Rule: arm 1 (the configured culling) and the pure pass are measured first (the pure pass's first trace is not
// counted: it compiles shaders and fills caches); the other culling arms once 2 * probeInterval traces have run,
// so that a short run does not spend itself exploring. Afterwards the
// arm with the lowest median of its last five times runs (another takes over once it is 5 % below), and each other arm is re-measured after an interval
// that keeps the expected cost of all probes under `probeBudget` of the trace time: an arm r times as slow as the
// best costs (r - 1) of a trace per probe, so with k losing arms it waits k (r - 1) / probeBudget traces (at
// least `probeInterval`, at most kMaxProbeInterval). Probes re-measure losers whose cost changed with the view;
// the running arm is measured every trace. Medians, not means: on shared machines one trace slowed down by
// another process otherwise flipped the choice.
#include <array>
#include <cstdint>
#include <vector>

namespace chcrt {

// The last five measured wall times of one way of tracing (five, not three: the ray sets of one kind differ —
// light samples, AO directions — and an arm is measured on whichever set it ran, so each time is noisier than
// the machine alone makes it).
class RecentTimes {
public:
    void add(double ms) { ms_[count_++ % ms_.size()] = ms; }
    bool known() const { return count_ > 0; }
    // Median of the last five (of an even count: the mean of the middle two).
    double estimate() const;

private:
    std::array<double, 5> ms_{};
    uint32_t count_ = 0;
};

class AdaptiveChoice {
public:
    static constexpr uint32_t kPureArm = 0;
    static constexpr uint32_t kMaxProbeInterval = 1024;
    static constexpr double kAllowedProbeCost = 0.03; // the share of trace time probing may cost at most
    // Another arm takes over only when its estimate is this much below the running arm's: near-equal arms would
    // otherwise swap on noise, and every swap runs the loser until its median moves.
    static constexpr double kSwitchMargin = 0.05;

    // `arms` >= 2: the pure pass and at least one culling configuration.
    explicit AdaptiveChoice(uint32_t arms = 2, uint32_t probeInterval = 8, double probeBudget = kAllowedProbeCost);

    // The arm the next trace should use.
    uint32_t next() const;
    // Report a trace of `arm`. `counted` false: not representative (a culling trace that started from cold
    // visibility fronts, a debug trace); the pure arm's first trace is never counted.
    void report(uint32_t arm, double ms, bool counted);

    uint32_t arms() const { return uint32_t(arms_.size()); }
    const RecentTimes& times(uint32_t arm) const { return arms_[arm].times; }
    // The running arm: after every arm was measured, the one with the lowest estimate, kept until another is
    // kSwitchMargin below it (kPureArm before any is measured).
    uint32_t best() const { return current_; }
    // Traces a losing arm waits between probes under the budget (its current value).
    uint32_t probeInterval(uint32_t arm) const;

    // The two-arm interface (pure pass or culling).
    bool shouldCull() const { return next() != kPureArm; }
    void culled(double ms, bool warm) { report(1, ms, warm); }
    void tracedFull(double ms) { report(kPureArm, ms, true); }
    const RecentTimes& cullTimes() const { return times(1); }
    const RecentTimes& fullTimes() const { return times(kPureArm); }

private:
    struct Arm {
        RecentTimes times;
        uint32_t since = 0; // traces since this arm last ran
        uint32_t runs = 0;
    };
    uint32_t lowest() const; // the arm with the lowest estimate among the measured ones
    std::vector<Arm> arms_;
    uint32_t base_;
    double budget_;
    uint32_t current_ = kPureArm;
    bool explored_ = false; // every arm has a measured time
    uint32_t traces_ = 0;
};

} // namespace chcrt
#endif
