#pragma once
// Shared by the fuzz harnesses: the readers take file paths, so each input is written to one scratch file per
// process (in /dev/shm when it exists: no disk traffic per execution) before the reader opens it. InputError is
// the expected outcome of bad input and is swallowed; any other exception escapes to libFuzzer (or the replay
// main), which reports it as a crash.
#include "renderer/core/error.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace chcrt::fuzz {

// Writes `size` bytes to this process's scratch file with extension `extension` (".ply") and returns its path.
std::filesystem::path writeScratchFile(const uint8_t* data, size_t size, const std::string& extension);

// A directory for this process's scratch files (created on first use).
const std::filesystem::path& scratchDirectory();

// The hang criterion of every harness: more than 1 s of CPU time on one input. A harness holds one of these for
// the whole of LLVMFuzzerTestOneInput; it arms the process's CPU-time timer (ITIMER_PROF: user + system time of
// all threads), and on expiry the harness aborts with "more than 1 s of CPU time on one input", which libFuzzer
// reports as a crash and keeps as crash-*. libFuzzer's own -timeout counts wall-clock time, which a process
// starved by other work on a shared machine exceeds without any hang; scripts/fuzz.sh sets that to a backstop.
class CpuTimeLimit {
public:
    CpuTimeLimit();
    ~CpuTimeLimit();
    CpuTimeLimit(const CpuTimeLimit&) = delete;
    CpuTimeLimit& operator=(const CpuTimeLimit&) = delete;
};

template <typename F>
void expectOnlyInputErrors(F&& f) {
    try {
        f();
    } catch (const InputError&) {
    }
}

} // namespace chcrt::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
