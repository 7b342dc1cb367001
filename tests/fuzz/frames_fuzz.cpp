// The --frames parser and the output-path pattern it feeds.
#include "renderer/core/frame_range.h"
#include "tests/fuzz/fuzz_input.h"

#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    const std::string text(reinterpret_cast<const char*>(data), size);
    chcrt::fuzz::expectOnlyInputErrors([&] {
        const std::vector<int> frames = chcrt::parseFrameRange(text);
        if (frames.empty()) std::abort(); // documented: never empty
        int signs = 0; // documented: negative numbers are rejected (a branch-free scan: 10^7 frames stay fast)
        for (const int f : frames) signs |= f;
        if (signs < 0) std::abort();
        (void)chcrt::formatFramePath("out_####.png", frames.back(), int(frames.size()));
        (void)chcrt::formatFramePath("out.png", frames.front(), int(frames.size()));
    });
    return 0;
}
