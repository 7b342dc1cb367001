// `chcrt report`: runs the benches and renders of a preset (app/report_plan.h) as child processes of this binary,
// one per group, or takes existing bench JSON (--from-json), and hands the data to
// scripts/report/chcrt_report.py, which writes the figures (PNG, SVG, CSV), index.html and report.md.
// Children, not calls: each bench then starts from a fresh GL context and process, as when run by hand, its
// command line is the exact one to reproduce it, and a group's output exists only once it finished (bench writes
// its JSON atomically), so an interrupted report resumes from the groups already measured.
#include "app/commands.h"
#include "app/report.h"
#include "app/report_plan.h"
#include "renderer/core/error.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>
#include <unistd.h>

#ifndef CHCRT_SOURCE_DIR
#define CHCRT_SOURCE_DIR ""
#endif

namespace fs = std::filesystem;

namespace chcrt::app {

CLI::App* addReport(CLI::App& cli, ReportOptions& r) {
    CLI::App* c = cli.add_subcommand("report", "Run a comparison (or read bench JSON) and write an HTML page, "
                                               "markdown tables and figures (docs/cli.md#report)");
    c->add_option("--out", r.out, "Report folder: index.html, report.md, figures/, data/, images/")->required();
    auto* preset = c->add_option("--preset", r.preset, "What to run: " + presetNames())->capture_default_str();
    auto* from = c->add_option("--from-json", r.fromJson, "Report these bench JSON files instead of running benches");
    struct Flag { const char* name; std::string* value; const char* help; };
    for (const Flag& f : std::initializer_list<Flag>{
             {"--scenes", &r.scenes, "Scenes: generator specs or files, each optionally @near, @far or @path.json"},
             {"--paths", &r.paths, "Paths of the generated scenes: near, far or camera path files"},
             {"--methods", &r.methods, "Methods of the compare study (bvh, the reference, always runs)"},
             {"--ray-types", &r.rayTypes, "Ray types: primary, shadow, ao, diffuse"},
             {"--studies", &r.studies, "Studies: compare, aggressive, rotation, work, ls-rc, ls-ao, ls-ss, "
                                       "ls-sscand, ls-ntree, images"},
             {"--frames", &r.frames, "Frames of the walkthroughs (bench --frames)"},
             {"--spp", &r.spp, "Samples per pixel: N, or type=N,... per ray type"},
             {"--thresholds", &r.thresholds, "aggressive: --chcrt-threshold values"},
             {"--rotations", &r.rotations, "rotation: --rotation values (degrees)"},
             {"--heights", &r.heights, "work: --chcrt-height values"},
             {"--ls-depths", &r.lsDepths, "ls-rc, ls-ao: --ls-depth values"},
             {"--ls-ss-n", &r.lsSsN, "ls-ss: --ls-n values"},
             {"--ls-ntree", &r.lsNtree, "ls-ntree: --ls-ntree N:d values"},
             {"--ls-ss-candidate", &r.lsSsCandidate, "ls-sscand: N:D pairs"},
             {"--ls-cache", &r.lsCache, "Line Space cache folder of the benches (bench --ls-cache)"},
             {"--gl", &r.gl, "Headless OpenGL context of every command: egl, osmesa"}}) {
        c->add_option(f.name, *f.value, f.help)->excludes(from);
    }
    struct Number { const char* name; int* value; const char* help; };
    for (const Number& n : std::initializer_list<Number>{
             {"--size", &r.size, "Image width = height"},
             {"--runs", &r.runs, "Timed runs per bench (min/max spread of the speedups)"},
             {"--warmup", &r.warmup, "Untimed warm-up runs per bench"},
             {"--single-view-runs", &r.singleViewRuns, "Timed runs of a scene's single view (no walkthrough)"},
             {"--ls-spp", &r.lsSpp, "ls-rc, ls-ao: samples per pixel"},
             {"--ls-n", &r.lsN, "ls-rc, ls-ao: --ls-n"},
             {"--ls-ss-depth", &r.lsSsDepth, "ls-ss: --ls-depth"},
             {"--ls-ntree-near", &r.lsNtreeNear, "ls-ntree: --ls-ntree-near"}}) {
        c->add_option(n.name, *n.value, n.help)->check(CLI::NonNegativeNumber)->excludes(from);
    }
    preset->excludes(from);
    c->add_flag("-q,--quiet", r.quiet, "No progress lines");
    return c;
}

namespace {

std::string shellQuote(const std::string& word) {
    if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                                "_-+=.,:/@") == std::string::npos) {
        return word;
    }
    std::string out = "'";
    for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// Runs `program args` with stdout and stderr into `log` (or inherited when empty); the exit status, 128 + signal.
int runChild(const std::string& program, const std::vector<std::string>& args, const fs::path& log) {
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        if (!log.empty()) {
            const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (fd >= 0) {
                dup2(fd, 1);
                dup2(fd, 2);
                close(fd);
            }
        }
        std::vector<char*> argv = {const_cast<char*>(program.c_str())};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execvp(program.c_str(), argv.data());
        _exit(127);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) throw std::runtime_error("waitpid failed");
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string lastLine(const fs::path& log) {
    std::ifstream in(log);
    std::string line, last;
    while (std::getline(in, line)) {
        if (!line.empty()) last = line;
    }
    return last;
}

nlohmann::json readJson(const fs::path& file) {
    std::ifstream in(file);
    if (!in) throw InputError(file.string() + ": cannot read");
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw InputError(file.string() + ": malformed JSON (" + std::string(e.what()) + ")");
    }
}

