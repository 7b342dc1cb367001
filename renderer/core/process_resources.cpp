#include "renderer/core/process_resources.h"

#include <cstdio>
#include <dirent.h>
#include <dlfcn.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CHCRT_ASAN_MALLOC 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define CHCRT_ASAN_MALLOC 1
#endif
#if defined(CHCRT_ASAN_MALLOC)
#include <sanitizer/allocator_interface.h>
#endif

namespace chcrt {
namespace {

// jemalloc's control interface when jemalloc is the process's malloc (`LD_PRELOAD=libjemalloc.so.2`, as the
// allocator comparisons of docs/robustness.md "Long runs" ran), looked up rather than linked; null under glibc's.
using Mallctl = int (*)(const char*, void*, size_t*, void*, size_t);
Mallctl jemallocControl() {
    static const auto mallctl = reinterpret_cast<Mallctl>(::dlsym(RTLD_DEFAULT, "mallctl"));
    return mallctl;
}

uint64_t heapInUse() {
    if (const Mallctl mallctl = jemallocControl()) {
        uint64_t epoch = 1;
        size_t size = sizeof epoch;
        mallctl("epoch", &epoch, &size, &epoch, size); // refreshes the statistics
        size_t allocated = 0;
        size = sizeof allocated;
        return mallctl("stats.allocated", &allocated, &size, nullptr, 0) == 0 ? allocated : 0;
    }
#if defined(CHCRT_ASAN_MALLOC) // the sanitizer builds' malloc is AddressSanitizer's, not glibc's
    return __sanitizer_get_current_allocated_bytes();
#elif defined(__GLIBC__)
    const struct mallinfo2 info = ::mallinfo2();
    return info.uordblks + info.hblkhd;
#else
    return 0;
#endif
}

} // namespace

ProcessResources sampleProcessResources() {
    ProcessResources r;
    // One read of /proc/self/status gives the resident memory, its split and the thread count.
    if (FILE* f = std::fopen("/proc/self/status", "r")) {
        char line[256];
        unsigned long long kb = 0;
        int threads = 0;
        while (std::fgets(line, sizeof line, f)) {
            if (std::sscanf(line, "VmRSS: %llu kB", &kb) == 1) r.residentBytes = kb << 10;
            else if (std::sscanf(line, "RssAnon: %llu kB", &kb) == 1) r.residentAnonBytes = kb << 10;
            else if (std::sscanf(line, "RssFile: %llu kB", &kb) == 1) r.residentFileBytes += kb << 10;
            else if (std::sscanf(line, "RssShmem: %llu kB", &kb) == 1) r.residentFileBytes += kb << 10;
            else if (std::sscanf(line, "Threads: %d", &threads) == 1) r.threads = threads;
        }
        std::fclose(f);
    }
    r.heapInUseBytes = heapInUse();
    if (DIR* d = ::opendir("/proc/self/fd")) {
        int entries = 0;
        while (const dirent* e = ::readdir(d)) {
            if (e->d_name[0] != '.') ++entries;
        }
        ::closedir(d);
        r.openFiles = entries - 1; // the directory's own descriptor
    }
    return r;
}

void releaseFreedMemory() {
    // jemalloc: "arena.<MALLCTL_ARENAS_ALL>.purge" (4096 in jemalloc 5) returns every arena's unused dirty pages now
    // instead of after their decay time.
    if (const Mallctl mallctl = jemallocControl()) {
        mallctl("arena.4096.purge", nullptr, nullptr, nullptr, 0);
        return;
    }
#if defined(__GLIBC__)
    ::malloc_trim(0);
#endif
}

} // namespace chcrt
