// `chcrt farm submit|bench|status|collect`: walkthroughs and comparison runs as Slurm job arrays (docs/farm.md).
// The farm directory's files and the sbatch script are app/farm.h; this file checks the flags, decides what is
// left to do from the records, runs sbatch and squeue, and writes the collected JSON.
#include "app/build_info.h"
#include "app/commands.h"
#include "app/farm.h"
#include "app/methods.h"
#include "app/render_records.h"
#include "app/report.h"
#include "culling/chcrt_tracer.h"
#include "renderer/core/error.h"
#include "renderer/core/frame_range.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sys/wait.h>

namespace chcrt::app {
namespace fs = std::filesystem;
using farm::Kind;

namespace {

// Farm flags: taken out of the words handed to the tasks (render or bench never see them).
const std::vector<std::string> kFarmFlagsWithValue = {"--chunk", "--partition", "--time",  "--mem",
                                                      "--cpus-per-task", "--gpus-per-task", "--gres",
                                                      "--account", "--sbatch-arg", "--job-name"};
const std::vector<std::string> kFarmSwitches = {"--print", "--wait", "--force"};

void addSubmitOptions(CLI::App& c, FarmOptions& f) {
    c.add_option("--partition", f.slurm.partition, "Slurm partition (sbatch --partition)");
    c.add_option("--time", f.slurm.time, "Time limit per task (sbatch --time)");
    c.add_option("--mem", f.slurm.mem, "Memory per task (sbatch --mem)");
    c.add_option("--cpus-per-task", f.slurm.cpusPerTask, "CPUs per task (sbatch --cpus-per-task)")
        ->check(CLI::Range(1, 4096));
    c.add_option("--gpus-per-task", f.slurm.gpusPerTask,
                 "GPUs per task (sbatch --gpus-per-task); each task renders on the GPU Slurm binds (--gl-device)")
        ->check(CLI::Range(1, 64));
    c.add_option("--gres", f.slurm.gres, "Generic resources per task (sbatch --gres, e.g. gpu:1)");
    c.add_option("--account", f.slurm.account, "Slurm account (sbatch --account)");
    c.add_option("--job-name", f.slurm.jobName, "Job name (default chcrt-render or chcrt-bench)");
    c.add_option("--sbatch-arg", f.slurm.extra, "Any other sbatch argument, one per flag (--sbatch-arg=--qos=high)");
    c.add_flag("--print", f.print, "Write the farm directory and print the sbatch script; submit nothing");
    c.add_flag("--wait", f.wait, "Wait for every task (sbatch --wait); exit with the worst task's exit code");
    c.add_flag("--force", f.force, "Render or measure everything again, even what the records prove done");
}

std::string timestamp() {
    const std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return text;
}

// Runs a command, returns its exit code and its stdout (stderr passes through); `echo` prints stdout lines too.
struct CommandResult {
    int exitCode = -1;
    std::string output;
};
CommandResult runCommand(const std::string& command, bool echo = false) {
    CommandResult r;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> line;
    while (std::fgets(line.data(), int(line.size()), pipe)) {
        r.output += line.data();
        if (echo) std::fputs(line.data(), stdout), std::fflush(stdout);
    }
    const int status = ::pclose(pipe);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    return r;
}

bool haveProgram(const std::string& name) { return runCommand("command -v " + name + " >/dev/null 2>&1").exitCode == 0; }

nlohmann::json readJsonOrNull(const fs::path& file) {
    std::ifstream in(file);
    if (!in) return nullptr;
    return nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
}

fs::path manifestPath(const fs::path& dir) { return dir / "manifest.json"; }

// Array tasks of earlier submissions of this directory that Slurm still lists (queued or running).
std::set<std::string> queuedTasks(const nlohmann::json& manifest) {
    std::set<std::string> queued;
    if (!manifest.is_object() || !manifest.contains("submissions") || !haveProgram("squeue")) return queued;
    for (const nlohmann::json& s : manifest["submissions"]) {
        const std::string job = s.value("job", "");
        if (job.empty()) continue;
        const CommandResult r = runCommand("squeue -h -r -j " + farm::shellQuote(job) + " -o %i 2>/dev/null");
        std::istringstream lines(r.output);
        for (std::string id; lines >> id;) queued.insert(id);
    }
    return queued;
}

// What Slurm says of the array tasks of every submitted job ("<job>_<task>" -> state): `sacct` where the cluster
// keeps accounting, else `scontrol show job`, which knows a finished job for MinJobAge seconds (300 by default).
// Empty without Slurm's commands or when neither knows the job any more.
std::map<std::string, farm::SlurmTaskState> slurmTaskStates(const nlohmann::json& manifest) {
    std::map<std::string, farm::SlurmTaskState> states;
    if (!manifest.is_object() || !manifest.contains("submissions")) return states;
    const bool sacct = haveProgram("sacct"), scontrol = haveProgram("scontrol");
    for (const nlohmann::json& s : manifest["submissions"]) {
        const std::string job = s.value("job", "");
        if (job.empty()) continue;
        std::map<int, farm::SlurmTaskState> tasks;
        if (sacct) {
            const CommandResult r = runCommand("sacct -X -n -P -j " + farm::shellQuote(job) +
                                               " --format=JobID,State,ExitCode,NodeList 2>/dev/null");
            if (r.exitCode == 0) tasks = farm::parseSacctTasks(r.output, job);
        }
        if (tasks.empty() && scontrol) {
            const CommandResult r = runCommand("scontrol show job -o " + farm::shellQuote(job) + " 2>/dev/null");
            if (r.exitCode == 0) tasks = farm::parseScontrolTasks(r.output, job);
        }
        for (const auto& [index, state] : tasks) states[job + "_" + std::to_string(index)] = state;
    }
    return states;
}

// Refuses to submit over a submission that is still running: its tasks would render the same frames twice.
void refuseWhileQueued(const nlohmann::json& manifest, const fs::path& dir) {
    const std::set<std::string> queued = queuedTasks(manifest);
    if (!queued.empty()) {
        throw InputError("farm: " + std::to_string(queued.size()) + " task(s) of an earlier submission in " +
                         dir.string() + " are still queued or running (" + *queued.begin() +
                         (queued.size() > 1 ? ", ..." : "") + "): wait for them or scancel them first");
    }
}

fs::path absoluteBinary() {
    std::error_code error;
    const fs::path self = fs::read_symlink("/proc/self/exe", error);
    if (error) throw InputError("farm: cannot find the chcrt binary (/proc/self/exe)");
    return self;
}

// Writes the script and submits it (or prints it); records the submission in the manifest. Returns the exit code.
int submitPlan(const farm::Plan& plan, nlohmann::json manifest, const FarmOptions& f, const std::string& what) {
    fs::create_directories(plan.directory / "parts");
    fs::create_directories(plan.directory / "logs");
    const size_t number = manifest["submissions"].size();
    const fs::path script = plan.directory / ("job-" + std::to_string(number) + ".sbatch");
    writeTextFileAtomically(script, farm::sbatchScript(plan));
    fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
    nlohmann::json labels = nlohmann::json::array();
    for (const farm::Task& t : plan.tasks) labels.push_back(t.label);
    // task_labels: what each array index covers, so that status can name the frames or row of a task that Slurm
    // ended before its script could append an exit line.
    nlohmann::json submission = {{"script", script.string()},
                                 {"tasks", plan.tasks.size()},
                                 {"task_labels", labels},
                                 {"submitted", timestamp()}};
    if (f.print) {
        std::ifstream in(script);
        std::printf("%s", std::string(std::istreambuf_iterator<char>(in), {}).c_str());
        std::fprintf(stderr, "farm: wrote %s (%s); not submitted (--print)\n", script.c_str(), what.c_str());
        submission["job"] = "";
        manifest["submissions"].push_back(submission);
        writeJsonFile(manifestPath(plan.directory), manifest);
        return kExitOk;
    }
    const std::string command = "sbatch --parsable" + std::string(f.wait ? " --wait " : " ") + farm::shellQuote(script.string());
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) throw InputError("farm: cannot run sbatch");
    std::array<char, 256> line{};
    std::string job;
    if (std::fgets(line.data(), int(line.size()), pipe)) {
        job = line.data();
        job = job.substr(0, job.find_first_of(";\n"));
    }
    if (!job.empty()) {
        // Recorded before waiting, so that status and a resubmission know the job while it runs.
        submission["job"] = job;
        manifest["submissions"].push_back(submission);
        writeJsonFile(manifestPath(plan.directory), manifest);
        std::printf("Submitted job %s: %zu array task(s), %s\n", job.c_str(), plan.tasks.size(), what.c_str());
        std::fflush(stdout);
    }
    while (std::fgets(line.data(), int(line.size()), pipe)) {}
    const int status = ::pclose(pipe);
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : kExitInternal;
    if (job.empty()) throw InputError("farm: sbatch did not submit the job (exit " + std::to_string(code) + ")");
    if (f.wait) {
        std::printf("job %s finished: worst task exit code %d (chcrt farm status %s)\n", job.c_str(), code,
                    manifest.value("collected", "").c_str());
    }
    return f.wait ? code : kExitOk;
}

farm::Plan basePlan(Kind kind, const fs::path& dir, const FarmOptions& f) {
    farm::Plan plan;
    plan.kind = kind;
    plan.directory = fs::absolute(dir);
    plan.binary = absoluteBinary();
    plan.workingDirectory = fs::current_path();
    plan.slurm = f.slurm;
    return plan;
}

void requireSbatch(const FarmOptions& f) {
    if (!f.print && !haveProgram("sbatch")) {
        throw InputError("farm: sbatch not found (is Slurm installed? scripts/slurm-local.sh start sets up a one-node "
                         "cluster; --print writes the script without submitting)");
    }
}

void warnIfSceneMissing(const std::string& scene) {
    const fs::path p(scene);
    std::error_code error;
    if (p.has_extension() && scene.find(':') == std::string::npos && !fs::exists(p, error)) {
        std::fprintf(stderr, "warning: scene %s does not exist here; the tasks fail unless the nodes have it\n",
                     scene.c_str());
    }
}

// --- render ---------------------------------------------------------------------------------------------------

std::vector<int> explicitFrames(const std::string& text) {
    if (text.empty()) throw InputError("farm submit needs --frames (e.g. 0-299)");
    if (text.rfind("all", 0) == 0 || text.rfind("spread", 0) == 0) {
        throw InputError("farm submit needs explicit --frames (0-299, 0-300:30, 3,5-9), not '" + text +
                         "': the camera path is read on the nodes");
    }
    return parseFrameRange(text);
}

void checkRenderFlags(const FarmOptions& f) {
    const RenderOptions& r = f.render;
    if (r.output.find('#') == std::string::npos) {
        throw InputError("farm submit needs #### in -o (" + r.output + "): every frame gets its own file");
    }
    if (r.common.statsJson.empty()) {
        throw InputError("farm submit needs --stats-json FILE: farm collect writes it, and its .farm directory keeps "
                         "the submission");
    }
    if (!r.records.empty() || r.resume) throw InputError("farm submit keeps its own records: drop --records/--resume");
    if (f.chunk < 1) throw InputError("--chunk must be at least 1");
    findGpuMethod(r.method);
    if (!r.debugImage.empty()) parseChcrtDebugImage(r.debugImage);
    toRenderSettings(r.common, 4); // the settings' own checks
    warnIfSceneMissing(r.common.scene);
}

int submitRender(const FarmOptions& f) {
    checkRenderFlags(f);
    const std::vector<int> frames = explicitFrames(f.render.common.frames);
    const fs::path collected = fs::absolute(f.render.common.statsJson);
    const fs::path dir = farm::farmDirectoryOf(collected);
    // What every task runs: render with the submitted words minus the farm's, the frames and the statistics.
    const std::vector<std::string> renderWords =
        farm::wordsWithout(f.words, kFarmFlagsWithValue, kFarmSwitches);
    const std::vector<std::string> taskWords = farm::wordsWithout(renderWords, {"--frames", "--stats-json"}, {"-q", "--quiet"});
    const std::string digest = flagsDigest(renderWords);
    const std::string commit = buildCommit();
    nlohmann::json old = readJsonOrNull(manifestPath(dir));
    refuseWhileQueued(old, dir);

    std::vector<int> todo = frames;
    if (!f.force) {
        const std::map<int, farm::ProvenFrame> done = farm::provenFrames(dir / "parts", frames, f.render.output, digest, commit);
        todo.clear();
        for (int frame : frames) {
            if (!done.count(frame)) todo.push_back(frame);
        }
        if (todo.empty()) {
            std::printf("farm: all %zu frame(s) are done (records in %s); nothing submitted. chcrt farm collect %s\n",
                        frames.size(), (dir / "parts").c_str(), collected.c_str());
            return kExitOk;
        }
    }
    requireSbatch(f); // only now: a finished sequence needs no Slurm to say so
    farm::Plan plan = basePlan(Kind::Render, dir, f);
    plan.command = {"render"};
    plan.command.insert(plan.command.end(), taskWords.begin(), taskWords.end());
    for (const std::vector<int>& chunk : farm::chunkFrames(todo, f.chunk)) {
        // The whole submission's frame count decides the file names' padding, so a chunk names its frames as a
        // render of all of them would ("####" never truncates; the farm requires it).
        const std::string selection = farm::frameSelection(chunk);
        plan.tasks.push_back({{"--frames", selection, "--records", "%j_%t.jsonl", "--stats-json", "%j_%t.json"},
                              "frames " + selection,
                              chunk,
                              "%j_%t.jsonl"});
    }
    // Records and statistics are written in parts/ (relative words resolve there: see the script's cd below).
    for (farm::Task& t : plan.tasks) {
        t.words[3] = (plan.directory / "parts" / t.words[3]).string();
        t.words[5] = (plan.directory / "parts" / t.words[5]).string();
    }
    const bool sameRun = old.is_object() && old.value("kind", "") == "render" && old.value("flags_digest", "") == digest &&
                         old.value("commit", "") == commit;
    nlohmann::json manifest = {{"kind", "render"},
                               {"collected", collected.string()},
                               {"output", f.render.output},
                               {"frames", frames},
                               {"chunk", f.chunk},
                               {"words", renderWords},
                               {"flags_digest", digest},
                               {"commit", commit},
                               {"submissions", sameRun ? old["submissions"] : nlohmann::json::array()}};
    const std::string what = std::to_string(todo.size()) + " of " + std::to_string(frames.size()) +
                             " frame(s) in chunks of " + std::to_string(f.chunk) + ", records in " +
                             (dir / "parts").string();
    return submitPlan(plan, manifest, f, what);
}

// --- bench ----------------------------------------------------------------------------------------------------

struct BenchRow {
    std::string scene, path, rayType, method;
    std::string label() const { return scene + " " + path + " " + rayType + " " + method; }
};

std::vector<BenchRow> benchRows(const BenchOptions& b) {
    const std::vector<std::string> scenes = splitList(b.common.scene);
    // No --camera-path: each scene's default walkthrough.
    const std::vector<std::string> paths = b.common.cameraPath.empty() ? std::vector<std::string>{""}
                                                                        : splitList(b.common.cameraPath);
    std::vector<BenchRow> rows;
    for (const std::string& scene : scenes) {
        for (const std::string& path : paths) {
            for (const std::string& type : splitList(b.rayTypes)) {
                for (const std::string& method : splitList(b.methods)) rows.push_back({scene, path, type, method});
            }
        }
    }
    return rows;
}

int submitBench(const FarmOptions& f) {
    const BenchOptions& b = f.bench;
    if (b.jsonFile.empty()) throw InputError("farm bench needs --json FILE: farm collect writes the rows there");
    if (b.runs < 1) throw InputError("--runs must be at least 1");
    if (b.warmupRuns < 0) throw InputError("--warmup must not be negative");
    const std::vector<BenchRow> rows = benchRows(b);
    if (rows.empty()) throw InputError("farm bench: no rows (give --scene, --ray-type and --method)");
    for (const BenchRow& r : rows) {
        findMethod(r.method);
        parseRayType(r.rayType);
        warnIfSceneMissing(r.scene);
    }
    toRenderSettings(b.common, 1);
    const fs::path collected = fs::absolute(b.jsonFile);
    const fs::path dir = farm::farmDirectoryOf(collected);
    const std::vector<std::string> taskWords = farm::wordsWithout(
        f.words, [] {
            std::vector<std::string> v = kFarmFlagsWithValue;
            for (const char* flag : {"--scene", "--camera-path", "--method", "--ray-type", "--json", "--csv", "--markdown"}) {
                v.push_back(flag);
            }
            return v;
        }(),
        [] {
            std::vector<std::string> v = kFarmSwitches;
            v.insert(v.end(), {"-q", "--quiet"});
            return v;
        }());
    const std::string commit = buildCommit();
    nlohmann::json old = readJsonOrNull(manifestPath(dir));
    refuseWhileQueued(old, dir);
    const bool sameRun = old.is_object() && old.value("kind", "") == "bench" && old["words"] == taskWords &&
                         old.value("commit", "") == commit && old["rows"].size() == rows.size();
    if (!sameRun) {
        requireSbatch(f); // before the old rows go
        if (fs::exists(dir / "parts")) fs::remove_all(dir / "parts"); // rows of other flags or another build
    }

    farm::Plan plan = basePlan(Kind::Bench, dir, f);
    plan.command = {"bench"};
    plan.command.insert(plan.command.end(), taskWords.begin(), taskWords.end());
    std::vector<size_t> indices; // the array index of each submitted row is its row index (row_<i>.json)
    nlohmann::json rowsJson = nlohmann::json::array();
    for (size_t i = 0; i < rows.size(); ++i) {
        rowsJson.push_back(rows[i].label());
        const fs::path part = plan.directory / "parts" / ("row_" + std::to_string(i) + ".json");
        if (!f.force && readJsonOrNull(part).is_object()) continue;
        farm::Task t;
        t.words = {"--scene", rows[i].scene, "--method", rows[i].method, "--ray-type", rows[i].rayType, "--json", part.string()};
        if (!rows[i].path.empty()) t.words.insert(t.words.end(), {"--camera-path", rows[i].path});
        t.label = rows[i].label();
        t.exitFile = "row_" + std::to_string(i) + ".exit.jsonl"; // the row's, whatever its array index
        plan.tasks.push_back(t);
        indices.push_back(i);
    }
    if (plan.tasks.empty()) {
        std::printf("farm: all %zu bench row(s) are done (%s); nothing submitted. chcrt farm collect %s\n", rows.size(),
                    (dir / "parts").c_str(), collected.c_str());
        return kExitOk;
    }
    requireSbatch(f);
    // Array index = position in plan.tasks, which is not the row index once rows are done: labels name the row.
    for (size_t t = 0; t < plan.tasks.size(); ++t) plan.tasks[t].label = "row " + std::to_string(indices[t]) + ": " + plan.tasks[t].label;
    nlohmann::json manifest = {{"kind", "bench"},
                               {"collected", collected.string()},
                               {"rows", rowsJson},
                               {"words", taskWords},
                               {"commit", commit},
                               {"submissions", sameRun ? old["submissions"] : nlohmann::json::array()}};
    const std::string what = std::to_string(plan.tasks.size()) + " of " + std::to_string(rows.size()) + " bench row(s)";
    return submitPlan(plan, manifest, f, what);
}

// --- status and collect ---------------------------------------------------------------------------------------

struct Submission {
    fs::path dir;
    nlohmann::json manifest;
};

Submission openSubmission(const std::string& target) {
    if (target.empty()) throw InputError("farm: give the submission's --stats-json or --json file (or its .farm directory)");
    fs::path dir = target;
    std::error_code error;
    if (!fs::is_directory(dir, error)) dir = farm::farmDirectoryOf(fs::absolute(target));
    Submission s{dir, readJsonOrNull(manifestPath(dir))};
    if (!s.manifest.is_object() || !s.manifest.contains("kind")) {
        throw InputError("farm: no submission in " + dir.string() + " (" + manifestPath(dir).string() +
                         " is missing or malformed)");
    }
    return s;
}

struct RenderState {
    std::vector<int> frames;
    std::map<int, farm::ProvenFrame> done;
    std::vector<farm::TaskOutcome> tasks;
    std::set<std::string> queued;
    std::map<std::string, farm::SlurmTaskState> slurm; // "<job>_<task>"
};

RenderState renderState(const Submission& s) {
    RenderState st;
    st.frames = s.manifest["frames"].get<std::vector<int>>();
    st.done = farm::provenFrames(s.dir / "parts", st.frames, s.manifest.value("output", ""),
                                 s.manifest.value("flags_digest", ""), s.manifest.value("commit", ""));
    st.tasks = farm::renderTaskOutcomes(s.dir / "parts");
    st.queued = queuedTasks(s.manifest);
    st.slurm = slurmTaskStates(s.manifest);
    return st;
}

// Every array task of every submitted job: "<job>_<task>" and the label it was submitted with.
std::vector<std::pair<std::string, std::string>> submittedTasks(const nlohmann::json& manifest) {
    std::vector<std::pair<std::string, std::string>> tasks;
    for (const nlohmann::json& s : manifest["submissions"]) {
        const std::string job = s.value("job", "");
        if (job.empty() || !s.contains("task_labels")) continue;
        for (size_t t = 0; t < s["task_labels"].size(); ++t) {
            tasks.emplace_back(job + "_" + std::to_string(t), s["task_labels"][t].get<std::string>());
        }
    }
    return tasks;
}

// Why a task that appended no exit line ended, when Slurm says it ended; "" while it may still run or nobody knows.
std::string endedWithoutExitLine(const std::string& task, const std::map<std::string, farm::SlurmTaskState>& slurm,
                                 const std::set<std::string>& queued) {
    if (queued.count(task)) return "";
    const auto s = slurm.find(task);
    if (s == slurm.end() || !s->second.finished()) return "";
    if (s->second.state == "COMPLETED" && s->second.exitCode == 0) return "";
    return "task " + task + ": Slurm " + s->second.describe() + ", no exit line";
}

// The frames a task's label ("frames 4-7") covers.
std::vector<int> framesOfLabel(const std::string& label) {
    const std::string prefix = "frames ";
    if (label.rfind(prefix, 0) != 0) return {};
    try {
        return parseFrameRange(label.substr(prefix.size()));
    } catch (const InputError&) {
        return {};
    }
}

int renderStatus(const Submission& s) {
    const RenderState st = renderState(s);
    std::map<int, std::string> failed; // frame -> why
    std::set<std::string> exited;      // tasks whose exit line the records hold ("<job>_<task>")
    for (const farm::TaskOutcome& t : st.tasks) {
        if (t.exited) exited.insert(t.part.substr(0, t.part.rfind('.')));
        if (!t.exited || t.exitCode == 0) continue;
        for (int frame : framesOfLabel(t.label)) {
            if (!st.done.count(frame)) {
                failed[frame] = t.part + " on " + (t.host.empty() ? "?" : t.host) + ": exit " + std::to_string(t.exitCode);
            }
        }
    }
    // Tasks that Slurm ended before their script could append the exit line (scancel, a time limit, a node).
    for (const auto& [task, label] : submittedTasks(s.manifest)) {
        if (exited.count(task)) continue;
        const std::string why = endedWithoutExitLine(task, st.slurm, st.queued);
        if (why.empty()) continue;
        for (int frame : framesOfLabel(label)) {
            if (!st.done.count(frame) && !failed.count(frame)) failed[frame] = why;
        }
    }
    std::vector<int> missing, failedFrames;
    for (int frame : st.frames) {
        if (st.done.count(frame)) continue;
        (failed.count(frame) ? failedFrames : missing).push_back(frame);
    }
    std::printf("farm %s: render of %zu frame(s), %zu submission(s)\n", s.dir.c_str(), st.frames.size(),
                s.manifest["submissions"].size());
    std::printf("  done     %zu\n", st.done.size());
    std::printf("  failed   %zu%s\n", failedFrames.size(),
                failedFrames.empty() ? "" : (": frames " + farm::frameSelection(failedFrames)).c_str());
    std::set<std::string> reasons;
    for (int frame : failedFrames) reasons.insert(failed[frame]);
    for (const std::string& why : reasons) std::printf("           %s (log in %s)\n", why.c_str(), (s.dir / "logs").c_str());
    std::printf("  missing  %zu%s\n", missing.size(), missing.empty() ? "" : (": frames " + farm::frameSelection(missing)).c_str());
    if (!st.queued.empty()) std::printf("  queued or running: %zu array task(s)\n", st.queued.size());
    return st.done.size() == st.frames.size() ? kExitOk : kExitCheckFailed;
}

nlohmann::json taskJson(const farm::TaskOutcome& t) {
    nlohmann::json j = {{"records", t.part},
                        {"host", t.host},
                        {"gl_renderer", t.header.value("gl_renderer", "")},
                        {"frames_rendered", t.framesRendered},
                        {"startup_s", t.header.value("startup_s", 0.0)},
                        {"wall_s", t.exited ? nlohmann::json(t.wallSeconds) : nlohmann::json(nullptr)},
                        {"exit_code", t.exited ? nlohmann::json(t.exitCode) : nlohmann::json(nullptr)}};
    if (!t.label.empty()) j["label"] = t.label;
    return j;
}

int renderCollect(const Submission& s, const FarmOptions& f) {
    const RenderState st = renderState(s);
    std::vector<int> missing;
    for (int frame : st.frames) {
        if (!st.done.count(frame)) missing.push_back(frame);
    }
    if (!missing.empty() && !f.partial) {
        std::fprintf(stderr, "farm collect: %zu of %zu frame(s) not done (frames %s); nothing written: submit again "
                             "(only those are rendered) or give --partial\n",
                     missing.size(), st.frames.size(), farm::frameSelection(missing).c_str());
        return kExitCheckFailed;
    }
    // Run-level fields from a task whose records prove frames (same digest and commit).
    nlohmann::json out = nlohmann::json::object();
    for (const farm::TaskOutcome& t : st.tasks) {
        if (t.started && t.header.value("flags_digest", "") == s.manifest.value("flags_digest", "")) out = t.header;
    }
    out.erase("host");
    nlohmann::json frames = nlohmann::json::array();
    std::sort(missing.begin(), missing.end());
    std::vector<int> ordered = st.frames;
    std::sort(ordered.begin(), ordered.end());
    for (int frame : ordered) {
        if (const auto d = st.done.find(frame); d != st.done.end()) frames.push_back(d->second.stats);
    }
    out["frames"] = frames;
    nlohmann::json tasks = nlohmann::json::array();
    for (const farm::TaskOutcome& t : st.tasks) tasks.push_back(taskJson(t));
    out["tasks"] = tasks;
    if (!missing.empty()) out["missing_frames"] = missing;
    const fs::path file = f.output.empty() ? fs::path(s.manifest.value("collected", "")) : fs::path(f.output);
    writeJsonFile(file, out);
    std::printf("farm collect: %zu frame(s) from %zu task record(s) -> %s\n", frames.size(), st.tasks.size(), file.c_str());
    return kExitOk;
}

struct BenchState {
    std::vector<std::string> rows;
    std::vector<nlohmann::json> parts; // null when not done
    std::vector<std::optional<TaskExit>> exits;
    std::vector<std::string> endedBySlurm; // per row: why Slurm ended its task without an exit line, or ""
};

BenchState benchState(const Submission& s) {
    BenchState st;
    st.rows = s.manifest["rows"].get<std::vector<std::string>>();
    for (size_t i = 0; i < st.rows.size(); ++i) {
        const fs::path part = s.dir / "parts" / ("row_" + std::to_string(i) + ".json");
        st.parts.push_back(readJsonOrNull(part));
        st.exits.push_back(readRecordsFile(s.dir / "parts" / ("row_" + std::to_string(i) + ".exit.jsonl")).taskExit);
    }
    st.endedBySlurm.assign(st.rows.size(), "");
    const std::set<std::string> queued = queuedTasks(s.manifest);
    const std::map<std::string, farm::SlurmTaskState> slurm = slurmTaskStates(s.manifest);
    for (const auto& [task, label] : submittedTasks(s.manifest)) {
        // Bench task labels are "row <i>: <row>".
        if (label.rfind("row ", 0) != 0) continue;
        const size_t row = size_t(std::atoi(label.c_str() + 4));
        if (row >= st.rows.size() || st.parts[row].is_object() || st.exits[row]) continue;
        const std::string why = endedWithoutExitLine(task, slurm, queued);
        if (!why.empty()) st.endedBySlurm[row] = why;
    }
    return st;
}

int benchStatus(const Submission& s) {
    const BenchState st = benchState(s);
    size_t done = 0;
    std::vector<std::string> failed, missing;
    for (size_t i = 0; i < st.rows.size(); ++i) {
        if (st.parts[i].is_object()) {
            ++done;
        } else if (st.exits[i] && st.exits[i]->exitCode != 0) {
            failed.push_back(st.rows[i] + " (exit " + std::to_string(st.exits[i]->exitCode) + ")");
        } else if (!st.endedBySlurm[i].empty()) {
            failed.push_back(st.rows[i] + " (" + st.endedBySlurm[i] + ")");
        } else {
            missing.push_back(st.rows[i]);
        }
    }
    std::printf("farm %s: bench of %zu row(s), %zu submission(s)\n", s.dir.c_str(), st.rows.size(),
                s.manifest["submissions"].size());
    std::printf("  done     %zu\n  failed   %zu\n", done, failed.size());
    for (const std::string& r : failed) std::printf("           %s\n", r.c_str());
    std::printf("  missing  %zu\n", missing.size());
    for (const std::string& r : missing) std::printf("           %s\n", r.c_str());
    return done == st.rows.size() ? kExitOk : kExitCheckFailed;
}

int benchCollect(const Submission& s, const FarmOptions& f) {
    const BenchState st = benchState(s);
    nlohmann::json out = nlohmann::json::object();
    nlohmann::json rows = nlohmann::json::array();
    nlohmann::json tasks = nlohmann::json::array();
    size_t missing = 0;
    for (size_t i = 0; i < st.rows.size(); ++i) {
        const nlohmann::json& part = st.parts[i];
        if (!part.is_object()) {
            ++missing;
            continue;
        }
        if (out.empty()) {
            // The run-level fields of bench --json (scene, bvh, GL, machine, settings, ...) from the first row's task;
            // every row carries its own scene and path.
            out = part;
            out.erase("rows");
            out.erase("command_line"); // one per task, below
        }
        for (const nlohmann::json& row : part["rows"]) rows.push_back(row);
        nlohmann::json task = {{"row", st.rows[i]}, {"scene", part["scene"]}, {"gl_renderer", part["gl_renderer"]},
                               {"command_line", part.value("command_line", nlohmann::json::array())}};
        if (st.exits[i]) {
            task["host"] = st.exits[i]->fields.value("host", "");
            task["wall_s"] = st.exits[i]->fields.value("wall_s", 0.0);
        }
        tasks.push_back(task);
    }
    if (missing > 0 && !f.partial) {
        std::fprintf(stderr, "farm collect: %zu of %zu bench row(s) not done; nothing written: submit again or give "
                             "--partial\n",
                     missing, st.rows.size());
        return kExitCheckFailed;
    }
    out["rows"] = rows;
    out["tasks"] = tasks;
    const fs::path file = f.output.empty() ? fs::path(s.manifest.value("collected", "")) : fs::path(f.output);
    writeJsonFile(file, out);
    std::printf("farm collect: %zu row(s) -> %s\n", rows.size(), file.c_str());
    return kExitOk;
}

} // namespace

