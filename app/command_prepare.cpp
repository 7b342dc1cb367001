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
    if (!o.grid.empty()) outofcore::parseGrid(o.grid, options.gridX, options.gridZ);
    const auto progress = makeTerminalProgress(!o.quiet);
    const outofcore::PrepareReport r = outofcore::prepareScene(o.scene, o.output, options, *progress);
    std::printf("prepared %s: %llu triangles, %u subtrees, %u parts, %.1f MB in %.1f s\n", o.output.c_str(),
                (unsigned long long)r.triangles, r.subtrees, r.chunks, double(r.fileBytes) / 1e6, r.seconds);
    return kExitOk;
}

} // namespace chcrt::app
