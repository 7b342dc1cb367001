#include "tests/fuzz/fuzz_input.h"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <sys/time.h>
#include <unistd.h>

namespace chcrt::fuzz {

const std::filesystem::path& scratchDirectory() {
    static const std::filesystem::path dir = [] {
        std::error_code ec;
        const std::filesystem::path base =
            std::filesystem::is_directory("/dev/shm", ec) ? std::filesystem::path("/dev/shm") : std::filesystem::temp_directory_path();
        std::filesystem::path d = base / ("chcrt-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

std::filesystem::path writeScratchFile(const uint8_t* data, size_t size, const std::string& extension) {
    const std::filesystem::path file = scratchDirectory() / ("input" + extension);
    std::FILE* f = std::fopen(file.c_str(), "wb");
    if (f == nullptr) throw std::runtime_error("cannot write " + file.string());
    const bool ok = size == 0 || std::fwrite(data, 1, size, f) == size;
    if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + file.string());
    return file;
}

namespace {

extern "C" void cpuTimeExceeded(int) {
    static const char message[] = "chcrt fuzz: more than 1 s of CPU time on one input (a hang)\n";
    (void)!::write(STDERR_FILENO, message, sizeof message - 1);
    std::abort();
}

void setCpuTimer(long seconds) {
    itimerval timer{};
    timer.it_value.tv_sec = seconds;
    ::setitimer(ITIMER_PROF, &timer, nullptr);
}

} // namespace

CpuTimeLimit::CpuTimeLimit() {
    static const bool installed = [] {
        struct sigaction action{};
        action.sa_handler = cpuTimeExceeded;
        sigemptyset(&action.sa_mask);
        return ::sigaction(SIGPROF, &action, nullptr) == 0;
    }();
    if (installed) setCpuTimer(1);
}

CpuTimeLimit::~CpuTimeLimit() { setCpuTimer(0); }

namespace {
// Removes the scratch directory when the process exits normally (libFuzzer's -max_total_time, the replay main).
struct ScratchCleanup {
    ~ScratchCleanup() {
        std::error_code ec;
        std::filesystem::remove_all(scratchDirectory(), ec);
    }
} cleanup;
} // namespace

} // namespace chcrt::fuzz
