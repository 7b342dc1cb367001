#pragma once
// Per-frame records of a render (`chcrt render --records FILE`, docs/farm.md): what makes a frame count as done
// for a resumed render and for `chcrt farm`. A records file is JSON Lines, appended and flushed line by line:
//   {"header": {...}}   once per run, after the scene loaded: the run-level fields of --stats-json
//   {"frame": k, "output": "...", "image_checksum": "...", "flags_digest": "...", "commit": "...", "stats": {...}}
//                       after frame k's image was renamed into place (so a record never names a partial image)
//   {"end": {...}}      when the run finished its frames
//   {"task_exit": rc, ...}  appended by a farm task's script after chcrt exited (any exit, crashes included)
// A process killed midway leaves at most one torn last line, which reading skips.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace chcrt::app {

// "fnv1a64:<16 hex digits>" of a file's bytes; empty when the file cannot be read.
std::string fileChecksum(const std::filesystem::path& file);

// The words of a `chcrt render` command line (after "render") that decide its images: all of them except the
// frame selection and where statistics, records and progress go (--frames, -o/--output, --stats-json,
// --records, --resume, --resource-log, --resource-every, -q/--quiet), the GL device (--gl-device: the same pixels on
// any device of a node) and the shader stage (--shader-stage: the same pixels in either stage,
// tests/render/trace_stage_test.cpp).
std::vector<std::string> pixelDecidingWords(const std::vector<std::string>& renderWords);
// "fnv1a64:<hex>" of pixelDecidingWords(renderWords), NUL-separated.
std::string flagsDigest(const std::vector<std::string>& renderWords);

struct FrameRecord {
    int frame = 0;
    std::string output, imageChecksum, flagsDigest, commit;
    nlohmann::json stats; // the frame's entry of --stats-json's "frames"
};

struct TaskExit {
    int exitCode = 0;
    nlohmann::json fields; // frames, host, job, task, wall_s as the task script wrote them
};

struct RecordsFile {
    std::vector<nlohmann::json> headers;
    std::vector<FrameRecord> frames; // in file order (a frame rendered twice appears twice)
    std::vector<nlohmann::json> ends;
    std::optional<TaskExit> taskExit;
    size_t tornLines = 0; // lines that did not parse (a write cut by a kill)
};
// Reads a records file; a missing file reads as empty. Throws InputError only when the file exists and cannot
// be opened.
RecordsFile readRecordsFile(const std::filesystem::path& file);

// True when `record` proves its frame done for a run with these flags and this build: same digest and commit,
// the image it names is `expectedOutput` and still holds the bytes it was written with.
bool recordProvesFrame(const FrameRecord& record, const std::string& expectedOutput, const std::string& digest,
                       const std::string& commit);

// Appends lines to a records file, each flushed and synced before the call returns.
class RecordsWriter {
public:
    explicit RecordsWriter(const std::filesystem::path& file); // throws InputError when it cannot be opened
    ~RecordsWriter();
    RecordsWriter(const RecordsWriter&) = delete;
    RecordsWriter& operator=(const RecordsWriter&) = delete;
    void append(const nlohmann::json& line);

private:
    std::filesystem::path file_;
    std::FILE* out_ = nullptr;
    bool endTornLine_ = false; // the file ended in a torn line
};

} // namespace chcrt::app
