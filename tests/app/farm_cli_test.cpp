// The farm's command line without a cluster: render --records/--resume, and `chcrt farm submit --print` whose
// script runs here as Slurm would run each array task (SLURM_ARRAY_TASK_ID set), then status and collect. The
// same flow on a real one-node cluster is tests/app/farm_cluster_test.sh.
#include "tests/app/cli_fixture.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace chcrt::clitest;

// The lines of a records file (JSON Lines) by kind.
struct Records {
    std::vector<nlohmann::json> headers, frames, ends;
};
Records readRecords(const fs::path& file) {
    Records r;
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
        const nlohmann::json j = nlohmann::json::parse(line);
        if (j.contains("header")) r.headers.push_back(j["header"]);
        else if (j.contains("end")) r.ends.push_back(j["end"]);
        else r.frames.push_back(j);
    }
    return r;
}

std::string frameName(const std::string& prefix, int frame) {
    char name[64];
    std::snprintf(name, sizeof name, "%s%04d.png", prefix.c_str(), frame);
    return name;
}

constexpr const char* kScene = "--scene city:10k ";

TEST_F(CliTest, RenderRecordsProveFramesAndResumeRendersOnlyWhatIsMissing) {
    const std::string render = std::string("render ") + kScene + "--frames 0-2 -o f_####.png --records r.jsonl " + kSmall;
    const Result first = run(render + " --stats-json s.json");
    ASSERT_EQ(first.exitCode, 0) << first.output;
    Records records = readRecords(dir_ / "r.jsonl");
    ASSERT_EQ(records.headers.size(), 1u);
    EXPECT_GT(records.headers[0]["startup_s"].get<double>(), 0.0);
    EXPECT_FALSE(records.headers[0]["commit"].get<std::string>().empty());
    const std::string digest = records.headers[0]["flags_digest"];
    ASSERT_EQ(records.frames.size(), 3u);
    for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(records.frames[k]["frame"], k);
        EXPECT_EQ(records.frames[k]["flags_digest"], digest);
        EXPECT_EQ(records.frames[k]["output"], frameName("f_", k));
        EXPECT_EQ(records.frames[k]["stats"]["frame"], k);
    }
    ASSERT_EQ(records.ends.size(), 1u);
    EXPECT_EQ(records.ends[0]["rendered"], 3);

    // Frame 1 lost, frame 2 damaged: a resumed run renders exactly those two, to the same bytes.
    const std::string frame1 = readFile(frameName("f_", 1));
    fs::remove(dir_ / frameName("f_", 1));
    write(frameName("f_", 2), "not an image");
    const Result resumed = run(render + " --resume --stats-json s.json");
    ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
    records = readRecords(dir_ / "r.jsonl");
    ASSERT_EQ(records.frames.size(), 5u);
    EXPECT_EQ(records.frames[3]["frame"], 1);
    EXPECT_EQ(records.frames[4]["frame"], 2);
    EXPECT_EQ(readFile(frameName("f_", 1)), frame1);
    const nlohmann::json stats = readJson("s.json");
    ASSERT_EQ(stats["frames"].size(), 3u); // every selected frame once, the resumed one from its record
    for (int k = 0; k < 3; ++k) EXPECT_EQ(stats["frames"][k]["frame"], k);

    // Nothing missing: nothing rendered. Other pixel-deciding flags: nothing proven, all rendered again.
    ASSERT_EQ(run(render + " --resume").exitCode, 0);
    EXPECT_EQ(readRecords(dir_ / "r.jsonl").frames.size(), 5u);
    ASSERT_EQ(run(render + " --resume --rotation 90").exitCode, 0);
    EXPECT_EQ(readRecords(dir_ / "r.jsonl").frames.size(), 8u);

    const Result noRecords = run(std::string("render ") + kScene + "--frames 0 -o g_####.png --resume " + kSmall);
    EXPECT_EQ(noRecords.exitCode, 2) << noRecords.output;
    EXPECT_NE(noRecords.output.find("--resume needs --records"), std::string::npos) << noRecords.output;
}

