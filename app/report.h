#pragma once
// Output helpers of the commands: JSON/CSV/markdown files written atomically (temp file + rename, so a failure
// never leaves a partial file), statistics as JSON, and fixed-width tables for the terminal.
#include "culling/chcrt_tracer.h"
#include "renderer/bvh/bvh.h"
#include "renderer/gl/context.h"
#include "renderer/render/renderer.h"
#include "renderer/scene/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace chcrt::app {

void writeTextFileAtomically(const std::filesystem::path& file, const std::string& text);
void writeJsonFile(const std::filesystem::path& file, const nlohmann::json& json);

nlohmann::json toJson(const FrameStats& stats, uint64_t pixels);
nlohmann::json toJson(const Scene& scene);
nlohmann::json toJson(const BvhStats& stats);

// A table: header row + rows of cells; printed with aligned columns, or as GitHub markdown / CSV.
struct Table {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::string toText() const;
    std::string toMarkdown() const;
    std::string toCsv() const;
};

std::string formatFixed(double value, int decimals);
std::string formatCount(uint64_t value); // 1234567 -> "1.23M"

// What a measurement ran on, taken before and after it (bench JSON "machine", stated by `chcrt report`): whether
// the machine was loaded matters as much as the CPU, since the GL rasteriser may share it.
struct MachineSnapshot {
    std::string utc;                 // ISO 8601, seconds
    std::vector<double> loadAverage; // 1, 5, 15 minutes (/proc/loadavg; empty where unreadable)
};
MachineSnapshot takeMachineSnapshot();
// The CPU's model name (/proc/cpuinfo; "unknown" where it has none): what a timing on a software renderer ran on.
std::string cpuModel();
// {cpu, cores, commit, started_utc, finished_utc, load_before, load_after}.
nlohmann::json machineJson(const MachineSnapshot& before, const MachineSnapshot& after);
// The GL implementation a measurement ran on, the fields every JSON of bench, render and verify carries at its top
// level: {gl_vendor, gl_renderer, gl_version, software_renderer (a CPU rasteriser: not GPU timings)}.
nlohmann::json glJson(const GlInfo& info);

// The process's own command line, word by word (/proc/self/cmdline), so outputs name the exact command.
std::vector<std::string> processCommandLine();

// CHC+RT counters (culling/chcrt_tracer.h) summed over `frames` frames: sums, per-frame means and Mrays/s over
// the tracer's own wall time ("chcrt" object of bench rows and render frames).
nlohmann::json chcrtStatsJson(const ChcrtStats& stats, double frames);

} // namespace chcrt::app
