#include "app/farm.h"

#include "app/render_records.h"
#include "renderer/core/frame_range.h"

#include <algorithm>
#include <map>
#include <sstream>

namespace chcrt::app::farm {
namespace fs = std::filesystem;

const char* toString(Kind kind) { return kind == Kind::Render ? "render" : "bench"; }

fs::path farmDirectoryOf(const fs::path& collectedOutput) {
    fs::path dir = collectedOutput;
    dir.replace_extension(".farm");
    return dir;
}

std::vector<std::vector<int>> chunkFrames(const std::vector<int>& frames, int chunk) {
    std::vector<std::vector<int>> chunks;
    for (size_t i = 0; i < frames.size(); i += size_t(chunk)) {
        chunks.emplace_back(frames.begin() + long(i), frames.begin() + long(std::min(frames.size(), i + size_t(chunk))));
    }
    return chunks;
}

std::string frameSelection(const std::vector<int>& frames) {
    std::string text;
    for (size_t i = 0; i < frames.size();) {
        size_t j = i;
        while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
        if (!text.empty()) text += ",";
        text += std::to_string(frames[i]);
        if (j > i) {
            text += '-';
            text += std::to_string(frames[j]);
        }
        i = j + 1;
    }
    return text;
}

std::vector<std::string> wordsWithout(const std::vector<std::string>& words,
                                      const std::vector<std::string>& flagsWithValue,
                                      const std::vector<std::string>& switches) {
    auto named = [](const std::vector<std::string>& list, const std::string& w) {
        return std::find(list.begin(), list.end(), w) != list.end();
    };
    std::vector<std::string> kept;
    for (size_t i = 0; i < words.size(); ++i) {
        const std::string& w = words[i];
        const std::string name = w.substr(0, w.find('='));
        if (named(switches, w)) continue;
        if (named(flagsWithValue, name)) {
            if (name == w) ++i; // "--chunk 10": the value is the next word
            continue;
        }
        kept.push_back(w);
    }
    return kept;
}

std::string shellQuote(const std::string& word) {
    std::string quoted = "'";
    for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

namespace {

// A word for the script, with %j and %t (job id, array index) expanded by bash at run time.
std::string scriptWord(const std::string& word) {
    if (word.find("%j") == std::string::npos && word.find("%t") == std::string::npos) return shellQuote(word);
    std::string quoted = "\"";
    for (size_t i = 0; i < word.size(); ++i) {
        if (word.compare(i, 2, "%j") == 0) {
            quoted += "${job}";
            ++i;
        } else if (word.compare(i, 2, "%t") == 0) {
            quoted += "${task}";
            ++i;
        } else {
            if (word[i] == '"' || word[i] == '$' || word[i] == '`' || word[i] == '\\') quoted += '\\';
            quoted += word[i];
        }
    }
    return quoted + "\"";
}

void addDirective(std::ostringstream& s, const std::string& name, const std::string& value) {
    if (!value.empty()) s << "#SBATCH --" << name << "=" << value << "\n";
}

} // namespace

std::string sbatchScript(const Plan& plan) {
    std::ostringstream s;
    const SlurmOptions& o = plan.slurm;
    s << "#!/bin/bash\n"
      << "# chcrt farm: " << toString(plan.kind) << ", " << plan.tasks.size()
      << " array task(s); written by `chcrt farm` (docs/farm.md)\n";
    addDirective(s, "job-name", o.jobName.empty() ? std::string("chcrt-") + toString(plan.kind) : o.jobName);
    addDirective(s, "array", "0-" + std::to_string(plan.tasks.size() - 1));
    addDirective(s, "output", (plan.directory / "logs" / "%A_%a.out").string());
    addDirective(s, "chdir", plan.workingDirectory.string());
    addDirective(s, "partition", o.partition);
    addDirective(s, "time", o.time);
    addDirective(s, "mem", o.mem);
    addDirective(s, "account", o.account);
    addDirective(s, "gres", o.gres);
    if (o.cpusPerTask > 0) addDirective(s, "cpus-per-task", std::to_string(o.cpusPerTask));
    if (o.gpusPerTask > 0) addDirective(s, "gpus-per-task", std::to_string(o.gpusPerTask));
    for (const std::string& extra : o.extra) s << "#SBATCH " << extra << "\n";
    s << "set -u\n"
      << "job=${SLURM_ARRAY_JOB_ID:-local}\n"
      << "task=${SLURM_ARRAY_TASK_ID:?run this script with sbatch}\n"
      << "parts=" << shellQuote((plan.directory / "parts").string()) << "\n"
      << "# llvmpipe renders with as many threads as the task has CPUs (a GPU ignores this).\n"
      << "cpus=${SLURM_CPUS_PER_TASK:-${SLURM_CPUS_ON_NODE:-}}\n"
      << "if [[ -n $cpus && -z ${LP_NUM_THREADS:-} ]]; then export LP_NUM_THREADS=$cpus; fi\n";
    s << "case $task in\n";
    for (size_t t = 0; t < plan.tasks.size(); ++t) {
        const Task& task = plan.tasks[t];
        s << "  " << t << ")\n    label=" << shellQuote(task.label) << "\n    words=(";
        for (size_t w = 0; w < task.words.size(); ++w) s << (w ? " " : "") << scriptWord(task.words[w]);
        s << ")\n    exit_file=\"${parts}\"/" << scriptWord(task.exitFile) << "\n    ;;\n";
    }
    s << "  *) echo \"chcrt farm: no array task $task\" >&2; exit 2 ;;\nesac\n";
    s << "gl_device=()\n";
    if (o.usesGpus()) {
        // The GPU Slurm bound to this task (physical index; CUDA_VISIBLE_DEVICES when Slurm does not say) is the
        // EGL device it renders on: no fall-back to another GPU or to a software rasteriser.
        s << "gpu=${SLURM_JOB_GPUS:-${SLURM_STEP_GPUS:-${CUDA_VISIBLE_DEVICES:-}}}\n"
          << "if [[ -n $gpu ]]; then gl_device=(--gl-device \"${gpu%%,*}\"); fi\n";
    }
    s << "start=$(date +%s.%N)\n"
      << shellQuote(plan.binary.string());
    for (const std::string& w : plan.command) s << " " << shellQuote(w);
    s << " \"${words[@]}\" \"${gl_device[@]}\" -q\n"
      << "rc=$?\n"
      << "wall=$(awk -v a=\"$start\" -v b=\"$(date +%s.%N)\" 'BEGIN { printf \"%.3f\", b - a }')\n"
      << "printf '{\"task_exit\": %d, \"label\": \"%s\", \"host\": \"%s\", \"job\": \"%s\", \"task\": %d, "
         "\"wall_s\": %s}\\n' \"$rc\" \"$label\" \"$(hostname)\" \"$job\" \"$task\" \"$wall\" >> \"$exit_file\"\n"
      << "exit $rc\n";
    return s.str();
}

namespace {

// The parts' records files, oldest first (a newer record of a frame replaces an older one).
std::vector<fs::path> recordsFiles(const fs::path& partsDirectory) {
    std::vector<fs::path> files;
    std::error_code error;
    if (!fs::is_directory(partsDirectory, error)) return files;
    for (const fs::directory_entry& e : fs::directory_iterator(partsDirectory)) {
        if (e.path().extension() == ".jsonl" && e.path().filename().string().rfind("row_", 0) != 0) {
            files.push_back(e.path());
        }
    }
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
        std::error_code ea, eb;
        const auto ta = fs::last_write_time(a, ea), tb = fs::last_write_time(b, eb);
        return ta != tb ? ta < tb : a < b;
    });
    return files;
}

} // namespace

