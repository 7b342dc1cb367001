#pragma once
// The subcommands of build/bin/chcrt. Each returns the process exit code (docs/cli.md):
//   0 success, 1 internal error, 2 bad input or usage, 3 OpenGL/shader failure, 4 check failed (verify found
//   differing pixels or rays that hit the shader loop cap).
#include "app/farm.h"
#include "app/options.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace chcrt::app {

enum ExitCode { kExitOk = 0, kExitInternal = 1, kExitBadInput = 2, kExitGl = 3, kExitCheckFailed = 4 };

struct RenderOptions {
    CommonOptions common;
    std::string output;
    bool demo = false;
    std::string method = "bvh";  // GPU tracing method (app/methods.h)
    std::string debugImage;      // CHC+RT debug image instead of the shaded frame: overdraw|subtrees|batches|cost
    std::string records;         // --records: per-frame records, JSON Lines (app/render_records.h)
    bool resume = false;         // --resume: skip the frames --records proves done
    std::string resourceLog;     // --resource-log: a JSON line of the process's resources every resourceEvery frames
    int resourceEvery = 100;     // (app/resource_log.h)
    std::vector<std::string> words; // the command line after "render" (flags digest of the records)
};
// Registers render's own flags (-o, --method, --debug-image, --records, --resume, --resource-log, --resource-every)
// on a command (render, farm submit).
void addRenderOwnOptions(CLI::App& command, RenderOptions& render);
int runRender(const RenderOptions& options);

struct BenchOptions {
    CommonOptions common;
    std::string methods = "bvh,embree";
    std::string rayTypes = "primary";
    int runs = 5;
    int warmupRuns = 1;
    bool steps = false; // --steps: BVH traversal steps per active ray of bvh and CHC+RT (untimed extra traces)
    int referenceSupersample = 1; // --reference-supersample: approximate methods' image error also against K×K-filtered exact frames
    std::string jsonFile, csvFile, markdownFile;
};
int runBench(const BenchOptions& options);
// Registers bench's own flags (--method, --ray-type, --runs, --warmup, --steps, --json, --csv, --markdown).
void addBenchOwnOptions(CLI::App& command, BenchOptions& bench);

struct VerifyOptions {
    CommonOptions common;
    std::string method = "bvh";
    std::string rayTypes = "primary";
    uint64_t maxDiffering = 0;
    int showDifferences = 0; // print this many differing pixels with both hits
    // What the method is compared with: auto (Embree for bvh, pure BVH tracing otherwise), embree, or pure BVH
    // tracing in a given shader stage, exactly: fragment | compute (bvh in one stage against the other).
    std::string reference = "auto";
};
int runVerify(const VerifyOptions& options);

struct InfoOptions {
    CommonOptions common;
    bool noScene = false;
    bool check = false; // --check: read every subtree of a prepared scene and verify its checksum (exit 4 if any fails)
    bool devices = false; // --devices: list the EGL devices (and what auto picks) instead of the scene
};
int runInfo(const InfoOptions& options);

// `chcrt methods`: the registered tracing methods (app/methods.h) as a table; --markdown for docs/cli.md.
struct MethodsOptions {
    bool markdown = false;
};
int runMethods(const MethodsOptions& options);

// `chcrt prepare`: writes a prepared scene (.chs) for out-of-core rendering (app/command_prepare.cpp).
struct PrepareCommandOptions {
    std::string scene;
    std::string output;
    uint64_t memoryMb = 2048;
    uint32_t subtreeTriangles = 1u << 16;
    uint32_t subtreeHeight = 24;
    uint32_t lodLevels = 3; // outofcore::kDefaultLodLevels (checked in command_prepare.cpp)
    std::string grid; // "NxM" copies
    std::string layout = "compact"; // subtree blobs: compact (version 3) | full (versions 1 and 2)
    bool quiet = false;
};
int runPrepare(const PrepareCommandOptions& options);

// `chcrt view`: the interactive walkthrough viewer (app/viewer/), a program of its own (build/bin/chcrt-view,
// which links GLFW and Dear ImGui; the CLI does not). `chcrt view ARGS` checks ARGS (addViewOptions) and runs
// chcrt-view ARGS from its own directory (app/command_view.cpp). Without CHCRT_BUILD_VIEWER it reports that the
// viewer was not built and returns kExitBadInput (app/viewer/viewer_disabled.cpp).
struct ViewOptions {
    ViewOptions();                 // the viewer's defaults: a 1280×720 window, 1 spp, shadows only
    CommonOptions common;          // width/height: window size
    std::string method = "bvh";    // "raster" or a GPU method
    std::string viewMode = "shaded";
    float renderScale = 0.5f;      // internal resolution / window resolution
    std::string script;            // scripted session (app/viewer/viewer_script.h)
    std::string recordFile = "walkthrough.json";
    bool play = false;             // start playing the camera path
    bool noAccumulate = false;
    bool hidePanel = false;
    std::string resourceLog;       // --resource-log, --resource-every (app/resource_log.h)
    int resourceEvery = 100;
};
// The flags of `chcrt view` (the CLI and chcrt-view parse the same ones).
void addViewOptions(CLI::App& command, ViewOptions& options);
// --resource-log FILE and --resource-every N (render, farm submit, view).
void addResourceLogOptions(CLI::App& command, std::string& file, int& every);
// Checks what the flags' parser cannot before a window opens (image size, samples, effects: toRenderSettings); throws
// InputError, so `chcrt view --width 0` is a usage error (exit 2), not a failed window (exit 3).
void checkViewOptions(const ViewOptions& options);
// `arguments`: the words after `view`, handed to chcrt-view unchanged.
int runView(const ViewOptions& options, const std::vector<std::string>& arguments);

// `chcrt farm submit|bench|status|collect` (app/command_farm.cpp, docs/farm.md).
struct FarmOptions {
    RenderOptions render;         // farm submit: the render flags every task runs with
    BenchOptions bench;           // farm bench: --scene and --camera-path take comma-separated lists
    farm::SlurmOptions slurm;
    int chunk = 10;               // frames per array task
    bool print = false, wait = false, force = false;
    std::string target;           // status, collect: the submission's collected output or its .farm directory
    std::string output;           // collect -o
    bool partial = false;         // collect --partial
    std::vector<std::string> words; // the command line after "submit" / "bench"
    CLI::App* submitCommand = nullptr;
    CLI::App* benchCommand = nullptr;
    CLI::App* statusCommand = nullptr;
    CLI::App* collectCommand = nullptr;
};
void addFarm(CLI::App& cli, FarmOptions& farm);
bool farmSelected(const FarmOptions& farm);
int runFarm(FarmOptions& farm);

// `chcrt report`: a comparison's benches and renders, or bench JSON, as an HTML page, markdown tables and figures
// (app/command_report.cpp, app/report_plan.h, docs/report.md).
struct ReportOptions;
CLI::App* addReport(CLI::App& cli, ReportOptions& report);
int runReport(const ReportOptions& options);

// Splits "a,b,c"; an empty list or a name given twice is an InputError.
std::vector<std::string> splitList(const std::string& text);

// Runs `body` and turns the library's errors into a one-line message on stderr and an exit code: InputError 2,
// GlError 3, anything else 1 (caught here, once, for both programs).
int runReportingErrors(const std::function<int()>& body);
// Parses the command line: nullopt when the program should go on, else its exit code (help and version 0, usage
// errors 2 with a one-line message).
std::optional<int> parseCommandLine(CLI::App& cli, int argc, char** argv);

} // namespace chcrt::app
