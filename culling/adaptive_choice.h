#ifndef CHCRT_CULLING_ADAPTIVE_CHOICE_H
#define CHCRT_CULLING_ADAPTIVE_CHOICE_H
// The adaptive fallback of the CHC+RT tracer (ours, not in the paper; culling/README.md "Adaptive fallback"): for
// one kind of rays, choose between a CHC+RT trace (culling) and one pure full-screen pass from measured wall
// times, so that views where culling does not pay (far views on llvmpipe) lose as little as possible.
//
// Rule: cull until a warm culling time is known, then measure the pure pass (its first use is not counted: it
// compiles shaders and fills caches); afterwards take the cheaper one by the median of its last three times.
// While the pure pass wins, culling is re-probed after `probeInterval` traces, the interval doubling up to 8x
// while probes keep losing; while culling wins, the pure pass is re-measured every `probeInterval` traces (one
// low culling time measured under load must not lock culling in). Medians, not means: on the shared machines a
// single trace slowed down by other processes otherwise flipped the choice (culling/README.md).
#include <array>
#include <cstdint>

namespace chcrt {

// The last three measured wall times of one way of tracing.
class RecentTimes {
public:
    void add(double ms) { ms_[count_++ % ms_.size()] = ms; }
    bool known() const { return count_ > 0; }
    // Median of the last three (of two: their mean; of one: it).
    double estimate() const;

private:
    std::array<double, 3> ms_{};
    uint32_t count_ = 0;
};

class AdaptiveChoice {
public:
    explicit AdaptiveChoice(uint32_t probeInterval = 8) : base_(probeInterval < 1 ? 1 : probeInterval), interval_(base_) {}

    // True: the next trace should cull; false: one pure pass.
    bool shouldCull() const;
    // Report the trace that was run. `warm`: the culling trace continued existing visibility fronts (a cold
    // trace from the root pair is not representative and is not counted).
    void culled(double ms, bool warm);
    void tracedFull(double ms);

    const RecentTimes& cullTimes() const { return cull_; }
    const RecentTimes& fullTimes() const { return full_; }
    uint32_t probeInterval() const { return interval_; }

private:
    RecentTimes cull_, full_;
    uint32_t base_, interval_;
    uint32_t sinceProbe_ = 0; // traces since culling last ran
    uint32_t sinceFull_ = 0;  // traces since the pure pass last ran
    bool fullWarm_ = false;   // the first pure pass is not measured
};

} // namespace chcrt
#endif