// A bench JSON the report can read: rows with the fields every table uses.
void checkBenchJson(const fs::path& file) {
    const nlohmann::json j = readJson(file);
    if (!j.is_object() || !j.contains("rows") || !j["rows"].is_array() || j["rows"].empty()) {
        throw InputError(file.string() + ": not chcrt bench JSON (no \"rows\")");
    }
    for (const nlohmann::json& row : j["rows"]) {
        for (const char* key : {"scene", "path", "ray_type", "method", "ms_median", "ms_runs", "speedup_vs_bvh"}) {
            if (!row.is_object() || !row.contains(key)) {
                throw InputError(file.string() + ": a row has no \"" + std::string(key) + "\" (not chcrt bench JSON)");
            }
        }
    }
}

// Whether a group's output was made by exactly this group's commands (a resumed report keeps it).
bool alreadyMeasured(const ReportGroup& g, const fs::path& out) {
    if (g.images) {
        const fs::path sidecar = out / "images" / (g.id + ".json");
        if (!fs::exists(sidecar)) return false;
        for (const auto& [key, file] : g.files) {
            if (!fs::exists(out / file)) return false;
        }
        try {
            return readJson(sidecar).value("commands", nlohmann::json()) == nlohmann::json(g.commands);
        } catch (const InputError&) {
            return false;
        }
    }
    const fs::path json = out / "data" / (g.id + ".json");
    if (!fs::exists(json)) return false;
    try {
        const nlohmann::json j = readJson(json);
        std::vector<std::string> words = j.value("command_line", std::vector<std::string>{});
        if (words.empty()) return false;
        words.erase(words.begin()); // the binary, wherever it was
        return words == g.commands.front();
    } catch (const std::exception&) {
        return false;
    }
}

std::string minutes(double seconds) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%d:%02d", int(seconds) / 60, int(seconds) % 60);
    return buffer;
}

// The report folder: created (with data/ and images/) only after every input was checked.
fs::path makeOutDir(const std::string& out) {
    const fs::path dir = out;
    std::error_code error;
    fs::create_directories(dir / "data", error);
    if (!error) fs::create_directories(dir / "images", error);
    if (error) throw InputError("--out " + out + ": cannot create (" + error.message() + ")");
    const fs::path probe = dir / "data" / ".write-test";
    if (!std::ofstream(probe)) throw InputError("--out " + out + ": not writable");
    fs::remove(probe);
    return dir;
}

struct GroupRun {
    nlohmann::json record;
    double seconds = 0;
    bool resumed = false;
};

// Runs one group's commands; throws with the child's exit code on failure (its log names what went wrong).
GroupRun runGroup(const ReportGroup& g, const fs::path& out, const std::string& self) {
    GroupRun run;
    run.resumed = alreadyMeasured(g, out);
    const auto start = std::chrono::steady_clock::now();
    const fs::path log = out / (g.images ? "images" : "data") / (g.id + ".log");
    for (size_t i = 0; i < g.commands.size() && !run.resumed; ++i) {
        const int code = runChild(self, g.commands[i], log);
        if (code != 0) {
            std::fprintf(stderr, "chcrt: error: report group %s failed (exit %d): %s (log: %s)\n", g.id.c_str(), code,
                         lastLine(log).c_str(), log.c_str());
            throw code;
        }
    }
    if (g.images && !run.resumed) writeJsonFile(out / "images" / (g.id + ".json"), {{"commands", g.commands}});
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    nlohmann::json commands = nlohmann::json::array();
    for (const auto& c : g.commands) {
        std::string line = shellQuote(self);
        for (const std::string& w : c) {
            line += ' ';
            line += shellQuote(w);
        }
        commands.push_back(line);
    }
    run.record = {{"id", g.id}, {"study", g.study}, {"label", g.label}, {"kind", g.images ? "images" : "bench"},
                  {"scene", g.scene}, {"path", g.path}, {"commands", commands}, {"resumed", run.resumed},
                  {"seconds", run.seconds}};
    if (g.images) {
        run.record["files"] = g.files;
        run.record["frame"] = g.frame;
    } else {
        run.record["json"] = "data/" + g.id + ".json";
    }
    return run;
}

