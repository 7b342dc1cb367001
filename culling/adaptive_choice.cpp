#include "culling/adaptive_choice.h"

#include <algorithm>

namespace chcrt {

double RecentTimes::estimate() const {
    if (count_ == 0) return 0.0;
    if (count_ == 1) return ms_[0];
    if (count_ == 2) return 0.5 * (ms_[0] + ms_[1]);
    return std::max(std::min(ms_[0], ms_[1]), std::min(std::max(ms_[0], ms_[1]), ms_[2]));
}

bool AdaptiveChoice::shouldCull() const {
    if (!cull_.known()) return true;
    if (!full_.known()) return false;
    if (cull_.estimate() > full_.estimate()) return sinceProbe_ + 1 >= interval_;
    return sinceFull_ + 1 < base_;
}

void AdaptiveChoice::culled(double ms, bool warm) {
    if (warm) cull_.add(ms);
    // Back-off: a probe that still loses doubles the interval (fewer costly probes in views where culling does
    // not pay); a win restores it.
    if (full_.known() && cull_.known()) {
        interval_ = cull_.estimate() > full_.estimate() ? std::min(2 * interval_, 8 * base_) : base_;
    }
    sinceProbe_ = 0;
    ++sinceFull_;
}

void AdaptiveChoice::tracedFull(double ms) {
    if (fullWarm_) full_.add(ms);
    fullWarm_ = true;
    sinceFull_ = 0;
    ++sinceProbe_;
}

} // namespace chcrt
