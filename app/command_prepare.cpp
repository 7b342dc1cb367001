// `chcrt prepare`: a scene (generator spec, grid of copies, or file) to a prepared scene file (.chs) for
// out-of-core rendering (renderer/outofcore/, docs/outofcore.md).
#include "app/commands.h"
#include "renderer/core/error.h"
#include "renderer/core/output_path.h"
#include "renderer/outofcore/prepare.h"

#include <cstdio>

namespace chcrt::app {

int runPrepare(const PrepareCommandOptions& o) {
    if (o.output.empty()) throw InputError("prepare: -o <file.chs> is required");
    if (std::filesystem::path(o.output).extension() != ".chs") throw InputError("prepare: the output must end in .chs");
    if (o.memoryMb < 1) throw InputError("--memory-mb must be positive");
    checkOutputPath(o.output);
    outofcore::PrepareOptions options;
    options.memoryBytes = o.memoryMb << 20;
    options.subtreeTriangles = o.subtreeTriangles;
    options.subtreeHeight = o.subtreeHeight;
    static_assert(PrepareCommandOptions{}.lodLevels == outofcore::kDefaultLodLevels);
    if (o.lodLevels > outofcore::kMaxLodLevels) {
        throw InputError("--lod-levels " + std::to_string(o.lodLevels) + ": at most " +
                         std::to_string(outofcore::kMaxLodLevels));
    }
    options.lodLevels = o.lodLevels;
    if (o.layout != "compact" && o.layout != "full") throw InputError("--layout " + o.layout + ": expected compact or full");
    options.compact = o.layout == "compact";
    if (!o.grid.empty()) outofcore::parseGrid(o.grid, options.gridX, options.gridZ);
    const auto progress = makeTerminalProgress(!o.quiet);
    const outofcore::PrepareReport r = outofcore::prepareScene(o.scene, o.output, options, *progress);
    std::printf("prepared %s: %llu triangles, %u subtrees, %u parts, %.1f MB in %.1f s\n", o.output.c_str(),
                (unsigned long long)r.triangles, r.subtrees, r.chunks, double(r.fileBytes) / 1e6, r.seconds);
    if (r.compact && r.triangles > 0) { // bytes per triangle of the subtrees (docs/outofcore.md, "Compact subtrees")
        std::printf("compact subtrees: %.1f bytes per triangle (%.2f distinct vertices per triangle)\n",
                    double(r.subtreeBytes) / double(r.triangles), double(r.vertices) / double(r.triangles));
    }
    if (options.lodLevels > 0) { // what the proxies cost beside what they replace (docs/outofcore.md, "LOD proxies")
        std::printf("LOD proxies: %llu of %u subtrees x %u levels kept, %.1f MB (%.1f %% of the subtrees' %.1f MB)\n",
                    (unsigned long long)r.proxies, r.subtrees, options.lodLevels, double(r.proxyBytes) / 1e6,
                    r.subtreeBytes ? 100.0 * double(r.proxyBytes) / double(r.subtreeBytes) : 0.0,
                    double(r.subtreeBytes) / 1e6);
    }
    return kExitOk;
}

} // namespace chcrt::app
