// The PLY reader (ASCII and both binary byte orders; the format is in the input's header).
#include "renderer/scene/scene_loader.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    const auto file = chcrt::fuzz::writeScratchFile(data, size, ".ply");
    chcrt::fuzz::expectOnlyInputErrors([&] { chcrt::loadPly(file); });
    return 0;
}
