#include "renderer/core/process_resources.h"

#include <cstdio>
#include <cstring>
#include <dirent.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>

namespace chcrt {

ProcessResources sampleProcessResources() {
    ProcessResources r;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        unsigned long long size = 0, resident = 0;
        if (std::fscanf(f, "%llu %llu", &size, &resident) == 2) {
            r.residentBytes = resident * uint64_t(::sysconf(_SC_PAGESIZE));
        }
        std::fclose(f);
    }
    if (DIR* d = ::opendir("/proc/self/fd")) {
        int entries = 0;
        while (const dirent* e = ::readdir(d)) {
            if (e->d_name[0] != '.') ++entries;
        }
        ::closedir(d);
        r.openFiles = entries - 1; // the directory's own descriptor
    }
    if (FILE* f = std::fopen("/proc/self/stat", "r")) {
        // "pid (comm) state ..." — comm may hold spaces and parentheses: fields count from the last ')'.
        char buffer[1024] = {};
        const size_t n = std::fread(buffer, 1, sizeof(buffer) - 1, f);
        std::fclose(f);
        buffer[n] = '\0';
        if (const char* end = std::strrchr(buffer, ')')) {
            long threads = 0;
            // After ')': state(3) ppid pgrp session tty_nr tpgid flags minflt cminflt majflt cmajflt utime stime
            // cutime cstime priority nice num_threads(20).
            if (std::sscanf(end + 1, " %*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %*u %*u %*d %*d %*d %*d %ld",
                            &threads) == 1) {
                r.threads = int(threads);
            }
        }
    }
    return r;
}

void releaseFreedMemory() {
#if defined(__GLIBC__)
    ::malloc_trim(0);
#endif
}

} // namespace chcrt
