// The scene-spec parsers: generator specs ("city:10m:seed=3") and prepare's grids ("grid:4x4:plant:12.8m").
// A spec that parses must print to a canonical form that parses back to itself (analytic scenes ignore a count
// and seed, so the canonical forms are compared, not the fields).
#include "renderer/outofcore/prepare.h"
#include "renderer/scene/procedural/procedural.h"
#include "tests/fuzz/fuzz_input.h"

#include <cstdlib>

namespace {

void parseSpec(const std::string& text) {
    chcrt::ProceduralSpec spec;
    if (!chcrt::parseProceduralSpec(text, spec)) return;
    chcrt::ProceduralSpec again;
    const std::string canonical = chcrt::toString(spec);
    if (!chcrt::parseProceduralSpec(canonical, again) || chcrt::toString(again) != canonical) {
        std::abort();
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const chcrt::fuzz::CpuTimeLimit limit;
    const std::string text(reinterpret_cast<const char*>(data), size);
    chcrt::fuzz::expectOnlyInputErrors([&] { parseSpec(text); });
    chcrt::fuzz::expectOnlyInputErrors([&] {
        // As prepareScene splits grid:NxM:<scene>.
        uint32_t x = 0, z = 0;
        if (text.rfind("grid:", 0) != 0) return chcrt::outofcore::parseGrid(text, x, z);
        const size_t sep = text.find(':', 5);
        if (sep == std::string::npos) return;
        chcrt::outofcore::parseGrid(text.substr(5, sep - 5), x, z);
        parseSpec(text.substr(sep + 1));
    });
    return 0;
}