// Slurm's part, played here: each array index of the printed script run by bash.
TEST_F(CliTest, FarmScriptTasksRenderTheSameFramesAsOneLocalRender) {
    const std::string flags = std::string(kScene) + "-o out/f_####.png --stats-json out/stats.json " + kSmall;
    const Result print = run("farm submit --frames 0-11 --chunk 4 --print " + flags, "PATH=/nonexistent");
    ASSERT_EQ(print.exitCode, 0) << print.output;
    EXPECT_NE(print.output.find("#SBATCH --array=0-2\n"), std::string::npos) << print.output;
    EXPECT_NE(print.output.find("'--frames' '8-11'"), std::string::npos) << print.output;
    EXPECT_NE(print.output.find("not submitted (--print)"), std::string::npos) << print.output;
    ASSERT_TRUE(exists("out/stats.farm/job-0.sbatch"));

    // Before any task ran: all 12 missing, nothing to collect.
    const Result before = run("farm status out/stats.json", "PATH=/nonexistent");
    EXPECT_EQ(before.exitCode, 4) << before.output;
    EXPECT_NE(before.output.find("missing  12: frames 0-11"), std::string::npos) << before.output;
    EXPECT_EQ(run("farm collect out/stats.json").exitCode, 4);
    EXPECT_FALSE(exists("out/stats.json"));

    for (int task = 0; task < 3; ++task) {
        const std::string command = "cd '" + dir_.string() + "' && SLURM_ARRAY_TASK_ID=" + std::to_string(task) +
                                    " SLURM_ARRAY_JOB_ID=7 bash out/stats.farm/job-0.sbatch > /dev/null 2>&1";
        ASSERT_EQ(std::system(command.c_str()), 0) << "task " << task;
    }
    const Result status = run("farm status out/stats.json", "PATH=/nonexistent");
    EXPECT_EQ(status.exitCode, 0) << status.output;
    EXPECT_NE(status.output.find("done     12"), std::string::npos) << status.output;
    const Result collect = run("farm collect out/stats.json");
    ASSERT_EQ(collect.exitCode, 0) << collect.output;
    const nlohmann::json stats = readJson("out/stats.json");
    ASSERT_EQ(stats["frames"].size(), 12u);
    for (int k = 0; k < 12; ++k) EXPECT_EQ(stats["frames"][k]["frame"], k);
    ASSERT_EQ(stats["tasks"].size(), 3u);
    for (const nlohmann::json& t : stats["tasks"]) {
        EXPECT_EQ(t["exit_code"], 0);
        EXPECT_GT(t["startup_s"].get<double>(), 0.0);
    }

    // The same frames from one local process: identical files.
    ASSERT_EQ(run(std::string("render ") + kScene + "--frames 0-11 -o local_####.png " + kSmall).exitCode, 0);
    for (int k = 0; k < 12; ++k) {
        EXPECT_EQ(readFile("out/" + frameName("f_", k)), readFile(frameName("local_", k))) << "frame " << k;
    }
    // Resubmitting a finished sequence submits nothing.
    const Result again = run("farm submit --frames 0-11 --chunk 4 " + flags, "PATH=/nonexistent");
    EXPECT_EQ(again.exitCode, 0) << again.output;
    EXPECT_NE(again.output.find("all 12 frame(s) are done"), std::string::npos) << again.output;
    // --force submits every frame again, proven or not.
    const Result forced = run("farm submit --frames 0-11 --chunk 4 --force --print " + flags, "PATH=/nonexistent");
    EXPECT_EQ(forced.exitCode, 0) << forced.output;
    EXPECT_NE(forced.output.find("#SBATCH --array=0-2\n"), std::string::npos) << forced.output;
    EXPECT_NE(forced.output.find("'--frames' '0-3'"), std::string::npos) << forced.output;
    EXPECT_NE(forced.output.find("'--frames' '8-11'"), std::string::npos) << forced.output;
}

