#pragma once
// What one run may allocate for its big buffers (`--max-memory-mb`, docs/robustness.md "Sizes from untrusted
// input"): the scene and its BVH, render targets, Line Spaces, out-of-core caches and decoded textures. Whatever
// sizes such a buffer from a number it was given (a header's counts, an image's dimensions, --width, a generator's
// triangle count) estimates the bytes first and calls checkMemoryBudget, so a size that cannot be satisfied is a
// one-line InputError naming the flag instead of an out-of-memory kill halfway through the run. Estimates count
// the big buffers only, so they are lower bounds of what a run allocates.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace chcrt {

// The machine's physical memory (sysconf), in bytes.
uint64_t physicalMemoryBytes();
// The budget when --max-memory-mb is not given: four fifths of the physical memory (the rest is left to the
// allocations the estimates do not count, the driver's and the system's).
uint64_t defaultMemoryBudgetBytes();

// The process-wide budget: defaultMemoryBudgetBytes() until set (app/session.cpp sets it from --max-memory-mb).
uint64_t memoryBudgetBytes();
void setMemoryBudgetBytes(uint64_t bytes);

// Named parts of an estimate ("render targets 4096x4096", bytes), for the message.
using MemoryParts = std::vector<std::pair<std::string, uint64_t>>;

// Throws InputError when the parts add up to more than the budget: "this run needs at least 75,161 MiB (render
// targets 16384x16384: 73,728 MiB, ...), more than the 19,283 MiB --max-memory-mb allows (default: 4/5 of the
// physical memory)".
void checkMemoryBudget(const MemoryParts& parts);
void checkMemoryBudget(uint64_t bytes, const std::string& what);

// "1,234 MiB" (rounded up, thousands separated).
std::string formatMegabytes(uint64_t bytes);

} // namespace chcrt
