// build/bin/chcrt: the command-line front end. Errors from the library are caught here, once, and become a
// one-line message and an exit code (app/commands.h, docs/cli.md).
#include "app/commands.h"
#include "renderer/core/error.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <sstream>

namespace chcrt::app {

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    std::stringstream stream(text);
    std::string item;
    while (std::getline(stream, item, ',')) {
        if (!item.empty()) items.push_back(item);
    }
    if (items.empty()) throw InputError("empty list '" + text + "'");
    return items;
}

namespace {

int run(int argc, char** argv) {
    CLI::App cli{"chcrt: hybrid raster/ray-trace renderer (CHC+RT, Line Space, out-of-core)", "chcrt"};
    cli.set_version_flag("--version", "chcrt 0.1.0");
    cli.require_subcommand(1);

    RenderOptions demo;
    demo.demo = true;
    demo.output = "demo.png";
    CLI::App* demoCommand =
        cli.add_subcommand("demo", "Render the embedded default scene (city, street level) with soft shadows, AO "
                                   "and one-bounce diffuse to an image and print a summary with timings");
    addCommonOptions(*demoCommand, demo.common, true);
    demoCommand->add_option("-o,--output", demo.output, "Output image (.png, .exr, .jpg)")->capture_default_str();

    RenderOptions render;
    CLI::App* renderCommand = cli.add_subcommand("render", "Render frames of a walkthrough to images");
    addCommonOptions(*renderCommand, render.common, true);
    renderCommand->add_option("-o,--output", render.output, "Output image; #### becomes the frame number")->required();
    renderCommand->add_option("--method", render.method, "Tracing method (bvh, chcrt, ...; see bench)")->capture_default_str();
    renderCommand->add_option("--debug-image", render.debugImage,
                              "CHC+RT debug image instead of the shaded frame: overdraw, subtrees, batches or cost "
                              "(chcrt methods only)");

    BenchOptions bench;
    CLI::App* benchCommand = cli.add_subcommand("bench", "Compare tracing methods on the same rays (table, JSON, CSV)");
    addCommonOptions(*benchCommand, bench.common, true); // --effects: frames of the image-error comparison
    benchCommand->add_option("--method", bench.methods, "Methods, comma-separated: bvh, chcrt, chcrt-aggressive, embree")->capture_default_str();
    benchCommand->add_option("--ray-type", bench.rayTypes, "Ray types, comma-separated: primary, shadow, ao, diffuse")
        ->capture_default_str();
    benchCommand->add_option("--runs", bench.runs, "Timed runs (the median is reported)")->capture_default_str();
    benchCommand->add_option("--warmup", bench.warmupRuns, "Untimed warm-up runs")->capture_default_str();
    benchCommand->add_flag("--steps", bench.steps,
                           "Also count BVH traversal steps (inner nodes + leaves + triangles) per active ray for bvh and the "
                           "chcrt methods, in the first timed run (CHC+RT: one extra untimed trace per pass; column "
                           "steps/ray, JSON steps_per_ray)");
    benchCommand->add_option("--json", bench.jsonFile, "Write the table as JSON ({\"rows\": [...]})");
    benchCommand->add_option("--csv", bench.csvFile, "Write the table as CSV");
    benchCommand->add_option("--markdown", bench.markdownFile, "Write the table as markdown");

    VerifyOptions verify;
    CLI::App* verifyCommand =
        cli.add_subcommand("verify", "Check a tracing method's hits against Embree; exit 4 on differences");
    addCommonOptions(*verifyCommand, verify.common, false);
    verifyCommand->add_option("--method", verify.method, "Method to check: bvh (against Embree), chcrt, chcrt-aggressive (against pure BVH)")->capture_default_str();
    verifyCommand->add_option("--ray-type", verify.rayTypes, "Ray types, comma-separated: primary, shadow, ao, diffuse")
        ->capture_default_str();
    verifyCommand->add_option("--max-diff", verify.maxDiffering, "Differing pixels tolerated")->capture_default_str();
    verifyCommand->add_option("--show-diff", verify.showDifferences,
                              "Print up to N differing pixels with their ray and both hits");

    InfoOptions info;
    CLI::App* infoCommand = cli.add_subcommand("info", "Print the OpenGL renderer, its limits and scene statistics");
    addCommonOptions(*infoCommand, info.common, false);
    infoCommand->add_flag("--no-scene", info.noScene, "Only the OpenGL information");

    PrepareCommandOptions prepare;
    CLI::App* prepareCommand = cli.add_subcommand(
        "prepare", "Write a prepared scene (.chs: BVH cut into termination subtrees) for out-of-core rendering");
    prepareCommand->add_option("--scene", prepare.scene, "Generator spec (city:140m), grid:NxM:<scene>, or scene file")
        ->required();
    prepareCommand->add_option("-o,--output", prepare.output, "Output file (.chs)")->required();
    prepareCommand->add_option("--memory-mb", prepare.memoryMb, "Peak memory budget of the preparation")
        ->capture_default_str();
    prepareCommand->add_option("--subtree-triangles", prepare.subtreeTriangles, "Termination subtree triangle limit")
        ->capture_default_str();
    prepareCommand->add_option("--subtree-height", prepare.subtreeHeight, "Termination subtree height limit")
        ->capture_default_str();
    prepareCommand->add_option("--grid", prepare.grid, "NxM copies of the scene (like the paper's Powerplant x 16)");
    prepareCommand->add_flag("-q,--quiet", prepare.quiet, "No progress bar");

    ViewOptions view;
    view.common.width = 1280;
    view.common.height = 720;
    view.common.spp = 1;
    view.common.effects = "shadow"; // interactive on a CPU rasteriser; the panel turns on AO and diffuse
    CLI::App* viewCommand = cli.add_subcommand("view", "Interactive walkthrough viewer (GLFW window, ImGui panel)");
    addCommonOptions(*viewCommand, view.common, true);
    viewCommand->remove_option(viewCommand->get_option("--gl")); // the viewer's context is its GLFW window
    viewCommand->add_option("--method", view.method,
                            "Tracing method: raster (no secondary rays) or a GPU method (bvh, chcrt, bvh+ls, ...)")
        ->capture_default_str();
    viewCommand->add_option("--view-mode", view.viewMode,
                            "shaded, position, normal, albedo, triangle, depth, cost, overdraw, subtrees, batches, "
                            "shafts, residency")->capture_default_str();
    viewCommand->add_option("--render-scale", view.renderScale, "Internal resolution / window resolution")
        ->capture_default_str();
    viewCommand->add_option("--script", view.script, "Run a scripted session (JSON list of steps) and exit");
    viewCommand->add_option("--record", view.recordFile, "Where recorded walkthroughs are saved")->capture_default_str();
    viewCommand->add_flag("--play", view.play, "Start playing the camera path");
    viewCommand->add_flag("--no-accumulate", view.noAccumulate, "No progressive refinement when the camera stops");
    viewCommand->add_flag("--hide-panel", view.hidePanel, "Start with the ImGui panel hidden (Tab toggles it)");

    try {
        cli.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return cli.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "chcrt: error: %s (see chcrt --help)\n", e.what());
        return kExitBadInput;
    }

    if (*demoCommand) return runRender(demo);
    if (*renderCommand) return runRender(render);
    if (*benchCommand) return runBench(bench);
    if (*verifyCommand) return runVerify(verify);
    if (*infoCommand) return runInfo(info);
    if (*viewCommand) return runView(view);
    if (*prepareCommand) return runPrepare(prepare);
    return kExitBadInput;
}

} // namespace
} // namespace chcrt::app

int main(int argc, char** argv) {
    using namespace chcrt;
    try {
        return app::run(argc, argv);
    } catch (const InputError& e) {
        std::fprintf(stderr, "chcrt: error: %s\n", e.what());
        return app::kExitBadInput;
    } catch (const GlError& e) {
        std::fprintf(stderr, "chcrt: OpenGL error: %s\n", e.what());
        return app::kExitGl;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "chcrt: internal error: %s\n", e.what());
        return app::kExitInternal;
    }
}
