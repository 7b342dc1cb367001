#include "culling/adaptive_choice.h"

#include <algorithm>
#include <cmath>

namespace chcrt {

double RecentTimes::estimate() const {
    const size_t n = std::min<size_t>(count_, ms_.size());
    if (n == 0) return 0.0;
    std::array<double, 5> sorted = ms_;
    std::sort(sorted.begin(), sorted.begin() + n);
    return n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
}

AdaptiveChoice::AdaptiveChoice(uint32_t arms, uint32_t probeInterval, double probeBudget)
    : arms_(std::max<uint32_t>(arms, 2)), base_(std::max<uint32_t>(probeInterval, 1)),
      budget_(probeBudget > 0.0 ? probeBudget : kAllowedProbeCost) {}

uint32_t AdaptiveChoice::lowest() const {
    uint32_t best = kPureArm;
    double bestMs = 0.0;
    bool any = false;
    for (uint32_t a = 0; a < arms_.size(); ++a) {
        if (!arms_[a].times.known()) continue;
        const double ms = arms_[a].times.estimate();
        if (!any || ms < bestMs) best = a, bestMs = ms, any = true;
    }
    return best;
}

uint32_t AdaptiveChoice::probeInterval(uint32_t arm) const {
    const uint32_t winner = best();
    if (arm == winner || !arms_[arm].times.known() || !arms_[winner].times.known()) return base_;
    const double bestMs = arms_[winner].times.estimate();
    const double ratio = bestMs > 0.0 ? arms_[arm].times.estimate() / bestMs : 1.0;
    const double losers = double(arms_.size() - 1);
    const double wait = std::ceil(losers * std::max(ratio - 1.0, 0.0) / budget_);
    return uint32_t(std::clamp(wait, double(base_), double(kMaxProbeInterval)));
}

uint32_t AdaptiveChoice::next() const {
    // The configured culling and the pure pass first; the further arms once 2 * probeInterval traces have run, so
    // that a short run does not spend itself on them.
    if (!arms_[1].times.known()) return 1;
    if (!arms_[kPureArm].times.known()) return kPureArm;
    for (uint32_t a = 2; a < arms_.size(); ++a) {
        if (!arms_[a].times.known() && traces_ >= 2 * base_) return a;
    }
    // The most overdue probe, else the best arm.
    const uint32_t winner = best();
    uint32_t probe = winner;
    double overdue = 0.0;
    for (uint32_t a = 0; a < arms_.size(); ++a) {
        if (a == winner || !arms_[a].times.known()) continue;
        const double due = double(arms_[a].since) / double(probeInterval(a)); // waited a whole interval
        if (due >= 1.0 && due > overdue) probe = a, overdue = due;
    }
    return probe;
}

void AdaptiveChoice::report(uint32_t arm, double ms, bool counted) {
    Arm& ran = arms_[arm];
    if (counted && !(arm == kPureArm && ran.runs == 0)) ran.times.add(ms);
    ++ran.runs;
    ran.since = 0;
    for (uint32_t a = 0; a < arms_.size(); ++a) {
        if (a != arm) ++arms_[a].since;
    }
    // Until every arm is measured the lowest runs outright; afterwards a challenger needs the margin.
    const uint32_t challenger = lowest();
    ++traces_;
    if (!explored_ || arms_[challenger].times.estimate() < (1.0 - kSwitchMargin) * arms_[current_].times.estimate()) {
        current_ = challenger;
    }
    explored_ = std::all_of(arms_.begin(), arms_.end(), [](const Arm& a) { return a.times.known(); });
}

} // namespace chcrt
