#pragma once
// Closed intervals of doubles for the conservative bounds the CPU makes of rays the GPU generates
// (camera_ray_bounds.h, hemisphere_ray_bounds.h): interval arithmetic over a cell's pixels instead of a reduction of
// its rays.
#include <algorithm>

namespace chcrt {

struct Interval {
    double lo, hi;
};

// [a] · [b] for finite intervals: the extremes of the four end products.
inline Interval times(Interval a, Interval b) {
    const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    return {*std::min_element(p, p + 4), *std::max_element(p, p + 4)};
}

} // namespace chcrt
