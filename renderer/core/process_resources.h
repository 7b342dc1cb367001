#pragma once
// What the process holds of the machine, read from /proc/self (Linux): resident memory, open file descriptors and
// threads. Long runs sample it (render and view: --stats-json frames and --resource-log) to show that memory,
// descriptors and threads stay flat: scripts/soak.sh, docs/benchmarks.md.
#include <cstdint>

namespace chcrt {

struct ProcessResources {
    uint64_t residentBytes = 0; // VmRSS (/proc/self/status)
    // VmRSS split (RssAnon; RssFile + RssShmem): anonymous pages (heaps, the driver's and the allocator's maps: what a leak
    // grows) and pages of mapped files and shared memory (the libraries' code, which the kernel keeps resident or
    // not as it needs, and the Mesa shader cache's index).
    uint64_t residentAnonBytes = 0, residentFileBytes = 0;
    // Bytes the process's malloc has handed out and not had back (jemalloc: stats.allocated; glibc: mallinfo2's
    // uordblks + hblkhd): against residentAnonBytes it tells a growth of live allocations from fragmentation or from
    // memory mapped outside malloc (the GL driver's JIT code).
    uint64_t heapInUseBytes = 0;
    int openFiles = 0;          // entries of /proc/self/fd (the descriptor reading it not counted)
    int threads = 0;            // Threads (/proc/self/status)
};

// Fields that cannot be read stay 0 (not Linux, /proc not mounted).
ProcessResources sampleProcessResources();

// Hands the memory allocator's free pages back to the system: glibc's malloc_trim, or jemalloc's purge of every arena
// when jemalloc is preloaded as the process's malloc; elsewhere nothing. Long runs call it every
// kReleaseFreedMemoryEvery frames: glibc keeps the pages of freed blocks, and with the driver's allocations between them a 32×24 walkthrough's resident memory rose by 1.5-2.6 MB (0.7-1.2 %) over its first 6,000 frames with
// no more memory in use (heaptrack: the same peak heap at frames 500 and 4,000), flat from then on to frame 40,000;
// with the release every 500 frames it stayed within 223.2-223.9 MB over 10,000 (docs/robustness.md, "Long runs").
void releaseFreedMemory();
inline constexpr uint64_t kReleaseFreedMemoryEvery = 500;

} // namespace chcrt
