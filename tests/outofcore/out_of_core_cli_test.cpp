// `--out-of-core` from the command line (issue #5 part 2): verify is exact with a GPU cache ~15x smaller than
// the scene, bench reports the Table 3 statistics, a scene that is not loaded in core renders and benchmarks
// without a pure-BVH reference, and bad combinations are one-line errors with exit code 2.
#include "tests/app/cli_fixture.h"
#include "tests/outofcore/outofcore_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>

namespace chcrt {
namespace {

using CliRun = clitest::Result;

CliRun chcrt(const std::filesystem::path& dir, const std::string& arguments) { return clitest::runChcrt(dir, arguments); }

size_t lineCount(const std::string& text) { return size_t(std::count(text.begin(), text.end(), '\n')); }

class OutOfCoreCli : public ::testing::Test {
protected:
    void SetUp() override {
        // ~14 MB of subtrees on the GPU, slots of ~0.3 MB: a 1 MB cache holds 3 of 90.
        const CliRun prepare = chcrt(dir_.file(""), "prepare --scene city:200k -o c.chs --subtree-triangles 4000 -q");
        ASSERT_EQ(prepare.exitCode, 0) << prepare.output;
    }
    test::ScratchDir dir_;
};

// Exact out of core in both subtree layouts; the compact one (the default) fits twice the subtrees in the same budget.
TEST_F(OutOfCoreCli, VerifyIsExactWithASmallCache) {
    const CliRun full = chcrt(dir_.file(""), "prepare --scene city:200k -o f.chs --subtree-triangles 4000 --layout full -q");
    ASSERT_EQ(full.exitCode, 0) << full.output;
    for (const std::string file : {"c.chs", "f.chs"}) {
        const CliRun run = chcrt(dir_.file(""), "verify --scene " + file + " --method chcrt --out-of-core --gpu-cache-mb 1 "
                                                "--host-cache-mb 2 --cache-policy round-robin --width 96 --height 64 "
                                                "--frames 0-2 --ray-type primary,shadow,ao -q");
        EXPECT_EQ(run.exitCode, 0) << run.output;
        EXPECT_NE(run.output.find("PASS: 0 differing"), std::string::npos) << run.output;
        const std::string slots = file == "c.chs" ? "out of core: 6 GPU cache slots" : "out of core: 3 GPU cache slots";
        EXPECT_NE(run.output.find(slots), std::string::npos) << run.output;
    }
}

TEST_F(OutOfCoreCli, BenchReportsTable3StatisticsInAndOutOfCore) {
    for (const std::string inCore : {"on", "off"}) {
        const CliRun run = chcrt(dir_.file(""), "bench --scene c.chs --method chcrt --out-of-core --gpu-cache-mb 1 "
                                                "--load-in-core " + inCore + " --ray-type primary,ao --width 64 "
                                                "--height 48 --frames 0-1 --runs 1 --warmup 0 --json b.json -q");
        ASSERT_EQ(run.exitCode, 0) << run.output;
        std::ifstream in(dir_.file("b.json"));
        const nlohmann::json j = nlohmann::json::parse(in);
        ASSERT_EQ(j["rows"].size(), 2u);
        for (const nlohmann::json& row : j["rows"]) {
            ASSERT_TRUE(row.contains("outofcore")) << row.dump();
            const nlohmann::json& o = row["outofcore"];
            EXPECT_GT(o["queries"].get<double>(), 0.0);
            EXPECT_LE(o["allocated_mb"].get<double>(), 1.0);
            EXPECT_EQ(o["slots"].get<int>(), 6); // compact subtrees: 6 of the largest in 1 MB
            EXPECT_EQ(o["frames"].size(), 2u);
            EXPECT_GT(row["active_rays_per_frame"].get<double>(), 0.0);
            if (inCore == "on") EXPECT_EQ(row["diff_pixels"].get<int>(), 0);
            else EXPECT_TRUE(row["diff_pixels"].is_null());
        }
        EXPECT_GT(j["rows"][0]["outofcore"]["cache_misses"].get<double>(), 6.0); // more uploads than slots
    }
}

TEST_F(OutOfCoreCli, RendersWithoutTheSceneInCore) {
    const CliRun run = chcrt(dir_.file(""), "render --scene c.chs --method chcrt --out-of-core --gpu-cache-mb 2 "
                                            "--load-in-core off --effects shadow,ao --width 64 --height 48 --frames 0-1 "
                                            "-o f_####.png --stats-json s.json -q");
    ASSERT_EQ(run.exitCode, 0) << run.output;
    EXPECT_TRUE(std::filesystem::exists(dir_.file("f_0001.png")));
    std::ifstream in(dir_.file("s.json"));
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_EQ(j["frames"].size(), 2u);
    EXPECT_GT(j["frames"][1]["outofcore"]["cache_hits"].get<double>(), 0.0);
}

TEST_F(OutOfCoreCli, BadCombinationsAreExit2WithOneLine) {
    for (const std::string arguments : {
             "verify --scene c.chs --method bvh --out-of-core",
             "verify --scene city:20k --method chcrt --out-of-core",
             "verify --scene c.chs --method chcrt --out-of-core --load-in-core off",
             "verify --scene c.chs --method chcrt --out-of-core --cache-policy fifo",
             "verify --scene c.chs --method chcrt --out-of-core --gpu-cache-mb 0",
             "bench --scene c.chs --method chcrt,embree --out-of-core --load-in-core off",
         }) {
        const CliRun run = chcrt(dir_.file(""), arguments + " --frames 0 --width 32 --height 32 -q");
        EXPECT_EQ(run.exitCode, 2) << arguments << "\n" << run.output;
        EXPECT_EQ(lineCount(run.output), 1u) << arguments << "\n" << run.output;
        EXPECT_EQ(run.output.rfind("chcrt: error: ", 0), 0u) << arguments << "\n" << run.output;
    }
}

// --prefetch-frames along a walkthrough with a host cache of a fraction of the scene: every frame's peaks of the
// host cache and of the GPU cache (from the counters) stay within --host-cache-mb and --gpu-cache-mb, and the
// read-ahead ran (reads, or prefetches skipped because the frames' own subtrees filled the host cache).
TEST_F(OutOfCoreCli, PrefetchKeepsTheHostAndGpuBudgetsAlongAWalkthrough) {
    const CliRun run = chcrt(dir_.file(""), "render --scene c.chs --method chcrt --out-of-core --gpu-cache-mb 1 "
                                            "--host-cache-mb 4 --prefetch-frames 2 --prefetch-mb 2 --load-in-core off "
                                            "--effects shadow,ao --spp 1 --width 64 --height 48 --frames 0-150:15 "
                                            "-o f_####.png --stats-json s.json -q");
    ASSERT_EQ(run.exitCode, 0) << run.output;
    std::ifstream in(dir_.file("s.json"));
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_EQ(j["frames"].size(), 11u);
    double reads = 0, skipped = 0, hostPeak = 0, gpuPeak = 0;
    for (const nlohmann::json& frame : j["frames"]) {
        const nlohmann::json& o = frame["outofcore"];
        EXPECT_EQ(o["prefetch_frames"].get<int>(), 2);
        EXPECT_LE(o["host_peak_resident_mb"].get<double>(), 4.0) << frame["frame"];
        EXPECT_LE(o["peak_resident_mb"].get<double>(), 1.0) << frame["frame"];
        reads += o["prefetch_reads"].get<double>();
        skipped += o["prefetch_skipped"].get<double>();
        hostPeak = std::max(hostPeak, o["host_peak_resident_mb"].get<double>());
        gpuPeak = std::max(gpuPeak, o["peak_resident_mb"].get<double>());
    }
    EXPECT_GT(reads + skipped, 0.0) << "the read-ahead ran";
    EXPECT_GT(hostPeak, 1.0) << "the host cache was used up to near its budget";
    EXPECT_GT(gpuPeak, 0.5);
}

TEST_F(OutOfCoreCli, BadPrefetchValuesAreExit2WithOneLine) {
    for (const std::string arguments : {
             "render --prefetch-frames -1 -o x.png",
             "render --prefetch-frames 100000 -o x.png",
             "render --prefetch-frames two -o x.png",
             "bench --prefetch-frames -1",
             "bench --prefetch-mb 0",
         }) {
        const CliRun run = chcrt(dir_.file(""), arguments + " --scene c.chs --method chcrt --out-of-core --frames 0 "
                                                            "--width 32 --height 32 -q");
        EXPECT_EQ(run.exitCode, 2) << arguments << "\n" << run.output;
        EXPECT_EQ(lineCount(run.output), 1u) << arguments << "\n" << run.output;
        EXPECT_EQ(run.output.rfind("chcrt: error: ", 0), 0u) << arguments << "\n" << run.output;
    }
}

} // namespace
} // namespace chcrt
