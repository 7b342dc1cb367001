// The Wavefront OBJ reader (a referenced .mtl is looked up next to the scratch file and is normally missing).
#include "renderer/scene/scene_loader.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    const auto file = chcrt::fuzz::writeScratchFile(data, size, ".obj");
    chcrt::fuzz::expectOnlyInputErrors([&] { chcrt::loadObj(file); });
    return 0;
}
