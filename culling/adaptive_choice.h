#ifndef CHCRT_CULLING_ADAPTIVE_CHOICE_H
#define CHCRT_CULLING_ADAPTIVE_CHOICE_H
// The adaptive choice of the CHC+RT tracer (ours, not in the paper; culling/README.md "Adaptive choice"): for one
// kind of rays, choose among ways of tracing — arm 0 is one pure full-screen pass, arms 1..n are culling
// configurations (termination heights) — from measured wall times, so that the tracer picks its own height and
// falls back to the pure pass where culling does not pay.
//
// Costs are relative to the pure pass on the same ray set: the ray sets of one kind differ (light samples, AO and
// diffuse directions per sample index), and an arm is measured on whichever set it ran, so absolute times compared
// a culling trace of a cheap set with a pure trace of an expensive one (the castle seen from above, 4 spp: AO culled
// half its traces at 0.74x of pure BVH). A culling trace of set s counts as its time over the lowest of the pure
// pass's last five times on s (below); a culling arm that is not running is traced only on sets the pure pass has a time for
// (else the pure pass runs).
//
// Rule: the pure pass is measured first (its first kWarmUpTraces traces are not counted: they compile shaders and
// fill caches; then kBaselineTraces counted ones; culling's first kWarmUpTraces are not counted either), then
// the configured culling (arm 1); the other culling arms only while some culling arm is within kExploreMargin of the
// pure pass and the probe ledger (below) affords their first traces, so that neither a short run nor a view where
// culling loses spends itself exploring. Afterwards the arm with the lowest median of its last five relative costs
// runs (an arm measured once within kRemeasureBelow of it is measured again at once, and so is an arm whose latest
// probe measured a win, until it takes over or a measurement says it would not); a culling arm takes over once it
// is kSwitchMargin below it on at least two measurements, the pure pass once it is below it at all; and each other measured
// arm is re-measured after an interval that keeps the expected cost of all probes under `probeBudget` of the trace
// time: an arm r times as slow as the best costs (r - 1) of a trace per probe, so with k losing arms it waits
// k (r - 1) / probeBudget traces (at least `probeInterval`, at most kMaxProbeInterval). Medians, not means: on shared
// machines one trace slowed down by another process otherwise flipped the choice. A culling trace's cost is relative
// to the lowest of the pure pass's last five times on its set: noise only adds, and a baseline raised by one slow
// pure trace made culling that lost look like a win.
//
// Seeded ray sets: a culling trace of a set without hit hints is cold and not counted, so an arm that does not run
// traces such a set only while fewer than kSeedSets sets of the kind have hints (RaySetHints, from the tracer); the
// running arm traces the others.
//
// The probe ledger: the intervals above bound probes by estimates, but where culling nearly ties, a short run's
// probes are mostly first traces — cold ones (1.2-1.6x of the pure pass, building another height's hierarchy) and
// re-measurements — that no interval spaces out. Every trace of a culling arm, counted or not, books its time beyond
// the pure pass's on its set (a winning culling books savings); exploring a further height and probing a losing
// further height are allowed only while the booked excess, with the trace's expected excess, stays within the budget
// of the pure pass's time for all traces so far. Exempt: the configured culling's first measurement (without it
// culling would never start) and the second measurement of an arm measured once (one slowed trace must not keep a
// winning culling out). (City and interior far primary rays, 32 traces per process: 0.94x and 0.92x of pure BVH with
// further heights explored after 16 traces; docs/benchmarks.md, 2026-12-05.) The configured culling itself is left to
// the ledger for neither: its start-up (its traces up to its first measurement, which a run pays once) books no
// excess, and once measured it is probed when its interval says (it has no cold trace left); booked, a shadow kind's
// 16 hint-less first traces and a few slowed measurements kept a culling that wins 2x out of whole runs
// (culling/README.md, "Adaptive choice").
#include <array>
#include <cstdint>
#include <map>
#include <vector>

