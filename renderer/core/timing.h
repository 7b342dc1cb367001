#pragma once
// Wall-clock intervals of the CPU side (GPU work is timed after glFinish, or by GpuTimer in gl_objects.h).
#include <chrono>

namespace chcrt {

// Milliseconds of std::chrono::steady_clock since `start`.
inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

} // namespace chcrt
