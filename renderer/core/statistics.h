#pragma once
// Summaries of measured samples (timings of repeated runs and frames).
#include <algorithm>
#include <vector>

namespace chcrt {

// The median: the middle value, of an even count the mean of the two middle ones; 0 when empty.
inline double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

} // namespace chcrt
