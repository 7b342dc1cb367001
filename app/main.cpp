// build/bin/chcrt: the command-line front end. Each subcommand's flags are registered by one function here (the
// shared ones come from the parameter table, app/parameters.h); errors from the library are caught once and become
// a one-line message and an exit code (app/commands.h, docs/cli.md).
#include "app/commands.h"
#include "app/methods.h"
#include "app/report_plan.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstring>

namespace chcrt::app {
namespace {

// Commands that render shaded images and open a headless GL context.
constexpr uint8_t kHeadlessShaded = kShadedCommands | kHeadlessCommands;

// A count's check with a message that says what is wrong (CLI11's NonNegativeNumber prints DBL_MAX in full).
CLI::Validator notNegative() {
    return CLI::Validator(
        [](const std::string& text) { return text.rfind('-', 0) == 0 ? std::string("must not be negative") : std::string(); },
        "NONNEGATIVE");
}

CLI::App* addDemo(CLI::App& cli, RenderOptions& demo) {
    demo.demo = true;
    demo.output = "demo.png";
    CLI::App* c = cli.add_subcommand("demo", "Render the embedded default scene (city, street level) with soft shadows, "
                                             "AO and one-bounce diffuse to an image and print a summary with timings");
    addCommonOptions(*c, demo.common, kHeadlessShaded);
    c->add_option("-o,--output", demo.output, "Output image (.png, .exr, .jpg)")->capture_default_str();
    return c;
}

} // namespace

void addRenderOwnOptions(CLI::App& c, RenderOptions& render) {
    c.add_option("-o,--output", render.output, "Output image; #### becomes the frame number")->required();
    c.add_option("--method", render.method, "Tracing method: " + methodNames(false) + " (chcrt methods)")
        ->capture_default_str();
    c.add_option("--debug-image", render.debugImage,
                 "CHC+RT debug image instead of the shaded frame: overdraw, subtrees, batches, cost or bounds "
                 "(chcrt methods only)");
    c.add_option("--records", render.records,
                 "Append a JSON line per finished frame (frame, image checksum, flags digest, commit, statistics; "
                 "docs/farm.md)");
    c.add_flag("--resume", render.resume, "Skip the frames whose --records prove them done (same flags and build, "
                                          "image unchanged)");
    addResourceLogOptions(c, render.resourceLog, render.resourceEvery);
}

namespace {

CLI::App* addRender(CLI::App& cli, RenderOptions& render) {
    CLI::App* c = cli.add_subcommand("render", "Render frames of a walkthrough to images");
    addCommonOptions(*c, render.common, kHeadlessShaded);
    addRenderOwnOptions(*c, render);
    return c;
}

} // namespace

void addBenchOwnOptions(CLI::App& command, BenchOptions& bench) {
    CLI::App* c = &command;
    c->add_option("--method", bench.methods, "Methods, comma-separated: " + methodNames() + " (chcrt methods)")
        ->capture_default_str();
    c->add_option("--ray-type", bench.rayTypes, "Ray types, comma-separated: primary, shadow, ao, diffuse")
        ->capture_default_str();
    c->add_option("--runs", bench.runs, "Timed runs (the median is reported)")->capture_default_str();
    c->add_option("--warmup", bench.warmupRuns, "Untimed warm-up runs")->capture_default_str();
    c->add_flag("--steps", bench.steps,
                "Also count BVH traversal steps (inner nodes + leaves + triangles) per active ray for bvh and the chcrt "
                "methods, in the last timed run (CHC+RT: one extra untimed trace per pass from the timed trace's hit "
                "hints, or pure BVH's steps where the adaptive choice traced a pure pass; column steps/ray, JSON "
                "steps_per_ray)");
    c->add_option("--reference-supersample", bench.referenceSupersample,
                  "Approximate methods (Line Space, chcrt-aggressive, chcrt-lod): also compare their frames with the exact "
                  "reference rendered at KxK the resolution and box-filtered down, and the exact 1-sample frame with it "
                  "(the sampling error any method that drops sub-pixel detail is measured against); columns filtered "
                  "PSNR dB and exact filtered dB, JSON image_error.filtered_psnr_db and sampling_floor_psnr_db. 1 = off")
        ->check(CLI::Range(1, 4))
        ->capture_default_str();
    c->add_option("--json", bench.jsonFile, "Write the table as JSON ({\"rows\": [...]})");
    c->add_option("--csv", bench.csvFile, "Write the table as CSV");
    c->add_option("--markdown", bench.markdownFile, "Write the table as markdown");
}

namespace {

CLI::App* addBench(CLI::App& cli, BenchOptions& bench) {
    CLI::App* c = cli.add_subcommand("bench", "Compare tracing methods on the same rays (table, JSON, CSV)");
    addCommonOptions(*c, bench.common, kHeadlessShaded); // --effects: frames of the image-error comparison
    addBenchOwnOptions(*c, bench);
    return c;
}

CLI::App* addVerify(CLI::App& cli, VerifyOptions& verify) {
    CLI::App* c = cli.add_subcommand("verify", "Check a tracing method's hits against Embree; exit 4 on differences");
    addCommonOptions(*c, verify.common, kHeadlessCommands);
    c->add_option("--method", verify.method,
                  "Method to check: bvh (against Embree) or another GPU method (against pure BVH, exactly): " +
                      methodNames(false))
        ->capture_default_str();
    c->add_option("--ray-type", verify.rayTypes, "Ray types, comma-separated: primary, shadow, ao, diffuse")
        ->capture_default_str();
    // Counts: a negative one is a slip (-1 would wrap to "any number tolerated" and switch the check off).
    c->add_option("--max-diff", verify.maxDiffering, "Differing pixels tolerated")
        ->check(notNegative())
        ->capture_default_str();
    c->add_option("--show-diff", verify.showDifferences, "Print up to N differing pixels with their ray and both hits")
        ->check(notNegative());
    c->add_option("--reference", verify.reference,
                  "What the hits are compared with: auto (Embree for bvh, pure BVH tracing for the other methods), "
                  "embree (within the stated tolerance), or pure BVH tracing in the fragment or compute stage, "
                  "exactly (--method bvh --shader-stage compute --reference fragment: the two stages bit for bit)")
        ->check(CLI::IsMember({"auto", "embree", "fragment", "compute"}))
        ->capture_default_str();
    return c;
}

CLI::App* addInfo(CLI::App& cli, InfoOptions& info) {
    CLI::App* c = cli.add_subcommand("info", "Print the OpenGL renderer, its limits and scene statistics");
    addCommonOptions(*c, info.common, kHeadlessCommands);
    c->add_flag("--no-scene", info.noScene, "Only the OpenGL information");
    c->add_flag("--devices", info.devices,
                "List the EGL devices (index for --gl-device, software or hardware, the driver's names, the OpenGL "
                "renderer each one creates) and the OpenGL information of the device --gl-device picks; no scene");
    c->add_flag("--check", info.check, "Prepared scenes: read every subtree and verify its checksum (exit 4 when one "
                                       "fails; opening checks only the header and metadata)");
    return c;
}

CLI::App* addMethods(CLI::App& cli, MethodsOptions& methods) {
    CLI::App* c = cli.add_subcommand("methods", "List the tracing methods: exact or approximate, what they need");
    c->add_flag("--markdown", methods.markdown, "As a markdown table (docs/cli.md)");
    return c;
}

CLI::App* addPrepare(CLI::App& cli, PrepareCommandOptions& prepare) {
    CLI::App* c = cli.add_subcommand(
        "prepare", "Write a prepared scene (.chs: BVH cut into termination subtrees) for out-of-core rendering");
    c->add_option("--scene", prepare.scene, "Generator spec (city:140m), grid:NxM:<scene>, or scene file")->required();
    c->add_option("-o,--output", prepare.output, "Output file (.chs)")->required();
    c->add_option("--memory-mb", prepare.memoryMb, "Peak memory budget of the preparation")->capture_default_str();
    c->add_option("--subtree-triangles", prepare.subtreeTriangles, "Termination subtree triangle limit")
        ->capture_default_str();
    c->add_option("--subtree-height", prepare.subtreeHeight, "Termination subtree height limit")->capture_default_str();
    c->add_option("--lod-levels", prepare.lodLevels,
                  "Level-of-detail proxy levels per subtree for chcrt-lod (errors of 0.2 %, 1 %, ... of the subtree's "
                  "extent; the last one clusters to 1/64 of its triangles; 0 = none, at most 4)")
        ->capture_default_str();
    c->add_option("--grid", prepare.grid, "NxM copies of the scene (like the paper's Powerplant x 16)");
    c->add_option("--layout", prepare.layout,
                  "Subtree layout: compact (quantized nodes, indexed triangles: about half the bytes to read and "
                  "upload) or full (the layout of files before version 3)")
        ->check(CLI::IsMember({"compact", "full"}))
        ->capture_default_str();
    c->add_flag("-q,--quiet", prepare.quiet, "No progress bar");
    return c;
}

CLI::App* addView(CLI::App& cli, ViewOptions& view) {
    CLI::App* c = cli.add_subcommand("view", "Interactive walkthrough viewer (GLFW window, ImGui panel; build/bin/chcrt-view)");
    addViewOptions(*c, view);
    return c;
}

// The words after `view`, for chcrt-view.
std::vector<std::string> argumentsAfter(const char* command, int argc, char** argv) {
    const auto end = argv + argc;
    const auto at = std::find_if(argv + 1, end, [command](const char* a) { return std::strcmp(a, command) == 0; });
    return at == end ? std::vector<std::string>{} : std::vector<std::string>(at + 1, end);
}

int run(int argc, char** argv) {
    CLI::App cli{"chcrt: hybrid raster/ray-trace renderer (CHC+RT, Line Space, out-of-core)", "chcrt"};
    cli.set_version_flag("--version", "chcrt 0.1.0");
    cli.require_subcommand(1);
    RenderOptions demo, render;
    BenchOptions bench;
    VerifyOptions verify;
    InfoOptions info;
    MethodsOptions methods;
    PrepareCommandOptions prepare;
    ViewOptions view;
    FarmOptions farm;
    ReportOptions report;
    CLI::App* demoCommand = addDemo(cli, demo);
    CLI::App* renderCommand = addRender(cli, render);
    CLI::App* benchCommand = addBench(cli, bench);
    CLI::App* verifyCommand = addVerify(cli, verify);
    CLI::App* infoCommand = addInfo(cli, info);
    CLI::App* methodsCommand = addMethods(cli, methods);
    CLI::App* prepareCommand = addPrepare(cli, prepare);
    CLI::App* viewCommand = addView(cli, view);
    addFarm(cli, farm);
    CLI::App* reportCommand = addReport(cli, report);
    if (const std::optional<int> exit = parseCommandLine(cli, argc, argv)) return *exit;

    if (*demoCommand) return runRender(demo);
    if (*renderCommand) {
        render.words = argumentsAfter("render", argc, argv);
        return runRender(render);
    }
    if (*benchCommand) return runBench(bench);
    if (*verifyCommand) return runVerify(verify);
    if (*infoCommand) return runInfo(info);
    if (*methodsCommand) return runMethods(methods);
    if (*viewCommand) return runView(view, argumentsAfter("view", argc, argv));
    if (*prepareCommand) return runPrepare(prepare);
    if (*reportCommand) return runReport(report);
    if (farmSelected(farm)) {
        farm.words = argumentsAfter(*farm.submitCommand ? "submit" : "bench", argc, argv);
        return runFarm(farm);
    }
    return kExitBadInput;
}

} // namespace
} // namespace chcrt::app

int main(int argc, char** argv) {
    return chcrt::app::runReportingErrors([&] { return chcrt::app::run(argc, argv); });
}
