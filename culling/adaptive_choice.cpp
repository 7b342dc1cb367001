#include "culling/adaptive_choice.h"

#include <algorithm>
#include <cmath>

namespace chcrt {

double RecentTimes::estimate() const {
    const size_t n = std::min<size_t>(count_, ms_.size());
    if (n == 0) return 0.0;
    std::array<double, 5> sorted = ms_;
    std::sort(sorted.begin(), sorted.begin() + n);
    if (n == 2) return sorted[0];
    return n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
}

double RecentTimes::lowest() const {
    const size_t n = std::min<size_t>(count_, ms_.size());
    return n == 0 ? 0.0 : *std::min_element(ms_.begin(), ms_.begin() + n);
}

AdaptiveChoice::AdaptiveChoice(uint32_t arms, uint32_t probeInterval, double probeBudget)
    : arms_(std::max<uint32_t>(arms, 2)), base_(std::max<uint32_t>(probeInterval, 1)),
      budget_(probeBudget > 0.0 ? probeBudget : kAllowedProbeCost) {}

bool AdaptiveChoice::measured(uint32_t arm) const {
    return arm == kPureArm ? pureAll_.known() : arms_[arm].relative.known();
}

double AdaptiveChoice::relativeCost(uint32_t arm) const {
    return arm == kPureArm ? 1.0 : arms_[arm].relative.estimate();
}

double AdaptiveChoice::baseline(uint32_t set) const {
    const auto it = pureBySet_.find(set);
    return it != pureBySet_.end() && it->second.known() ? it->second.lowest() : 0.0;
}

double AdaptiveChoice::ledgerBase(uint32_t set) const {
    return baseline(set) > 0.0 ? baseline(set) : pureAll_.lowest();
}

double AdaptiveChoice::bestCullingCost() const {
    double best = 0.0;
    for (uint32_t a = 1; a < arms_.size(); ++a) {
        if (measured(a) && (best == 0.0 || relativeCost(a) < best)) best = relativeCost(a);
    }
    return best;
}

uint32_t AdaptiveChoice::lowest() const {
    uint32_t best = kPureArm;
    for (uint32_t a = 1; a < arms_.size(); ++a) {
        if (measured(a) && (!measured(best) || relativeCost(a) < relativeCost(best))) best = a;
    }
    return best;
}

uint32_t AdaptiveChoice::probeInterval(uint32_t arm) const {
    const uint32_t winner = best();
    if (arm == winner || !measured(arm) || !measured(winner)) return base_;
    const double bestCost = relativeCost(winner);
    const double ratio = bestCost > 0.0 ? relativeCost(arm) / bestCost : 1.0;
    const double losers = double(arms_.size() - 1);
    const double wait = std::ceil(losers * std::max(ratio - 1.0, 0.0) / budget_);
    return uint32_t(std::clamp(wait, double(base_), double(kMaxProbeInterval)));
}

bool AdaptiveChoice::affordable(uint32_t arm, uint32_t set) const {
    if (arm == kPureArm) return true; // the ledger's reference: never beyond itself
    // The configured culling, once measured, is probed when its interval says (it needs no cold trace): with the
    // ledger, a few measurements slowed by another process, booked as excess, kept a culling that wins 2x out of a
    // whole run, its estimate frozen at those values.
    if (arm == 1 && measured(1)) return true;
    const double base = ledgerBase(set);
    // The expected excess over the pure pass (in pure traces) and the traces it takes: a measured arm, one trace at
    // its estimate; a further height, its cold trace and a measured one like the best measured culling arm's.
    double excess = 0.0, traces = 1.0;
    if (measured(arm)) {
        excess = relativeCost(arm) - 1.0;
        if (excess <= 0.0) return true; // expected to save: it cannot add to the excess
    } else {
        excess = (kColdTraceCost - 1.0) + std::max(bestCullingCost() - 1.0, 0.0);
        traces = 2.0;
    }
    return excessMs_ + excess * base <= budget_ * (pureEquivalentMs_ + traces * base);
}

uint32_t AdaptiveChoice::next(uint32_t set, RaySetHints hints) const {
    const uint32_t arm = choose(set);
    if (arm == kPureArm || (measured(arm) && arm == best())) return arm;
    // A trace that measures an arm counts only against the pure pass on the same set: without that baseline, the
    // running arm traces the set (the pure pass is never worse than a culling arm that still has to prove itself).
    // Nor does a cold trace count: once kSeedSets sets have hints, an arm that does not run is measured on those.
    // This holds for a probe that measured a win too: let onto cold sets, its re-measurements ran a cold trace on
    // each set up to the next seeded one (the plant's near AO rays, 17 in a row).
    if (baseline(set) <= 0.0) return best();
    if (!hints.set && hints.ofKind >= kSeedSets) return best();
    return arm;
}

uint32_t AdaptiveChoice::choose(uint32_t set) const {
    // The pure pass first (the baseline of every relative cost: kBaselineTraces counted traces, of which the lowest
    // counts), then the configured culling.
    if (pureAll_.count() < kBaselineTraces) return kPureArm;
    if (!measured(1)) return 1;
    // An arm measured once that would take over, or that lost by less than kRemeasureBelow, is measured again at
    // once: a switch needs two measurements (confirming a winner costs nothing), and a single slowed trace must not
    // keep a culling arm out for a whole probe interval.
    const uint32_t winner = best();
    for (uint32_t a = 1; a < arms_.size(); ++a) {
        if (a != winner && arms_[a].relative.count() == 1 && relativeCost(a) < kRemeasureBelow * relativeCost(winner)) {
            return a;
        }
    }
    // A probe that measured a win is followed by another measurement at once, until the arm takes over or a
    // measurement says it would not: noise only adds time, so a win is credible, while the estimate (a median) still
    // holds the values of a slowed period, which probes at the arm's interval would replace only one by one.
    for (uint32_t a = 1; a < arms_.size(); ++a) {
        if (a != winner && arms_[a].relative.count() >= 2 && affordable(a, set) &&
            arms_[a].relative.latest() < (1.0 - kSwitchMargin) * relativeCost(winner)) {
            return a;
        }
    }
    // Further arms only while culling comes close to the pure pass, and only once the ledger affords them: where
    // culling wins, as soon as its savings cover a cold trace; where it nearly ties, once the run is long enough.
    const double culling = bestCullingCost();
    if (culling > 0.0 && culling <= 1.0 + kExploreMargin) {
        for (uint32_t a = 2; a < arms_.size(); ++a) {
            if (!measured(a) && affordable(a, set)) return a;
        }
    }
    // The most overdue probe among the measured arms, else the best arm.
    uint32_t probe = winner;
    double overdue = 0.0;
    for (uint32_t a = 0; a < arms_.size(); ++a) {
        if (a == winner || !measured(a) || !affordable(a, set)) continue;
        const double due = double(arms_[a].since) / double(probeInterval(a)); // waited a whole interval
        if (due >= 1.0 && due > overdue) probe = a, overdue = due;
    }
    return probe;
}

void AdaptiveChoice::report(uint32_t arm, double ms, bool counted, uint32_t set) {
    Arm& ran = arms_[arm];
    // The configured culling's traces up to its first measurement are its start-up, which every run that tries
    // culling pays once (compiles, and with hints a cold trace per ray set), not a probe the ledger must budget.
    const bool startUp = arm == 1 && !measured(1);
    if (arm == kPureArm) {
        if (counted && ran.runs >= kWarmUpTraces) {
            pureBySet_[set].add(ms);
            pureAll_.add(ms);
        }
    } else if (counted && cullingTraces_ >= kWarmUpTraces && baseline(set) > 0.0) {
        ran.relative.add(ms / baseline(set));
    }
    if (arm != kPureArm) ++cullingTraces_;
    // The ledger books every trace against the pure pass's time on its set (once there is one); the culling's
    // start-up adds no excess.
    const double base = ledgerBase(set);
    if (base > 0.0) {
        pureEquivalentMs_ += base;
        if (arm != kPureArm && !startUp) excessMs_ += ms - base;
    }
    ++ran.runs;
    ran.since = 0;
    for (uint32_t a = 0; a < arms_.size(); ++a) {
        if (a != arm) ++arms_[a].since;
    }
    // Until the pure pass and the configured culling are measured the lowest runs outright; afterwards a culling
    // challenger needs the margin and a second measurement (one noisy trace does not switch), while the pure pass
    // takes over as soon as it is the lowest: a culling arm runs only while it is estimated to cost no more than the
    // pure pass (with the margin both ways, a culling that nearly tied stayed on at up to 1.05x: the city's far
    // primary rays at 0.81x of pure BVH in one process of sixteen, docs/benchmarks.md, 2026-12-06 · 51aa016).
    const uint32_t challenger = lowest();
    const bool started = measured(kPureArm) && measured(1);
    const bool confirmed = challenger == kPureArm || arms_[challenger].relative.count() >= 2;
    const double margin = challenger == kPureArm ? 0.0 : kSwitchMargin;
    if (!started || !measured(current_) ||
        (confirmed && relativeCost(challenger) < (1.0 - margin) * relativeCost(current_))) {
        current_ = challenger;
    }
}

} // namespace chcrt
