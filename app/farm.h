#pragma once
// Render farms (`chcrt farm`, docs/farm.md): a walkthrough or a comparison run as one Slurm job array. A
// submission is kept in a farm directory next to its collected output (out/stats.json -> out/stats.farm/):
//   manifest.json   what was submitted: kind, the task command lines, frames or rows, digest, commit, jobs
//   job-<n>.sbatch  the script of the n-th submission (one array task per chunk of frames or bench row)
//   parts/          what the tasks wrote: render records (<job>_<task>.jsonl, app/render_records.h) and
//                   per-task statistics; bench rows (row_<i>.json) and their exit lines (row_<i>.exit.jsonl)
//   logs/           Slurm's stdout/stderr per task
// Everything here is plain logic on files and words (tested without Slurm); app/command_farm.cpp runs sbatch.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace chcrt::app::farm {

// sbatch options passed through (`--partition`, ...); empty or 0: not given.
struct SlurmOptions {
    std::string jobName, partition, time, mem, account, gres;
    int cpusPerTask = 0;
    int gpusPerTask = 0;
    std::vector<std::string> extra; // --sbatch-arg, each one sbatch argument ("--qos=high")
    bool usesGpus() const { return gpusPerTask > 0 || !gres.empty(); }
};

enum class Kind { Render, Bench };
const char* toString(Kind kind);

// One array task: the words appended to the shared command line, what it covers, and where its results go
// (relative to the farm directory; "%j" in them becomes the job id, "%t" the array index, in the script).
struct Task {
    std::vector<std::string> words;
    std::string label;       // "frames 0-9", "city near shadow chcrt"
    std::vector<int> frames; // render: the chunk's frames
    std::string exitFile;    // in parts/: where the script appends the task's exit line ("%j_%t.jsonl", "row_3.exit.jsonl")
};

struct Plan {
    Kind kind = Kind::Render;
    std::filesystem::path directory;        // the farm directory (absolute)
    std::filesystem::path binary;           // chcrt, absolute
    std::filesystem::path workingDirectory; // where the tasks run (the submitting directory)
    std::vector<std::string> command;       // subcommand and flags shared by every task ("render", "--scene", ...)
    std::vector<Task> tasks;
    SlurmOptions slurm;
};

// The farm directory of a collected output: "out/stats.json" -> "out/stats.farm".
std::filesystem::path farmDirectoryOf(const std::filesystem::path& collectedOutput);

// Consecutive chunks of at most `chunk` frames, in the given order.
std::vector<std::vector<int>> chunkFrames(const std::vector<int>& frames, int chunk);
// A --frames value that selects exactly `frames` (ascending runs become ranges): {0,1,2,5,7,8} -> "0-2,5,7-8".
std::string frameSelection(const std::vector<int>& frames);

// `words` without the flags named in `flagsWithValue` (with their values, "--x v" or "--x=v") and `switches`.
std::vector<std::string> wordsWithout(const std::vector<std::string>& words,
                                      const std::vector<std::string>& flagsWithValue,
                                      const std::vector<std::string>& switches);

// A word quoted for bash: 'it'\''s'.
std::string shellQuote(const std::string& word);

// The sbatch script of a plan: #SBATCH lines, the tasks' words per array index, the GPU binding, the run and
// the exit line each task appends to its Task::exitFile (render: its records; bench: row_<i>.exit.jsonl).
std::string sbatchScript(const Plan& plan);

// The frames of a render submission that records in `partsDirectory` prove done for this digest and commit,
// with the record of each (the newest one when a frame was rendered more than once).
struct ProvenFrame {
    nlohmann::json stats;
    std::string part; // the records file
};
std::map<int, ProvenFrame> provenFrames(const std::filesystem::path& partsDirectory, const std::vector<int>& frames,
                                        const std::string& outputPattern, const std::string& digest,
                                        const std::string& commit);

// What the records say of each task of a submission (render) or row (bench).
struct TaskOutcome {
    std::string part;          // records or row file name
    std::string label;         // what the task covered ("frames 4-7"), from its exit line
    bool started = false;      // a header line (render) or the row file (bench) exists
    bool exited = false;       // the script appended its exit line
    int exitCode = 0;
    std::string host;
    double wallSeconds = 0.0;
    std::vector<int> framesRendered;
    nlohmann::json header;     // render: the records' header (run-level statistics, GL renderer, start-up)
};
std::vector<TaskOutcome> renderTaskOutcomes(const std::filesystem::path& partsDirectory);

// What Slurm says of one array task of a job: its state (COMPLETED, FAILED, CANCELLED, TIMEOUT, NODE_FAIL,
// OUT_OF_MEMORY, PENDING, RUNNING, ...), exit code and signal, and node. A task killed with its script (scancel,
// a time limit, a failed node) never appends its exit line; this is what `farm status` says of it instead.
struct SlurmTaskState {
    std::string state; // first word of the state ("CANCELLED by 0" -> "CANCELLED")
    int exitCode = 0;
    int signal = 0;
    std::string node;
    bool finished() const; // a state a task does not leave (not PENDING, RUNNING, SUSPENDED, ...)
    std::string describe() const; // "CANCELLED (exit 0, signal 15) on vm"
};
// The array tasks of `sacct -X -n -P -j JOB --format=JobID,State,ExitCode,NodeList` output ("7_2|CANCELLED by
// 0|0:15|vm"); lines of other jobs and pending ranges ("7_[3-5]") are skipped.
std::map<int, SlurmTaskState> parseSacctTasks(const std::string& output, const std::string& job);
// The same from `scontrol show job -o JOB` output (one line per task: "... ArrayJobId=7 ArrayTaskId=2
// JobState=CANCELLED ... ExitCode=0:15 ... NodeList=vm ..."), what the controller remembers of a finished job for
// MinJobAge seconds when the cluster keeps no accounting.
std::map<int, SlurmTaskState> parseScontrolTasks(const std::string& output, const std::string& job);

} // namespace chcrt::app::farm