std::map<int, ProvenFrame> provenFrames(const fs::path& partsDirectory, const std::vector<int>& frames,
                                        const std::string& outputPattern, const std::string& digest,
                                        const std::string& commit) {
    std::map<int, ProvenFrame> proven;
    const std::vector<int> sorted = [&] {
        std::vector<int> f = frames;
        std::sort(f.begin(), f.end());
        return f;
    }();
    for (const fs::path& file : recordsFiles(partsDirectory)) {
        for (const FrameRecord& r : readRecordsFile(file).frames) {
            if (!std::binary_search(sorted.begin(), sorted.end(), r.frame)) continue;
            // The name a render of all the submission's frames gives the frame (the farm requires '#').
            const std::string expected = formatFramePath(outputPattern, r.frame, int(frames.size()));
            if (recordProvesFrame(r, expected, digest, commit)) proven[r.frame] = {r.stats, file.filename().string()};
        }
    }
    return proven;
}

std::vector<TaskOutcome> renderTaskOutcomes(const fs::path& partsDirectory) {
    std::vector<TaskOutcome> outcomes;
    for (const fs::path& file : recordsFiles(partsDirectory)) {
        const RecordsFile records = readRecordsFile(file);
        TaskOutcome t;
        t.part = file.filename().string();
        t.started = !records.headers.empty();
        if (t.started) {
            t.header = records.headers.back();
            t.host = t.header.value("host", "");
        }
        if (records.taskExit) {
            t.exited = true;
            t.exitCode = records.taskExit->exitCode;
            const nlohmann::json& f = records.taskExit->fields;
            if (f.contains("host") && f["host"].is_string()) t.host = f["host"].get<std::string>();
            if (f.contains("wall_s") && f["wall_s"].is_number()) t.wallSeconds = f["wall_s"].get<double>();
            if (f.contains("label") && f["label"].is_string()) t.label = f["label"].get<std::string>();
        }
        for (const FrameRecord& r : records.frames) t.framesRendered.push_back(r.frame);
        outcomes.push_back(std::move(t));
    }
    return outcomes;
}

