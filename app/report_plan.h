#pragma once
// What `chcrt report` measures (app/command_report.cpp): a preset's scenes, paths, methods and studies, the flags
// that override them, and the list of bench and render commands they make. Each command is one resumable group:
// its output (bench JSON, or images with a sidecar) is kept in the report's data/ and images/ folders, and a
// resumed report skips every group whose output was made by the same command.
#include <map>
#include <string>
#include <vector>

namespace chcrt::app {

// The studies a report can run, each the shape of one of the papers' tables or figures.
//   compare     every method over scenes x paths x ray types (Table 2, Figures 7 and 8; --steps where the preset
//               counts steps: culling efficiency)
//   aggressive  chcrt-aggressive per visibility threshold (Table 4), on each scene's first path
//   rotation    per-pixel sample rotation (Table 5), bvh, chcrt, chcrt-noadapt
//   work        BVH traversal steps of bvh and chcrt-noadapt per forced termination height
//   ls-rc       bvh, bvh+ls-exact, bvh+ls per Line Space depth (RC Table 1 shape: speed against image error)
//   ls-ao       AO candidates per depth and face rule
//   ls-ss       25 shadow rays per pixel, bvh+ls shadow termination per patch count N (SS Table 1 shape)
//   ls-sscand   the same with representative candidates per N:D
//   ls-ntree    the same over the N-tree (ntree+ls) per N:d
//   images      the rendered frame, the CHC+RT debug images and every approximate method's frame (difference
//               images against pure BVH), frame 0 of each scene's first path
const std::vector<std::string>& reportStudies();

struct ReportSettings {
    std::vector<std::string> scenes; // generator spec or file, optionally "@near", "@far" or "@path.json"
    std::vector<std::string> paths;  // of generated scenes without "@"
    std::vector<std::string> methods; // compare study (bvh is always traced: the reference)
    std::vector<std::string> rayTypes;
    std::vector<std::string> studies;
    int size = 128;          // width = height
    std::string frames = "0-7"; // consecutive, so that temporal coherence works and the curves are curves
    int runs = 3, warmup = 1;
    int singleViewRuns = 8;  // a scene file's single view: its runs are what temporal coherence sees
    std::map<std::string, int> spp; // per ray type
    bool steps = true;       // compare: bench --steps
    std::vector<std::string> thresholds, rotations, heights;
    std::vector<std::string> aggressiveRayTypes, rotationRayTypes;
    std::vector<std::string> lsDepths, lsSsN, lsNtree, lsSsCandidate;
    int lsSpp = 1, lsN = 6, lsSsDepth = 9, lsNtreeNear = 0;
    std::string lsCache;     // "" = bench's default
    int imageSpp = 1;
    std::string gl;          // --gl for every command, "" = the default
};

// quick: the procedural scenes at 200k triangles, 128², 8 frames, a few minutes on two cores; paper: the CHC+RT
// paper's set (scripts/bench_chcrt.sh); linespace: the Line Space papers' set (scripts/bench_linespace.sh).
// Throws InputError naming the presets for an unknown one.
ReportSettings presetSettings(const std::string& preset);
std::string presetNames();

// One command of a report: a bench writing data/<id>.json, or the renders of an images group.
struct ReportGroup {
    std::string id;    // file name stem, unique within the report
    std::string study;
    std::string label; // for progress lines: "city-200k near primary,shadow"
    bool images = false;
    std::vector<std::vector<std::string>> commands; // words after the binary
    double cost = 1;   // relative work, for the ETA
    // images: what the files are (key -> path relative to the report folder)
    std::map<std::string, std::string> files;
    std::string scene, path;
    int frame = 0;
};

// Checks every name (scenes, paths, methods, ray types, studies, numbers) and makes the groups, their outputs under
// `outDir`; throws InputError for anything that would fail later, so that bad input writes nothing.
std::vector<ReportGroup> planReport(const ReportSettings& settings, const std::string& outDir);

// `chcrt report`'s flags: a preset, what overrides it (empty strings and -1: not given), or existing bench JSON.
struct ReportOptions {
    std::string out;
    std::string preset = "quick";
    std::string scenes, paths, methods, rayTypes, studies, frames, spp, thresholds, rotations, heights;
    std::string lsDepths, lsSsN, lsNtree, lsSsCandidate, lsCache, gl;
    int size = -1, runs = -1, warmup = -1, singleViewRuns = -1, lsSpp = -1, lsN = -1, lsSsDepth = -1,
        lsNtreeNear = -1;
    std::vector<std::string> fromJson; // report these instead of running benches
    bool quiet = false;
    std::vector<std::string> words;    // the command line, for the report
};
// The preset with the given flags applied.
ReportSettings reportSettings(const ReportOptions& options);

// "city:200k" -> "city-200k", "../scenes/castle.gltf" -> "castle": a file-name-safe label.
std::string sceneLabel(const std::string& scene);

} // namespace chcrt::app