namespace chcrt {

// The last five measured values (times, or costs relative to the pure pass) of one way of tracing.
class RecentTimes {
public:
    void add(double ms) { ms_[count_++ % ms_.size()] = ms; }
    bool known() const { return count_ > 0; }
    uint32_t count() const { return count_; }
    // Median of the last five (of four: the mean of the middle two); of two, the lower: timing noise on a shared
    // machine only ever adds, and with two values a median is their mean, which one slowed trace still dominates.
    double estimate() const;
    double lowest() const; // of the last five
    double latest() const { return count_ == 0 ? 0.0 : ms_[(count_ - 1) % ms_.size()]; }

private:
    std::array<double, 5> ms_{};
    uint32_t count_ = 0;
};

// What the tracer knows of the hit hints of a trace's ray set (culling/README.md "Hit hints";
// AdaptiveChoice::kSeedSets).
struct RaySetHints {
    bool set = true;     // the set has hints (or its kind uses none): a culling trace of it can be counted
    uint32_t ofKind = 0; // sets of the kind that have hints
};

class AdaptiveChoice {
public:
    static constexpr uint32_t kPureArm = 0;
    // Traces not counted at the start, of the pure pass and of culling (all culling arms together; a further arm's
    // own first trace is cold too, which the tracer reports). The second trace can still be warming up: on the
    // interior's far path the pure pass's measured 18.8 ms where `bvh` traced the same rays in 13.3 ms, and culling
    // at 14.1 ms then counted as 0.75x and ran for the whole 32-trace run at 0.93x of pure BVH; on its near path
    // culling's second trace took 12.1 ms against 7.6-8.4 ms from the third on, and counted as 1.27x it kept out, for
    // the whole run, a culling that runs at 1.25x of pure BVH (docs/benchmarks.md, 2026-12-05).
    static constexpr uint32_t kWarmUpTraces = 2;
    // Counted traces of the pure pass before culling is measured against it. With one, a baseline slowed by another
    // process made culling look cheaper and run (the city's far primary rays: a pure pass at 16.6 ms against 15.1 ms
    // later, culling at 0.91x of it, then 22 traces until the pure pass was probed again; 0.88x of pure BVH in one
    // process of 24, docs/benchmarks.md, 2026-12-06).
    static constexpr uint32_t kBaselineTraces = 2;
    static constexpr uint32_t kMaxProbeInterval = 1024;
    static constexpr double kAllowedProbeCost = 0.03; // the share of trace time probing may cost at most
    // A culling arm takes over only when its estimate is this much below the running arm's (and it was measured at
    // least twice): near-equal arms would otherwise swap on noise, and every swap runs the loser until its median
    // moves. The pure pass needs no margin: it takes over once a running culling arm's estimate exceeds it.
    static constexpr double kSwitchMargin = 0.05;
    // Further culling arms are explored only while some measured culling arm costs at most this much more than the
    // pure pass: other heights of a culling that loses by more rarely win, and each first trace of one is a probe.
    static constexpr double kExploreMargin = 0.10;
    // An arm measured once that costs less than this times the running arm is measured again at once (with two
    // values the lower counts): one trace slowed by another process must not keep a winning culling out for a whole
    // probe interval, while an arm that loses by more is not worth the extra trace.
    static constexpr double kRemeasureBelow = 1.5;
    // What the ledger expects the first (cold) trace of a culling arm not yet measured to cost relative to the pure
    // pass: cold traces measured 1.2-1.6x (docs/benchmarks.md, 2026-12-05 · 3652eba).
    static constexpr double kColdTraceCost = 1.5;
    // Ray sets a culling arm that does not run traces while they have no hit hints (next's `hints`): such a trace is
    // cold (not counted) and only seeds its set for a measurement a frame later, so only this many sets of the kind
    // are seeded (the first kWarmUpTraces culling traces compile, and so does the first hint pass: one more), and
    // the running arm traces the others. Seeding every set cost the castle's street view (20 AO ray sets, one view,
    // culling losing) a cold culling trace per set: 0.96x and 0.99x of pure BVH.
    static constexpr uint32_t kSeedSets = kWarmUpTraces + 1;

    // `arms` >= 2: the pure pass and at least one culling configuration.
    explicit AdaptiveChoice(uint32_t arms = 2, uint32_t probeInterval = 8, double probeBudget = kAllowedProbeCost);

    // The arm the next trace, of ray set `set`, should use.
    uint32_t next(uint32_t set = 0, RaySetHints hints = {}) const;
    // Report a trace of `arm` on ray set `set` (e.g. the sample index). `counted` false: not representative (a
    // culling trace that started from cold visibility fronts, a debug trace); the pure arm's first trace is never
    // counted.
    void report(uint32_t arm, double ms, bool counted, uint32_t set = 0);

    uint32_t arms() const { return uint32_t(arms_.size()); }
    // Whether the arm has a cost, and its estimate relative to the pure pass (1 for the pure pass itself).
    bool measured(uint32_t arm) const;
    double relativeCost(uint32_t arm) const;
    // The pure pass's recent times over all sets (ms).
    const RecentTimes& pureTimes() const { return pureAll_; }
    // The running arm: once the pure pass and the configured culling are measured, the one with the lowest estimate,
    // kept until a culling arm is kSwitchMargin below it, or the pure pass below it at all (kPureArm before).
    uint32_t best() const { return current_; }
    // Traces a losing arm waits between probes under the budget (its current value).
    uint32_t probeInterval(uint32_t arm) const;
    // The ledger: time culling traces took beyond the pure pass on their sets (negative where culling saved), and
    // the pure pass's time for all traces so far (ms).
    double excessMs() const { return excessMs_; }
    double pureEquivalentMs() const { return pureEquivalentMs_; }

private:
    struct Arm {
        RecentTimes relative; // culling arms: cost relative to the pure pass on the same set
        uint32_t since = 0;   // traces since this arm last ran
        uint32_t runs = 0;
    };
    uint32_t lowest() const; // the measured arm with the lowest estimate
    double bestCullingCost() const; // the lowest estimate of a measured culling arm, 0 when none is measured
    uint32_t choose(uint32_t set) const; // next() before the check for the set's baseline
    // Whether the ledger affords a trace of `arm` on `set` beyond what the running arm would take.
    bool affordable(uint32_t arm, uint32_t set) const;
    double baseline(uint32_t set) const; // the pure pass's time on `set` (ms), 0 when it has none at all
    double ledgerBase(uint32_t set) const; // what the ledger books as the pure pass's time on `set` (ms), else 0
    std::vector<Arm> arms_;
    std::map<uint32_t, RecentTimes> pureBySet_;
    RecentTimes pureAll_;
    uint32_t base_;
    double budget_;
    uint32_t current_ = kPureArm;
    uint32_t cullingTraces_ = 0; // traces of all culling arms
    double excessMs_ = 0.0;
    double pureEquivalentMs_ = 0.0;
};

} // namespace chcrt
#endif
