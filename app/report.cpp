#include "app/report.h"

#include "app/build_info.h"
#include "renderer/core/error.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace chcrt::app {

void writeTextFileAtomically(const std::filesystem::path& file, const std::string& text) {
    // The process id keeps two processes writing the same file from sharing a temporary one.
    const std::filesystem::path temp = file.string() + ".tmp" + std::to_string(::getpid());
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError(file.string() + ": cannot write (does the directory exist?)");
        out << text;
        out.flush();
        if (!out) {
            out.close();
            std::filesystem::remove(temp);
            throw InputError(file.string() + ": write failed");
        }
    }
    std::error_code error;
    std::filesystem::rename(temp, file, error);
    if (error) {
        std::filesystem::remove(temp);
        throw InputError(file.string() + ": " + error.message());
    }
}

void writeJsonFile(const std::filesystem::path& file, const nlohmann::json& json) {
    writeTextFileAtomically(file, json.dump(2) + "\n");
}

nlohmann::json toJson(const FrameStats& s, uint64_t pixels) {
    nlohmann::json trace = nlohmann::json::object();
    for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao, RayType::Diffuse}) {
        const TraceStats& t = s.trace[size_t(type)];
        if (t.passes == 0) continue;
        trace[toString(type)] = {{"passes", t.passes}, {"ms", t.milliseconds}};
    }
    return {{"ms_total", s.totalMs},       {"ms_gbuffer", s.gbufferMs}, {"ms_raygen", s.raygenMs},
            {"ms_trace", s.traceMs()},     {"ms_shade", s.shadeMs},     {"trace", trace},
            {"rays_generated", s.raysGenerated}, {"capped_rays", s.cappedRays},
            {"gbuffer_triangles", s.gbufferTriangles},
            {"mrays_per_s_generated", s.traceMs() > 0 ? double(s.raysGenerated) / (s.traceMs() * 1000.0) : 0.0},
            {"pixels", pixels}};
}

nlohmann::json toJson(const Scene& scene) {
    const Aabb b = scene.bounds();
    return {{"name", scene.name},
            {"triangles", scene.triangleCount()},
            {"unique_triangles", scene.stats.uniqueTriangles},
            {"instanced_triangles", scene.stats.instancedTriangles},
            {"meshes", scene.stats.meshCount},
            {"instances", scene.stats.instanceCount},
            {"vertices", scene.positions.size()},
            {"materials", scene.materials.size()},
            {"textures", scene.textures.size()},
            {"degenerate_triangles_dropped", scene.stats.degenerateTrianglesDropped},
            {"bounds_min", {b.lower.x, b.lower.y, b.lower.z}},
            {"bounds_max", {b.upper.x, b.upper.y, b.upper.z}}};
}

nlohmann::json toJson(const BvhStats& s) {
    return {{"build_seconds", s.buildSeconds}, {"sah_cost", s.sahCost},     {"nodes", s.nodeCount},
            {"leaves", s.leafCount},           {"max_depth", s.maxDepth},   {"avg_leaf_triangles", s.averageLeafTriangles},
            {"bytes", s.bytes}};
}

std::string Table::toText() const {
    std::vector<size_t> widths(header.size(), 0);
    for (size_t c = 0; c < header.size(); ++c) widths[c] = header[c].size();
    for (const auto& row : rows)
        for (size_t c = 0; c < row.size() && c < widths.size(); ++c) widths[c] = std::max(widths[c], row[c].size());
    std::ostringstream out;
    auto printRow = [&](const std::vector<std::string>& row) {
        for (size_t c = 0; c < row.size(); ++c) {
            out << (c ? "  " : "") << std::setw(int(widths[c])) << (c < 4 ? std::left : std::right) << row[c];
        }
        out << "\n";
    };
    printRow(header);
    size_t total = 0;
    for (size_t w : widths) total += w + 2;
    out << std::string(total > 2 ? total - 2 : 0, '-') << "\n";
    for (const auto& row : rows) printRow(row);
    return out.str();
}

std::string Table::toMarkdown() const {
    std::ostringstream out;
    auto printRow = [&](const std::vector<std::string>& row) {
        out << "|";
        for (const std::string& cell : row) out << " " << cell << " |";
        out << "\n";
    };
    printRow(header);
    out << "|";
    for (size_t c = 0; c < header.size(); ++c) out << (c < 4 ? " --- |" : " ---: |");
    out << "\n";
    for (const auto& row : rows) printRow(row);
    return out.str();
}

std::string Table::toCsv() const {
    std::ostringstream out;
    auto printRow = [&](const std::vector<std::string>& row) {
        for (size_t c = 0; c < row.size(); ++c) {
            const bool quote = row[c].find_first_of(",\"") != std::string::npos;
            std::string cell = row[c];
            if (quote) {
                std::string escaped;
                for (char ch : cell) escaped += ch == '"' ? std::string("\"\"") : std::string(1, ch);
                cell = "\"" + escaped + "\"";
            }
            out << (c ? "," : "") << cell;
        }
        out << "\n";
    };
    printRow(header);
    for (const auto& row : rows) printRow(row);
    return out.str();
}

std::string formatFixed(double value, int decimals) {
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
    return buffer;
}

