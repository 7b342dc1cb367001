// Line Space build time and memory on real scenes (not a test; figures for linespace/README.md).
//   linespace_report --scene city:100k [--scene dragon.glb] --n 4,6,8 --depth 9 --threshold 8 [--binary]
//                    [--threads 2] [--cache DIR] [--ntree 4:4,6:3,8:3] [--ntree-only]
// Prints, per scene and parameter set: Line Space nodes, build seconds, filled fractions, MB, bytes per shaft,
// and the BVH + triangle bytes for comparison.
#include "linespace/linespace_cache.h"
#include "linespace/ntree.h"
#include "renderer/bvh/bvh.h"
#include "renderer/core/error.h"
#include "renderer/scene/procedural/procedural.h"
#include "renderer/scene/scene_loader.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::vector<uint32_t> parseList(const std::string& text) {
    std::vector<uint32_t> values;
    std::stringstream stream(text);
    std::string item;
    while (std::getline(stream, item, ',')) {
        values.push_back(static_cast<uint32_t>(std::stoul(item)));
    }
    return values;
}

chcrt::Scene loadScene(const std::string& spec) {
    chcrt::ProceduralSpec procedural;
    if (chcrt::parseProceduralSpec(spec, procedural)) {
        return chcrt::generateProceduralScene(procedural);
    }
    return chcrt::loadSceneFile(spec);
}

} // namespace

int main(int argc, char** argv) {
    std::vector<std::string> scenes;
    std::vector<uint32_t> ns{6}, depths{9};
    uint32_t threshold = 8, threads = 0;
    bool candidates = true;
    std::string cache;
    std::vector<std::pair<uint32_t, uint32_t>> ntrees; // (N, d)
    bool skipBvh = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "missing value for %s\n", arg.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (arg == "--scene") {
            scenes.push_back(next());
        } else if (arg == "--n") {
            ns = parseList(next());
        } else if (arg == "--depth") {
            depths = parseList(next());
        } else if (arg == "--threshold") {
            threshold = static_cast<uint32_t>(std::stoul(next()));
        } else if (arg == "--threads") {
            threads = static_cast<uint32_t>(std::stoul(next()));
        } else if (arg == "--binary") {
            candidates = false;
        } else if (arg == "--ntree") {
            std::stringstream stream(next());
            std::string item;
            while (std::getline(stream, item, ',')) {
                const size_t colon = item.find(':');
                ntrees.emplace_back(static_cast<uint32_t>(std::stoul(item.substr(0, colon))),
                                    static_cast<uint32_t>(std::stoul(item.substr(colon + 1))));
            }
        } else if (arg == "--ntree-only") {
            skipBvh = true;
        } else if (arg == "--cache") {
            cache = next();
        } else {
            std::printf("usage: linespace_report --scene SPEC... [--n 4,6,8] [--depth 9] [--threshold 8] [--binary] "
                        "[--threads N] [--cache DIR] [--ntree 4:4,6:3,8:3] [--ntree-only]\n");
            return arg == "--help" ? 0 : 2;
        }
    }
    if (scenes.empty()) {
        scenes.push_back("city:100k");
    }
    try {
        auto progress = chcrt::makeTerminalProgress(true);
        for (const std::string& spec : scenes) {
            const chcrt::Scene scene = loadScene(spec);
            const chcrt::Bvh bvh = chcrt::buildBvh(scene);
            std::printf("%s: %zu triangles, BVH %u nodes, depth %u, %.2f MB (nodes + triangles), built in %.2f s\n",
                        spec.c_str(), scene.triangleCount(), bvh.stats.nodeCount, bvh.stats.maxDepth,
                        double(bvh.stats.bytes) / 1e6, bvh.stats.buildSeconds);
            for (const auto& [n, d] : ntrees) {
                chcrt::ls::NTreeParams params;
                params.n = n;
                params.depth = d;
                params.threads = threads;
                const chcrt::ls::NTree tree = chcrt::ls::buildNTree(bvh, params, *progress);
                std::printf("  %s: %s\n", params.toString().c_str(), tree.stats.summary().c_str());
                std::fflush(stdout);
            }
            for (const uint32_t depth : skipBvh ? std::vector<uint32_t>{} : depths) {
                for (const uint32_t n : ns) {
                    chcrt::ls::LineSpaceParams params;
                    params.n = n;
                    params.depth = depth;
                    params.triangleThreshold = threshold;
                    params.candidates = candidates;
                    params.threads = threads;
                    chcrt::ls::CacheOutcome outcome{};
                    const auto start = std::chrono::steady_clock::now();
                    const chcrt::ls::LineSpaces spaces =
                        chcrt::ls::loadOrBuildLineSpaces(bvh, params, cache, *progress, &outcome);
                    const double seconds =
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                    std::printf("  %s: %s; %s (%.2f s wall); +%.1f%% over BVH\n", params.toString().c_str(),
                                spaces.stats.summary().c_str(), chcrt::ls::toString(outcome), seconds,
                                100.0 * double(spaces.stats.totalBytes()) / double(bvh.stats.bytes));
                    std::fflush(stdout);
                }
            }
        }
    } catch (const chcrt::InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
    }
    return 0;
}