// bench rows (scene x ray type x method) as array tasks; a row whose task never ran is the only one resubmitted,
// and its exit line lands in its own row's file although it is array index 0 of the second job.
TEST_F(CliTest, FarmBenchRowsResubmitOnlyTheMissingRowAndCollectInOrder) {
    const std::string bench = "farm bench --scene city:10k,plane-and-box --ray-type shadow --method bvh,chcrt "
                              "--frames 0 --runs 1 --warmup 0 --json out/bench.json --width 32 --height 24 -q --print";
    ASSERT_EQ(run(bench, "PATH=/nonexistent").exitCode, 0);
    auto runTask = [&](const std::string& script, int task) {
        const std::string command = "cd '" + dir_.string() + "' && SLURM_ARRAY_TASK_ID=" + std::to_string(task) +
                                    " SLURM_ARRAY_JOB_ID=9 bash " + script + " > /dev/null 2>&1";
        return std::system(command.c_str());
    };
    for (int task : {0, 1, 3}) ASSERT_EQ(runTask("out/bench.farm/job-0.sbatch", task), 0) << "task " << task;
    const Result partial = run("farm status out/bench.json", "PATH=/nonexistent");
    EXPECT_EQ(partial.exitCode, 4) << partial.output;
    EXPECT_NE(partial.output.find("missing  1"), std::string::npos) << partial.output;

    const Result again = run(bench, "PATH=/nonexistent");
    ASSERT_EQ(again.exitCode, 0) << again.output;
    EXPECT_NE(again.output.find("#SBATCH --array=0-0\n"), std::string::npos) << again.output;
    EXPECT_NE(again.output.find("'row_2.exit.jsonl'"), std::string::npos) << again.output;
    ASSERT_EQ(runTask("out/bench.farm/job-1.sbatch", 0), 0);
    EXPECT_TRUE(exists("out/bench.farm/parts/row_2.exit.jsonl"));
    EXPECT_EQ(run("farm status out/bench.json", "PATH=/nonexistent").exitCode, 0);
    const Result collect = run("farm collect out/bench.json");
    ASSERT_EQ(collect.exitCode, 0) << collect.output;
    const nlohmann::json j = readJson("out/bench.json");
    // Each row task traces its method and pure BVH (the reference of its ratio): the method's rows, in row order.
    std::vector<std::string> rows;
    for (const nlohmann::json& row : j["rows"]) {
        EXPECT_EQ(row["ray_type"], "shadow");
        EXPECT_EQ(row["diff_pixels"], 0) << row["method"];
        rows.push_back(row["scene"].get<std::string>() + " " + row["method"].get<std::string>());
    }
    EXPECT_FALSE(rows.empty());
    EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end(), [](const std::string& a, const std::string& b) {
        return a.rfind("city", 0) == 0 && b.rfind("city", 0) != 0; // city's rows first: row order, not finish order
    }));
    ASSERT_EQ(j["tasks"].size(), 4u);
    EXPECT_TRUE(j.contains("settings") && j.contains("gl_renderer") && j.contains("machine"));
    for (const nlohmann::json& t : j["tasks"]) EXPECT_FALSE(t["command_line"].empty());
}

TEST_F(CliTest, FarmSubmitRefusesBadInputBeforeWritingAnything) {
    const std::string ok = std::string(kScene) + "--frames 0-11 -o out/f_####.png --stats-json out/stats.json " + kSmall;
    for (const std::string& bad : {ok + " --spp banana", ok + " --chunk 0", ok + " --method nosuch",
                                   ok + " --no-such-flag", std::string(kScene) + "-o out/f.png --frames 0-3 --stats-json out/s.json",
                                   std::string(kScene) + "-o out/f_####.png --frames 0-3",
                                   std::string(kScene) + "-o out/f_####.png --frames all --stats-json out/s.json"}) {
        const Result r = run("farm submit --print " + bad, "PATH=/nonexistent");
        EXPECT_EQ(r.exitCode, 2) << bad << "\n" << r.output;
        EXPECT_FALSE(exists("out")) << bad;
    }
    // Without Slurm: a clear error and no farm directory (--print still works, above).
    const Result noSlurm = run("farm submit " + ok, "PATH=/nonexistent");
    EXPECT_EQ(noSlurm.exitCode, 2) << noSlurm.output;
    EXPECT_NE(noSlurm.output.find("sbatch not found"), std::string::npos) << noSlurm.output;
    EXPECT_FALSE(exists("out"));
    const Result noSubmission = run("farm status out/stats.json");
    EXPECT_EQ(noSubmission.exitCode, 2) << noSubmission.output;
}

} // namespace
