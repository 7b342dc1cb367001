// The short soak run (the long one is scripts/soak.sh; docs/robustness.md, "Long runs"): 500-frame walkthroughs at
// low resolution keep the process's resident memory, open files, threads and live GL objects flat after a warm-up
// of 50 frames, read from their --resource-log samples.
#include "tests/app/cli_fixture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace chcrt::clitest;

constexpr int kFrames = 500, kWarmup = 50, kEvery = 25;
constexpr double kFileBackedSlackMb = 8;

// An orbit at street level around the centre of city:20k (bounds ±167 × 0..68 × ±174), one lap per 300 frames.
std::string orbitPath() {
    std::ostringstream path;
    path << R"({"version": 1, "fps": 30, "keyframes": [)";
    for (int k = 0; k <= kFrames / 300 * 8 + 8; ++k) {
        const double a = 2 * M_PI * k / 8, r = 110, h = 12;
        path << (k ? "," : "") << R"({"t": )" << k * 10.0 / 8 << R"(, "eye": [)" << r * std::cos(a) << ", " << h << ", "
             << r * std::sin(a) << R"(], "target": [)" << r * std::cos(a + 0.6) << ", " << h << ", "
             << r * std::sin(a + 0.6) << "]}";
    }
    path << "]}";
    return path.str();
}

std::vector<nlohmann::json> readLines(const fs::path& file) {
    std::vector<nlohmann::json> lines;
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
        if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
    }
    return lines;
}

// After the warm-up: anonymous resident memory (heaps and anonymous maps: what a leak grows) within 1 % of the
// warm-up sample's resident memory, the same open files, threads and GL objects. Out of core the subtrees in flight
// move the anonymous part by ~1 MB (one run: 100.18 against 99.09 MB, about 0.45 % of its ~240 MB resident). Resident
// pages of mapped files (the libraries' code, ~144 MB of the ~238 MB here, libLLVM's most) are the kernel's to map: a
// page fault maps its neighbours too where they are in the page cache ("fault-around"), so what other processes ran
// decides part of it; they may move by kFileBackedSlackMb. A CI run of this test beside others stepped by 4.2 MB (1.8 %
// of all resident memory, which was all it recorded then) between frames 50 and 75 and was flat after; runs here,
// alone and beside other tests, did not reproduce it.
// `queryGrowth`: out of core, CHC+RT's pool of subtree-pass timers (two queries each, culling/chcrt_tracer.cpp
// beginPassTimer) grows to the most cache rounds one trace has needed so far, which this walkthrough reaches after the
// warm-up: queries may grow by that much, and never shrink.
void expectFlat(const std::vector<nlohmann::json>& samples, int frames, int queryGrowth = 0) {
    ASSERT_EQ(samples.size(), size_t(frames / kEvery + 1)) << "a sample every " << kEvery << " frames and the last";
    const nlohmann::json* warm = nullptr;
    for (const nlohmann::json& s : samples) {
        if (s["frame"].get<int>() < kWarmup) continue;
        if (!warm) {
            warm = &s;
            EXPECT_GT(s["gl_objects"]["total"].get<int>(), 0);
            continue;
        }
        const double anon = s["rss_anon_mb"].get<double>(), anon0 = (*warm)["rss_anon_mb"].get<double>();
        const double rss0 = (*warm)["rss_mb"].get<double>();
        EXPECT_LT(std::abs(anon - anon0) / rss0, 0.01) << "frame " << s["frame"] << ": " << anon << " MB anonymous, "
                                                     << anon0 << " MB at frame " << (*warm)["frame"] << " of " << rss0
                                                     << " MB resident";
        const double file = s["rss_file_mb"].get<double>(), file0 = (*warm)["rss_file_mb"].get<double>();
        EXPECT_LT(std::abs(file - file0), kFileBackedSlackMb) << "frame " << s["frame"] << ": " << file
                                                              << " MB of files, " << file0 << " MB at the warm-up";
        nlohmann::json objects = s["gl_objects"], warmObjects = (*warm)["gl_objects"];
        const int queries = objects["queries"].get<int>(), warmQueries = warmObjects["queries"].get<int>();
        EXPECT_GE(queries, warmQueries) << "frame " << s["frame"];
        EXPECT_LE(queries, warmQueries + queryGrowth) << "frame " << s["frame"];
        for (nlohmann::json* o : {&objects, &warmObjects}) o->erase("queries"), o->erase("total");
        EXPECT_EQ(objects, warmObjects) << "frame " << s["frame"];
        EXPECT_EQ(s["open_files"], (*warm)["open_files"]) << "frame " << s["frame"];
        EXPECT_EQ(s["threads"], (*warm)["threads"]) << "frame " << s["frame"];
    }
    EXPECT_EQ(samples.back()["frame"].get<int>(), frames - 1);
}