bool SlurmTaskState::finished() const {
    for (const char* active : {"PENDING", "RUNNING", "SUSPENDED", "COMPLETING", "CONFIGURING", "REQUEUED",
                               "REQUEUE_HOLD", "REQUEUE_FED", "RESIZING", "SIGNALING", "STAGE_OUT", "STOPPED",
                               "RESV_DEL_HOLD"}) {
        if (state == active) return false;
    }
    return !state.empty();
}

std::string SlurmTaskState::describe() const {
    std::string text = state + " (exit " + std::to_string(exitCode);
    if (signal != 0) text += ", signal " + std::to_string(signal);
    text += ")";
    // sacct writes "None assigned" for a task that never ran, scontrol "(null)".
    if (!node.empty() && node.rfind("None", 0) != 0 && node != "(null)") text += " on " + node;
    return text;
}

namespace {

// "3:0" -> exit 3, signal 0.
void parseExitCode(const std::string& text, SlurmTaskState& s) {
    const size_t colon = text.find(':');
    try {
        s.exitCode = std::stoi(text.substr(0, colon));
        if (colon != std::string::npos) s.signal = std::stoi(text.substr(colon + 1));
    } catch (const std::exception&) {
        s.exitCode = 0;
        s.signal = 0;
    }
}

// The array index of "7_2" for job "7"; -1 for anything else ("7", "7_[3-5]", "8_1", "7_2.batch").
int arrayIndexOf(const std::string& jobId, const std::string& job) {
    const std::string prefix = job + "_";
    if (jobId.rfind(prefix, 0) != 0) return -1;
    const std::string index = jobId.substr(prefix.size());
    if (index.empty() || index.find_first_not_of("0123456789") != std::string::npos) return -1;
    return std::stoi(index);
}

std::vector<std::string> splitOn(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::string part;
    std::istringstream in(text);
    while (std::getline(in, part, separator)) parts.push_back(part);
    return parts;
}

} // namespace

std::map<int, SlurmTaskState> parseSacctTasks(const std::string& output, const std::string& job) {
    std::map<int, SlurmTaskState> tasks;
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
        const std::vector<std::string> f = splitOn(line, '|');
        if (f.size() < 4) continue;
        const int index = arrayIndexOf(f[0], job);
        if (index < 0) continue;
        SlurmTaskState s;
        s.state = f[1].substr(0, f[1].find(' '));
        parseExitCode(f[2], s);
        s.node = f[3];
        tasks[index] = s;
    }
    return tasks;
}

std::map<int, SlurmTaskState> parseScontrolTasks(const std::string& output, const std::string& job) {
    std::map<int, SlurmTaskState> tasks;
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
        std::map<std::string, std::string> fields;
        std::istringstream words(line);
        for (std::string word; words >> word;) {
            const size_t equals = word.find('=');
            if (equals != std::string::npos && !fields.count(word.substr(0, equals))) {
                fields[word.substr(0, equals)] = word.substr(equals + 1);
            }
        }
        if (fields["ArrayJobId"] != job) continue;
        const std::string index = fields["ArrayTaskId"];
        if (index.empty() || index.find_first_not_of("0123456789") != std::string::npos) continue; // "3-5": pending
        SlurmTaskState s;
        s.state = fields["JobState"];
        parseExitCode(fields["ExitCode"], s);
        s.node = fields["NodeList"];
        tasks[std::stoi(index)] = s;
    }
    return tasks;
}

} // namespace chcrt::app::farm
