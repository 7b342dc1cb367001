#include "app/render_records.h"

#include "linespace/cache_file.h"
#include "renderer/core/error.h"

#include <array>
#include <cinttypes>
#include <fstream>
#include <unistd.h>

namespace chcrt::app {
namespace {

std::string hexDigest(uint64_t hash) {
    char text[32];
    std::snprintf(text, sizeof text, "fnv1a64:%016" PRIx64, hash);
    return text;
}

// Flags that take a value and do not decide pixels (pixelDecidingWords); -q/--quiet and --resume take none.
bool isBookkeepingFlagWithValue(const std::string& flag) {
    return flag == "--frames" || flag == "-o" || flag == "--output" || flag == "--stats-json" ||
           flag == "--records" || flag == "--gl-device" || flag == "--shader-stage" || flag == "--resource-log" ||
           flag == "--resource-every";
}
bool isBookkeepingSwitch(const std::string& flag) { return flag == "-q" || flag == "--quiet" || flag == "--resume"; }

} // namespace

std::string fileChecksum(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return {};
    uint64_t hash = 0xcbf29ce484222325ull;
    std::array<char, 1 << 16> buffer;
    while (in) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        hash = ls::fnv1a64(buffer.data(), size_t(in.gcount()), hash);
    }
    return in.bad() ? std::string() : hexDigest(hash);
}

std::vector<std::string> pixelDecidingWords(const std::vector<std::string>& renderWords) {
    std::vector<std::string> kept;
    for (size_t i = 0; i < renderWords.size(); ++i) {
        const std::string& w = renderWords[i];
        const std::string name = w.substr(0, w.find('='));
        if (isBookkeepingSwitch(w)) continue;
        if (isBookkeepingFlagWithValue(name)) {
            if (name == w) ++i; // "--frames 0-9": the value is the next word
            continue;
        }
        kept.push_back(w);
    }
    return kept;
}

std::string flagsDigest(const std::vector<std::string>& renderWords) {
    uint64_t hash = 0xcbf29ce484222325ull;
    for (const std::string& w : pixelDecidingWords(renderWords)) hash = ls::fnv1a64(w.c_str(), w.size() + 1, hash);
    return hexDigest(hash);
}

RecordsFile readRecordsFile(const std::filesystem::path& file) {
    RecordsFile records;
    std::error_code error;
    if (!std::filesystem::exists(file, error)) return records;
    std::ifstream in(file);
    if (!in) throw InputError(file.string() + ": cannot read the records file");
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        const nlohmann::json j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
        if (!j.is_object()) {
            ++records.tornLines;
            continue;
        }
        if (j.contains("header")) {
            records.headers.push_back(j["header"]);
        } else if (j.contains("end")) {
            records.ends.push_back(j["end"]);
        } else if (j.contains("task_exit") && j["task_exit"].is_number_integer()) {
            records.taskExit = TaskExit{j["task_exit"].get<int>(), j};
        } else if (j.contains("frame") && j["frame"].is_number_integer()) {
            FrameRecord r;
            r.frame = j["frame"].get<int>();
            r.output = j.value("output", "");
            r.imageChecksum = j.value("image_checksum", "");
            r.flagsDigest = j.value("flags_digest", "");
            r.commit = j.value("commit", "");
            r.stats = j.value("stats", nlohmann::json::object());
            records.frames.push_back(std::move(r));
        } else {
            ++records.tornLines;
        }
    }
    return records;
}

bool recordProvesFrame(const FrameRecord& record, const std::string& expectedOutput, const std::string& digest,
                       const std::string& commit) {
    return record.flagsDigest == digest && record.commit == commit && record.output == expectedOutput &&
           !record.imageChecksum.empty() && fileChecksum(record.output) == record.imageChecksum;
}

RecordsWriter::RecordsWriter(const std::filesystem::path& file) : file_(file) {
    out_ = std::fopen(file.c_str(), "a+");
    if (!out_) throw InputError(file.string() + ": cannot open the records file for appending (does the directory exist?)");
    // A run killed mid-line leaves a torn last line without its newline: end it, so that the first line appended
    // now is not glued to it (and skipped with it when read).
    if (std::fseek(out_, -1, SEEK_END) == 0 && std::fgetc(out_) != '\n') endTornLine_ = true;
}

RecordsWriter::~RecordsWriter() {
    if (out_) std::fclose(out_);
}

void RecordsWriter::append(const nlohmann::json& line) {
    // A line that does not reach the disk would make a finished frame look missing (rendered again), never the
    // reverse: the image is renamed into place before its record is written.
    std::string text = endTornLine_ ? std::string(1, '\n') : std::string();
    text += line.dump();
    text += '\n';
    endTornLine_ = false;
    if (std::fwrite(text.data(), 1, text.size(), out_) != text.size() || std::fflush(out_) != 0 ||
        ::fsync(::fileno(out_)) != 0) {
        throw InputError(file_.string() + ": writing a record failed");
    }
}

} // namespace chcrt::app