// Runs every group with a progress line each (row, elapsed, ETA from the measured time per unit of work).
nlohmann::json runGroups(const std::vector<ReportGroup>& groups, const fs::path& out, bool quiet) {
    const std::string self = fs::read_symlink("/proc/self/exe").string();
    double totalCost = 0, doneCost = 0, measuredCost = 0, measuredSeconds = 0;
    for (const ReportGroup& g : groups) totalCost += g.cost;
    const auto start = std::chrono::steady_clock::now();
    nlohmann::json records = nlohmann::json::array();
    for (size_t i = 0; i < groups.size(); ++i) {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!quiet) {
            const std::string eta = measuredCost > 0 ? ", ETA " + minutes(measuredSeconds / measuredCost * (totalCost - doneCost)) : "";
            std::fprintf(stderr, "report: [%zu/%zu] %s (elapsed %s%s)\n", i + 1, groups.size(), groups[i].label.c_str(),
                         minutes(elapsed).c_str(), eta.c_str());
        }
        GroupRun run = runGroup(groups[i], out, self);
        if (!run.resumed) {
            measuredCost += groups[i].cost;
            measuredSeconds += run.seconds;
        } else if (!quiet) {
            std::fprintf(stderr, "report:   already measured by the same command, kept\n");
        }
        doneCost += groups[i].cost;
        records.push_back(run.record);
    }
    return records;
}

fs::path reportScript() {
    const fs::path self = fs::read_symlink("/proc/self/exe");
    for (const fs::path& candidate : {fs::path(CHCRT_SOURCE_DIR) / "scripts/report/chcrt_report.py",
                                      self.parent_path() / "../../scripts/report/chcrt_report.py"}) {
        if (!candidate.empty() && fs::exists(candidate)) return fs::canonical(candidate);
    }
    throw InputError("scripts/report/chcrt_report.py not found next to the sources (" + std::string(CHCRT_SOURCE_DIR) + ")");
}

// A Python 3 with matplotlib: $CHCRT_PYTHON, Debian's /usr/bin/python3 (python3-matplotlib), or python3 on PATH
// (which may be a virtual environment or pyenv shim without it). Checked before anything is written.
std::string findPython() {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("CHCRT_PYTHON"); env && *env) candidates.push_back(env);
    candidates.insert(candidates.end(), {"/usr/bin/python3", "python3"});
    for (const std::string& python : candidates) {
        if (runChild(python, {"-c", "import matplotlib"}, "/dev/null") == 0) return python;
    }
    throw InputError("no python3 with matplotlib found (tried $CHCRT_PYTHON, /usr/bin/python3, python3; "
                     "scripts/setup.sh installs python3-matplotlib)");
}

int report(const ReportOptions& options) {
    const fs::path script = reportScript();
    const std::string python = findPython();
    const MachineSnapshot before = takeMachineSnapshot();
    nlohmann::json manifest = {{"command_line", processCommandLine()}, {"from_json", !options.fromJson.empty()}};
    std::vector<ReportGroup> groups;
    if (options.fromJson.empty()) {
        const ReportSettings settings = reportSettings(options);
        groups = planReport(settings, options.out);
        manifest["preset"] = options.preset;
        manifest["studies"] = settings.studies;
    } else {
        for (const std::string& f : options.fromJson) checkBenchJson(f);
    }
    const bool existed = fs::exists(options.out);
    const fs::path out = makeOutDir(options.out);
    if (options.fromJson.empty()) {
        manifest["groups"] = runGroups(groups, out, options.quiet);
    } else {
        manifest["groups"] = nlohmann::json::array();
        for (const std::string& f : options.fromJson) {
            manifest["groups"].push_back({{"id", fs::path(f).stem().string()}, {"study", "from-json"}, {"kind", "bench"},
                                          {"json", fs::absolute(f).string()}, {"resumed", false}});
        }
    }
    manifest["machine"] = machineJson(before, takeMachineSnapshot());
    const fs::path manifestFile = out / "data" / "report.json";
    writeJsonFile(manifestFile, manifest);
    if (!options.quiet) std::fprintf(stderr, "report: writing figures and pages into %s\n", options.out.c_str());
    const int code = runChild(python, {script.string(), manifestFile.string(), out.string()}, "");
    if (code != 0) {
        // Bad input the script found (it said why): a report of given JSON leaves no folder behind. Measured
        // groups stay, so that a fixed report resumes from them.
        if (code == kExitBadInput && !existed && !options.fromJson.empty()) fs::remove_all(out);
        if (code != kExitBadInput) std::fprintf(stderr, "chcrt: error: %s failed (exit %d)\n", script.c_str(), code);
        return code == kExitBadInput ? kExitBadInput : kExitInternal;
    }
    std::printf("report: %s\n", (out / "index.html").c_str());
    return kExitOk;
}

} // namespace

int runReport(const ReportOptions& options) {
    try {
        return report(options);
    } catch (int code) { // a child failed; it said why
        return code;
    }
}

} // namespace chcrt::app