std::string formatCount(uint64_t value) {
    if (value >= 1'000'000) return formatFixed(double(value) / 1e6, 2) + "M";
    if (value >= 10'000) return formatFixed(double(value) / 1e3, 1) + "k";
    return std::to_string(value);
}

MachineSnapshot takeMachineSnapshot() {
    MachineSnapshot s;
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm utc{};
    gmtime_r(&now, &utc);
    char buffer[32];
    std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%SZ", &utc);
    s.utc = buffer;
    std::ifstream load("/proc/loadavg");
    double value = 0.0;
    for (int i = 0; i < 3 && load >> value; ++i) s.loadAverage.push_back(value);
    return s;
}

std::string cpuModel() {
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    while (std::getline(cpuinfo, line)) {
        if (line.rfind("model name", 0) != 0) continue;
        const size_t colon = line.find(':');
        if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
    return "unknown";
}

nlohmann::json machineJson(const MachineSnapshot& before, const MachineSnapshot& after) {
    return {{"cpu", cpuModel()},
            {"cores", std::thread::hardware_concurrency()},
            {"commit", buildCommit()},
            {"started_utc", before.utc},
            {"finished_utc", after.utc},
            {"load_before", before.loadAverage},
            {"load_after", after.loadAverage}};
}

nlohmann::json glJson(const GlInfo& info) {
    return {{"gl_vendor", info.vendor},
            {"gl_renderer", info.renderer},
            {"gl_version", info.version},
            {"software_renderer", info.softwareRenderer}};
}

std::vector<std::string> processCommandLine() {
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::vector<std::string> words;
    std::string word;
    while (std::getline(in, word, '\0')) words.push_back(word);
    return words;
}

nlohmann::json chcrtStatsJson(const ChcrtStats& s, double frames) {
    const double f = frames > 0 ? frames : 1.0;
    nlohmann::json sums = {{"traces", s.traces},
                           {"fallback_traces", s.fallbackTraces},
                           {"culled_share", s.culledShare()},
                           {"mean_height", s.meanHeight()},
                           {"queries", s.queries},
                           {"queries_single", s.queriesSingle},
                           {"queries_multi", s.queriesMulti},
                           {"queries_multi_failed", s.queriesMultiFailed},
                           {"queries_invisible", s.queriesInvisible},
                           {"queries_lazy", s.queriesLazy},
                           {"queries_traversal", s.queriesTraversal},
                           {"queries_skipped_extent", s.queriesSkippedExtent},
                           {"leaves_skipped_extent", s.leavesSkippedExtent},
                           {"subtrees_postponed", s.subtreesPostponed},
                           {"pairs_decided_bounds", s.pairsDecidedBounds},
                           {"pairs_tested_batched", s.pairsTestedBatched},
                           {"batched_rounds", s.batchedRounds},
                           {"bounds_updates", s.boundsUpdates},
                           {"bounds_from_camera", s.boundsFromCamera},
                           {"bounds_from_hemisphere", s.boundsFromHemisphere},
                           {"cells_drawn", s.cellsDrawn},
                           {"cell_entries", s.cellEntries},
                           {"cells_whole_tree", s.cellsWholeTree},
                           {"hint_passes", s.hintPasses},
                           {"hint_rays_left", s.hintRaysLeft},
                           {"shared_lists_made", s.sharedListsMade},
                           {"shared_lists_reused", s.sharedListsReused},
                           {"bounds_ms", s.boundsMs},
                           {"decide_ms", s.decideMs},
                           {"cell_list_ms", s.cellListMs},
                           {"pass_timed_traces", s.passTimedTraces},
                           {"bounds_culled_pieces", s.boundsCulledPieces},
                           {"bounds_culled_frustum", s.boundsCulledFrustum},
                           {"bounds_reached", s.boundsReached},
                           {"pairs_visible", s.pairsVisible},
                           {"pairs_invisible", s.pairsInvisible},
                           {"pairs_newly_visible", s.pairsNewlyVisible},
                           {"pairs_pulled_up", s.pairsPulledUp},
                           {"subtrees_scheduled", s.subtreesScheduled},
                           {"shader_calls", s.shaderCalls},
                           {"barriers", s.barriers},
                           {"residency_rounds", s.residencyRounds},
                           {"rays_traced", s.raysTraced},
                           {"phase1_ms", s.phase1Ms},
                           {"phase2_ms", s.phase2Ms},
                           {"phase3_ms", s.phase3Ms},
                           {"fallback_ms", s.fallbackMs}};
    // Pass times only where some trace's passes were timed (ChcrtOptions::passTimerInterval): estimated for all
    // culled traces from those.
    if (s.passTimedTraces > 0) {
        sums["subtree_pass_ms"] = s.estimatedPassMs(s.subtreePassMs);
        sums["hint_pass_ms"] = s.estimatedPassMs(s.hintPassMs);
    }
    nlohmann::json perFrame = nlohmann::json::object();
    for (auto it = sums.begin(); it != sums.end(); ++it) perFrame[it.key()] = it.value().get<double>() / f;
    const double ms = s.totalMs();
    return {{"frames", frames},
            {"sum", sums},
            {"per_frame", perFrame},
            {"mrays_per_s", ms > 0 ? double(s.raysTraced) / (ms * 1000.0) : 0.0}};
}

} // namespace chcrt::app
