#pragma once
// What the process holds of the machine, read from /proc/self (Linux): resident memory, open file descriptors and
// threads. Long runs sample it (render and view: --stats-json frames and --resource-log) to show that memory,
// descriptors and threads stay flat: scripts/soak.sh, docs/benchmarks.md.
#include <cstdint>

namespace chcrt {

struct ProcessResources {
    uint64_t residentBytes = 0; // VmRSS (/proc/self/statm: resident pages × page size)
    int openFiles = 0;          // entries of /proc/self/fd (the descriptor reading it not counted)
    int threads = 0;            // /proc/self/stat field 20
};

// Fields that cannot be read stay 0 (not Linux, /proc not mounted).
ProcessResources sampleProcessResources();

} // namespace chcrt
