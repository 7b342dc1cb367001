// The glTF 2.0 loader as chcrt uses it (tinygltf, then hierarchy, instancing, accessors, materials): input that
// starts with the GLB magic is written as .glb, anything else as .gltf (the seeds embed their buffers as data
// URIs so a .gltf needs no file next to it; textures they name are missing on purpose).
#include "renderer/core/memory_budget.h"
#include "renderer/scene/scene_loader.h"
#include "tests/fuzz/fuzz_input.h"

#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    // The loader sizes textures and the flattened scene by the memory budget (--max-memory-mb): held to 512 MiB
    // here, well inside libFuzzer's -rss_limit_mb=2048 of scripts/fuzz.sh.
    static const bool budget = (chcrt::setMemoryBudgetBytes(uint64_t(512) << 20), true);
    (void)budget;
    const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    const auto file = chcrt::fuzz::writeScratchFile(data, size, glb ? ".glb" : ".gltf");
    chcrt::fuzz::expectOnlyInputErrors([&] { chcrt::loadGltf(file); });
    return 0;
}
