// Prints procedural generation speed in triangles per second (one run per spec after an untimed warm-up
// of the smallest size). Not a test: timings are never asserted.
//   procedural_timing [spec ...]     default: city/interior/plant at 1M and 10M
#include "renderer/scene/procedural/procedural.h"

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    std::vector<std::string> specs(argv + 1, argv + argc);
    if (specs.empty())
        specs = {"city:1m", "interior:1m", "plant:1m", "city:10m", "interior:10m", "plant:10m"};
    chcrt::generateProceduralScene(chcrt::ProceduralSpec{chcrt::ProceduralKind::City, 100'000, 1}); // warm-up
    for (const std::string& text : specs) {
        chcrt::ProceduralSpec spec;
        if (!chcrt::parseProceduralSpec(text, spec)) {
            std::fprintf(stderr, "not a generator spec: %s\n", text.c_str());
            return 2;
        }
        const auto start = std::chrono::steady_clock::now();
        const chcrt::Scene scene = chcrt::generateProceduralScene(spec);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double megabytes = double(scene.positions.size() * 24 + scene.triangles.size() * 16) / 1e6;
        std::printf("%-28s %10zu triangles %10zu vertices  %7.3f s  %6.2f Mtri/s  %7.1f MB\n", scene.name.c_str(),
                    scene.triangleCount(), scene.positions.size(), seconds, scene.triangleCount() / seconds / 1e6,
                    megabytes);
    }
    return 0;
}