void addFarm(CLI::App& cli, FarmOptions& f) {
    CLI::App* farmCommand =
        cli.add_subcommand("farm", "Render farms: walkthroughs and comparison runs as Slurm job arrays (docs/farm.md)");
    farmCommand->require_subcommand(1);
    f.submitCommand = farmCommand->add_subcommand(
        "submit", "Render frames as a Slurm job array, one task per chunk; resubmitting renders only what is missing");
    addCommonOptions(*f.submitCommand, f.render.common, kShadedCommands | kHeadlessCommands);
    addRenderOwnOptions(*f.submitCommand, f.render);
    f.submitCommand->add_option("--chunk", f.chunk, "Frames per array task")->capture_default_str();
    addSubmitOptions(*f.submitCommand, f);

    f.benchCommand = farmCommand->add_subcommand(
        "bench", "Run bench rows (scene x path x ray type x method) as a Slurm job array; --scene and --camera-path "
                 "take comma-separated lists");
    addCommonOptions(*f.benchCommand, f.bench.common, kShadedCommands | kHeadlessCommands);
    addBenchOwnOptions(*f.benchCommand, f.bench);
    addSubmitOptions(*f.benchCommand, f);

    f.statusCommand = farmCommand->add_subcommand(
        "status", "Frames or rows done, failed (with the task's exit code and host) and missing; exit 4 unless all done");
    f.statusCommand->add_option("submission", f.target, "The submission's --stats-json or --json file, or its .farm directory")
        ->required();
    f.collectCommand = farmCommand->add_subcommand(
        "collect", "Merge the tasks' results into one stats JSON (render) or bench JSON, in frame or row order");
    f.collectCommand->add_option("submission", f.target, "The submission's --stats-json or --json file, or its .farm directory")
        ->required();
    f.collectCommand->add_option("-o,--output", f.output, "Write here instead of the submitted --stats-json / --json");
    f.collectCommand->add_flag("--partial", f.partial, "Write what is done even when frames or rows are missing");
}

bool farmSelected(const FarmOptions& f) {
    return (f.submitCommand && *f.submitCommand) || (f.benchCommand && *f.benchCommand) ||
           (f.statusCommand && *f.statusCommand) || (f.collectCommand && *f.collectCommand);
}

int runFarm(FarmOptions& f) {
    if (*f.submitCommand) return submitRender(f);
    if (*f.benchCommand) return submitBench(f);
    const Submission s = openSubmission(f.target);
    const bool render = s.manifest.value("kind", "") == "render";
    if (*f.statusCommand) return render ? renderStatus(s) : benchStatus(s);
    return render ? renderCollect(s, f) : benchCollect(s, f);
}

} // namespace chcrt::app