const std::string kWalk = "render --camera-path orbit.json --width 32 --height 24 --spp 1 --effects shadow -q -o f.png "
                          "--resource-every " + std::to_string(kEvery) + " --resource-log r.jsonl ";
const std::string kAll = "--frames 0-" + std::to_string(kFrames - 1) + " ";

TEST_F(CliTest, FiveHundredFramesOfEachKindOfMethodKeepTheProcessFlat) {
    write("orbit.json", orbitPath());
    const std::string& walk = kWalk;
    const std::string& all = kAll;
    // chcrt-noadapt rather than chcrt: chcrt's adaptive choice follows measured times, so on a loaded machine it can
    // first use a configuration (its shader variants compiled, its buffers made at first use) long after the warm-up
    // — one run stepped by 4.1 MB (1.5 %) between frames 50 and 225 and stayed flat after. That is not a leak but
    // fails a 1 % bound; the always-culling variant runs the same culling code from its first frames. chcrt's long
    // run is in scripts/soak.sh (docs/robustness.md, "Long runs").
    for (const char* method : {"bvh", "chcrt-noadapt", "chcrt+ls"}) {
        SCOPED_TRACE(method);
        const Result r = run(walk + all + "--scene city:20k --ls-cache cache --method " + method, "LP_NUM_THREADS=0");
        ASSERT_EQ(r.exitCode, 0) << r.output;
        expectFlat(readLines(dir_ / "r.jsonl"), kFrames);
    }
}

// Out of core through a GPU cache of 3 slots and a 2 MiB host store: every frame uploads and reads subtrees.
TEST_F(CliTest, FiveHundredFramesOutOfCoreKeepTheProcessFlat) {
    write("orbit.json", orbitPath());
    const std::string& walk = kWalk;
    const std::string& all = kAll;
    ASSERT_EQ(run("prepare --scene city:200k --subtree-triangles 4000 -o c.chs -q").exitCode, 0);
    const std::string outOfCore = "--scene c.chs --out-of-core --load-in-core off --gpu-cache-mb 1 --host-cache-mb 2 "
                                  "--method chcrt";
    const Result r = run(walk + all + outOfCore, "LP_NUM_THREADS=0");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    expectFlat(readLines(dir_ / "r.jsonl"), kFrames, 16);
    // It streamed (a separate run: --stats-json keeps every frame's statistics in memory until the end): the cache
    // evicted and the store read after the warm-up; each frame's statistics hold the resources of the process.
    const Result stats = run(walk + outOfCore + " --frames 50-99 --stats-json s.json", "LP_NUM_THREADS=0");
    ASSERT_EQ(stats.exitCode, 0) << stats.output;
    double evictions = 0, reads = 0;
    const nlohmann::json run = readJson("s.json");
    for (const nlohmann::json& f : run["frames"]) {
        evictions += f["outofcore"]["cache_evictions"].get<double>();
        reads += f["outofcore"]["host_reads"].get<double>();
        EXPECT_GT(f["resources"]["gl_objects"]["total"].get<int>(), 0) << f.dump();
        EXPECT_GT(f["resources"]["rss_mb"].get<double>(), 0.0);
    }
    EXPECT_GT(evictions, 0.0) << stats.output;
    EXPECT_GT(reads, 0.0);
}

} // namespace
