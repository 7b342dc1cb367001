// The render farm's logic without Slurm (app/farm.h, app/render_records.h): how frames are chunked and selected,
// which flags decide pixels, what proves a frame done, how records survive a kill, and what the sbatch script
// runs, and what Slurm's sacct and scontrol say of array tasks. The cluster itself is exercised by
// tests/app/farm_cluster_test.sh.
#include "app/farm.h"
#include "app/render_records.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace chcrt::app;
using Words = std::vector<std::string>;

class FarmFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("chcrt_farm_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
                std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path write(const std::string& name, const std::string& bytes) const {
        std::ofstream(dir_ / name, std::ios::binary) << bytes;
        return dir_ / name;
    }
    fs::path dir_;
};

TEST(FarmChunks, ChunksAreConsecutiveAndCoverEveryFrameOnce) {
    std::vector<int> frames;
    for (int f = 0; f < 12; ++f) frames.push_back(f);
    const auto chunks = farm::chunkFrames(frames, 5);
    ASSERT_EQ(chunks.size(), 3u);
    EXPECT_EQ(chunks[0], (std::vector<int>{0, 1, 2, 3, 4}));
    EXPECT_EQ(chunks[1], (std::vector<int>{5, 6, 7, 8, 9}));
    EXPECT_EQ(chunks[2], (std::vector<int>{10, 11})); // the last chunk is shorter
    EXPECT_EQ(farm::chunkFrames(frames, 4).size(), 3u);
    EXPECT_EQ(farm::chunkFrames(frames, 100).size(), 1u);
    EXPECT_TRUE(farm::chunkFrames({}, 10).empty());
}

TEST(FarmChunks, FrameSelectionWritesRunsAsRanges) {
    EXPECT_EQ(farm::frameSelection({0, 1, 2, 5, 7, 8}), "0-2,5,7-8");
    EXPECT_EQ(farm::frameSelection({6, 7}), "6-7");
    EXPECT_EQ(farm::frameSelection({3}), "3");
    EXPECT_EQ(farm::frameSelection({}), "");
}

TEST(FarmWords, WordsWithoutDropsFlagsWithTheirValues) {
    const Words words = {"--scene", "city:200k", "--chunk", "10", "--partition=debug", "--wait", "--spp", "2"};
    EXPECT_EQ(farm::wordsWithout(words, {"--chunk", "--partition"}, {"--wait"}),
              (Words{"--scene", "city:200k", "--spp", "2"}));
    EXPECT_EQ(farm::wordsWithout(words, {}, {}), words);
}

TEST(FarmWords, ShellQuoteSurvivesQuotesAndSpaces) {
    EXPECT_EQ(farm::shellQuote("plain"), "'plain'");
    EXPECT_EQ(farm::shellQuote("it's a $x"), "'it'\\''s a $x'");
}

TEST(FarmRecords, DigestIgnoresBookkeepingButNotPixels) {
    const Words base = {"--scene", "city:200k", "--spp", "2", "--frames", "0-9", "-o", "out/f_####.png"};
    const std::string digest = flagsDigest(base);
    // Where a run writes and which frames it renders do not change any frame's pixels.
    EXPECT_EQ(flagsDigest({"--scene", "city:200k", "--spp", "2", "--frames=3", "-o", "elsewhere_####.png",
                           "--stats-json", "s.json", "--records", "r.jsonl", "--resume", "-q", "--gl-device", "1",
                           "--shader-stage", "compute"}),
              digest);
    EXPECT_EQ(pixelDecidingWords(base), (Words{"--scene", "city:200k", "--spp", "2"}));
    // Anything else does, and word boundaries count ("--spp 2" is not "--spp2").
    EXPECT_NE(flagsDigest({"--scene", "city:200k", "--spp", "4"}), digest);
    EXPECT_NE(flagsDigest({"--scene", "city:200k", "--spp2"}), flagsDigest({"--scene", "city:200k", "--spp", "2"}));
    EXPECT_EQ(digest.rfind("fnv1a64:", 0), 0u);
}

TEST_F(FarmFiles, ChecksumChangesWithTheBytes) {
    const fs::path a = write("a.bin", "pixels");
    const std::string sum = fileChecksum(a);
    EXPECT_FALSE(sum.empty());
    EXPECT_EQ(fileChecksum(write("b.bin", "pixels")), sum);
    EXPECT_NE(fileChecksum(write("c.bin", "pixelz")), sum);
    EXPECT_EQ(fileChecksum(dir_ / "missing.bin"), "");
}

TEST_F(FarmFiles, RecordProvesAFrameOnlyWithTheSameFlagsBuildAndImage) {
    const fs::path image = write("frame_0003.png", "image bytes");
    FrameRecord r;
    r.frame = 3;
    r.output = image.string();
    r.imageChecksum = fileChecksum(image);
    r.flagsDigest = "fnv1a64:0000000000000001";
    r.commit = "abc";
    EXPECT_TRUE(recordProvesFrame(r, image.string(), r.flagsDigest, "abc"));
    EXPECT_FALSE(recordProvesFrame(r, image.string(), "fnv1a64:0000000000000002", "abc")); // other flags
    EXPECT_FALSE(recordProvesFrame(r, image.string(), r.flagsDigest, "abd"));               // other build
    EXPECT_FALSE(recordProvesFrame(r, (dir_ / "frame_03.png").string(), r.flagsDigest, "abc")); // other name
    write("frame_0003.png", "overwritten");                                                   // image changed
    EXPECT_FALSE(recordProvesFrame(r, image.string(), r.flagsDigest, "abc"));
    fs::remove(image);                                                                        // image gone
    EXPECT_FALSE(recordProvesFrame(r, image.string(), r.flagsDigest, "abc"));
}

TEST_F(FarmFiles, RecordsSurviveATornLineAndWritingGoesOn) {
    const fs::path file = dir_ / "r.jsonl";
    {
        RecordsWriter w(file);
        w.append({{"header", {{"host", "node1"}}}});
        w.append({{"frame", 0}, {"output", "f0.png"}, {"image_checksum", "x"}, {"flags_digest", "d"}, {"commit", "c"}});
    }
    { std::ofstream(file, std::ios::app) << R"({"frame": 1, "output": "f1.p)"; } // killed mid-line
    {
        RecordsWriter w(file); // a resumed run appends after the torn line, not onto it
        w.append({{"frame", 2}, {"output", "f2.png"}, {"image_checksum", "y"}, {"flags_digest", "d"}, {"commit", "c"}});
    }
    { std::ofstream(file, std::ios::app) << R"({"task_exit": 137, "host": "node1", "wall_s": 1.5})" << "\n"; }
    const RecordsFile records = readRecordsFile(file);
    ASSERT_EQ(records.headers.size(), 1u);
    EXPECT_EQ(records.headers[0]["host"], "node1");
    ASSERT_EQ(records.frames.size(), 2u);
    EXPECT_EQ(records.frames[0].frame, 0);
    EXPECT_EQ(records.frames[1].frame, 2);
    EXPECT_EQ(records.frames[1].imageChecksum, "y");
    EXPECT_EQ(records.tornLines, 1u);
    ASSERT_TRUE(records.taskExit.has_value());
    EXPECT_EQ(records.taskExit->exitCode, 137);
    EXPECT_TRUE(readRecordsFile(dir_ / "missing.jsonl").frames.empty());
}

TEST_F(FarmFiles, ProvenFramesAndOutcomesComeFromThePartsRecords) {
    const fs::path parts = dir_ / "parts";
    fs::create_directories(parts);
    const std::string pattern = (dir_ / "f_####.png").string();
    const std::string digest = flagsDigest({"--spp", "1"});
    auto record = [&](RecordsWriter& w, int frame, const std::string& commit) {
        const fs::path image = write("f_000" + std::to_string(frame) + ".png", "frame " + std::to_string(frame));
        w.append({{"frame", frame}, {"output", image.string()}, {"image_checksum", fileChecksum(image)},
                  {"flags_digest", digest}, {"commit", commit}, {"stats", {{"frame", frame}}}});
    };
    {
        RecordsWriter w(parts / "7_0.jsonl");
        w.append({{"header", {{"host", "nodeA"}, {"startup_s", 0.5}}}});
        record(w, 0, "c1");
        record(w, 1, "c1");
        w.append({{"task_exit", 0}, {"label", "frames 0-1"}, {"host", "nodeA"}, {"wall_s", 2.0}});
    }
    {
        RecordsWriter w(parts / "7_1.jsonl");
        w.append({{"header", {{"host", "nodeB"}}}});
        record(w, 2, "c1");
        record(w, 3, "other build");
        w.append({{"task_exit", 137}, {"label", "frames 2-3"}, {"host", "nodeB"}, {"wall_s", 1.0}});
    }
    const auto proven = farm::provenFrames(parts, {0, 1, 2, 3}, pattern, digest, "c1");
    ASSERT_EQ(proven.size(), 3u);
    EXPECT_TRUE(proven.count(0) && proven.count(1) && proven.count(2));
    EXPECT_EQ(proven.at(2).part, "7_1.jsonl");
    EXPECT_EQ(proven.at(1).stats["frame"], 1);
    EXPECT_TRUE(farm::provenFrames(parts, {0, 1, 2, 3}, pattern, flagsDigest({"--spp", "2"}), "c1").empty());

    const auto outcomes = farm::renderTaskOutcomes(parts);
    ASSERT_EQ(outcomes.size(), 2u);
    for (const farm::TaskOutcome& t : outcomes) {
        EXPECT_TRUE(t.started && t.exited) << t.part;
        if (t.part == "7_1.jsonl") {
            EXPECT_EQ(t.exitCode, 137);
            EXPECT_EQ(t.label, "frames 2-3");
            EXPECT_EQ(t.host, "nodeB");
            EXPECT_EQ(t.framesRendered, (std::vector<int>{2, 3}));
        } else {
            EXPECT_EQ(t.exitCode, 0);
            EXPECT_DOUBLE_EQ(t.wallSeconds, 2.0);
            EXPECT_EQ(t.header["startup_s"], 0.5);
        }
    }
}

TEST(FarmScript, RunsEachChunkWithTheSharedFlagsQuoted) {
    farm::Plan plan;
    plan.directory = "/farm/out/stats.farm";
    plan.binary = "/opt/chcrt/bin/chcrt";
    plan.workingDirectory = "/farm";
    plan.command = {"render", "--scene", "my scene's.gltf", "-o", "out/f_####.png"};
    plan.tasks = {{{"--frames", "0-4", "--records", "parts/%j_%t.jsonl"}, "frames 0-4", {0, 1, 2, 3, 4}, "%j_%t.jsonl"},
                  {{"--frames", "5-6", "--records", "parts/%j_%t.jsonl"}, "frames 5-6", {5, 6}, "row_6.exit.jsonl"}};
    plan.slurm.partition = "gpu";
    plan.slurm.time = "01:00:00";
    plan.slurm.cpusPerTask = 4;
    plan.slurm.extra = {"--qos=high"};
    const std::string s = farm::sbatchScript(plan);
    auto has = [&](const std::string& text) { return s.find(text) != std::string::npos; };
    EXPECT_EQ(s.rfind("#!/bin/bash\n", 0), 0u);
    EXPECT_TRUE(has("#SBATCH --array=0-1\n"));
    EXPECT_TRUE(has("#SBATCH --partition=gpu\n"));
    EXPECT_TRUE(has("#SBATCH --time=01:00:00\n"));
    EXPECT_TRUE(has("#SBATCH --cpus-per-task=4\n"));
    EXPECT_TRUE(has("#SBATCH --qos=high\n"));
    EXPECT_TRUE(has("#SBATCH --chdir=/farm\n"));
    EXPECT_FALSE(has("--mem")) << "options not given are not written";
    EXPECT_FALSE(has("--gl-device")) << "no GPU binding without GPUs";
    // Each task's own frames; %j and %t expand at run time, everything else is quoted verbatim.
    EXPECT_TRUE(has("  0)\n    label='frames 0-4'\n    words=('--frames' '0-4' '--records' \"parts/${job}_${task}.jsonl\")"));
    EXPECT_TRUE(has("  1)\n    label='frames 5-6'\n    words=('--frames' '5-6'"));
    // Each task's exit line goes to its own file, named by the task (a bench row keeps its row's name).
    EXPECT_TRUE(has("  0)\n    label='frames 0-4'\n    words=('--frames' '0-4' '--records' \"parts/${job}_${task}.jsonl\")\n    exit_file=\"${parts}\"/\"${job}_${task}.jsonl\"\n    ;;\n"));
    EXPECT_TRUE(has("    exit_file=\"${parts}\"/'row_6.exit.jsonl'\n    ;;\n"));
    EXPECT_TRUE(has("'/opt/chcrt/bin/chcrt' 'render' '--scene' 'my scene'\\''s.gltf' '-o' 'out/f_####.png' \"${words[@]}\""));
    EXPECT_TRUE(has("exit $rc\n"));

    plan.slurm.gpusPerTask = 1;
    const std::string gpu = farm::sbatchScript(plan);
    EXPECT_NE(gpu.find("#SBATCH --gpus-per-task=1\n"), std::string::npos);
    EXPECT_NE(gpu.find("gl_device=(--gl-device \"${gpu%%,*}\")"), std::string::npos);
}

TEST(FarmScript, FarmDirectorySitsBesideTheCollectedOutput) {
    EXPECT_EQ(farm::farmDirectoryOf("out/stats.json"), fs::path("out/stats.farm"));
    EXPECT_EQ(farm::farmDirectoryOf("bench"), fs::path("bench.farm"));
}

// Slurm 22.05's own output shapes: `sacct -X -n -P -j 12 --format=JobID,State,ExitCode,NodeList` and
// `scontrol show job -o 12` for an array of four tasks (one completed, one cancelled while running, two pending).
TEST(FarmSlurm, SacctLinesGiveEachEndedArrayTask) {
    const std::string output = "12_0|COMPLETED|0:0|localhost\n"
                               "12_1|CANCELLED by 0|0:15|localhost\n"
                               "12_[2-3]|PENDING|0:0|None assigned\n"
                               "12_4|TIMEOUT|0:0|vm\n"
                               "12_5|NODE_FAIL|0:0|vm\n"
                               "12_6|FAILED|2:0|vm\n"
                               "12_6.batch|FAILED|2:0|vm\n"
                               "120_7|FAILED|1:0|vm\n"
                               "torn line\n";
    const auto tasks = farm::parseSacctTasks(output, "12");
    ASSERT_EQ(tasks.size(), 5u) << "the pending range, the step, the other job (120) and the torn line are skipped";
    EXPECT_EQ(tasks.at(0).state, "COMPLETED");
    EXPECT_TRUE(tasks.at(0).finished());
    EXPECT_EQ(tasks.at(0).exitCode, 0);
    const farm::SlurmTaskState& cancelled = tasks.at(1);
    EXPECT_EQ(cancelled.state, "CANCELLED") << "\"CANCELLED by 0\" is reduced to its first word";
    EXPECT_EQ(cancelled.exitCode, 0);
    EXPECT_EQ(cancelled.signal, 15);
    EXPECT_EQ(cancelled.node, "localhost");
    EXPECT_TRUE(cancelled.finished());
    EXPECT_EQ(cancelled.describe(), "CANCELLED (exit 0, signal 15) on localhost");
    EXPECT_EQ(tasks.at(4).describe(), "TIMEOUT (exit 0) on vm");
    EXPECT_EQ(tasks.at(5).state, "NODE_FAIL");
    EXPECT_EQ(tasks.at(6).exitCode, 2);
    EXPECT_FALSE(tasks.count(2) || tasks.count(3) || tasks.count(7));
    EXPECT_TRUE(farm::parseSacctTasks("", "12").empty());
    EXPECT_TRUE(farm::parseSacctTasks(output, "1").empty()) << "job 1 is not a prefix match of 12";
}

TEST(FarmSlurm, ScontrolLinesGiveEachEndedArrayTask) {
    const std::string output =
        "JobId=13 ArrayJobId=12 ArrayTaskId=1 JobName=chcrt-test UserId=root(0) GroupId=root(0) MCS_label=N/A "
        "Priority=4294901758 Nice=0 Account=(null) QOS=(null) JobState=CANCELLED Reason=None Dependency=(null) "
        "Requeue=1 Restarts=0 BatchFlag=1 Reboot=0 ExitCode=0:15 RunTime=00:00:04 TimeLimit=UNLIMITED "
        "TimeMin=N/A SubmitTime=2026-12-03T12:30:00 EligibleTime=2026-12-03T12:30:00 Partition=local "
        "ReqNodeList=(null) ExcNodeList=(null) NodeList=vm BatchHost=vm NumNodes=1 NumCPUs=1 "
        "Command=/tmp/a b/job-0.sbatch WorkDir=/tmp/a b StdOut=/tmp/a b/logs/12_1.out Power=\n"
        "JobId=14 ArrayJobId=12 ArrayTaskId=0 JobName=chcrt-test JobState=COMPLETED Reason=None ExitCode=0:0 "
        "ReqNodeList=(null) ExcNodeList=(null) NodeList=vm BatchHost=vm\n"
        "JobId=12 ArrayJobId=12 ArrayTaskId=2-3 JobName=chcrt-test JobState=PENDING Reason=Resources "
        "ExitCode=0:0 ReqNodeList=(null) ExcNodeList=(null) NodeList=(null)\n"
        "JobId=15 ArrayJobId=12 ArrayTaskId=4 JobState=FAILED Reason=NonZeroExitCode ExitCode=2:0 NodeList=vm\n"
        "JobId=21 ArrayJobId=20 ArrayTaskId=0 JobState=FAILED ExitCode=1:0 NodeList=vm\n";
    const auto tasks = farm::parseScontrolTasks(output, "12");
    ASSERT_EQ(tasks.size(), 3u) << "the pending range and the other job are skipped";
    EXPECT_EQ(tasks.at(1).state, "CANCELLED");
    EXPECT_EQ(tasks.at(1).signal, 15);
    EXPECT_EQ(tasks.at(1).node, "vm") << "NodeList, not ReqNodeList";
    EXPECT_EQ(tasks.at(1).describe(), "CANCELLED (exit 0, signal 15) on vm");
    EXPECT_EQ(tasks.at(0).state, "COMPLETED");
    EXPECT_EQ(tasks.at(4).describe(), "FAILED (exit 2) on vm");
    EXPECT_TRUE(farm::parseScontrolTasks("slurm_load_jobs error: Invalid job id specified\n", "12").empty());
}

TEST(FarmSlurm, OnlyStatesATaskDoesNotLeaveCountAsFinished) {
    for (const char* active : {"PENDING", "RUNNING", "SUSPENDED", "COMPLETING", "CONFIGURING", "REQUEUED"}) {
        EXPECT_FALSE(farm::SlurmTaskState{active}.finished()) << active;
    }
    for (const char* ended : {"COMPLETED", "CANCELLED", "FAILED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY",
                              "PREEMPTED", "BOOT_FAIL", "DEADLINE"}) {
        EXPECT_TRUE(farm::SlurmTaskState{ended}.finished()) << ended;
    }
    EXPECT_FALSE(farm::SlurmTaskState{}.finished()) << "no state: nothing is known";
    farm::SlurmTaskState unassigned{"CANCELLED"};
    for (const char* none : {"None assigned", "None", "(null)", ""}) {
        unassigned.node = none;
        EXPECT_EQ(unassigned.describe(), "CANCELLED (exit 0)") << "no node for \"" << none << "\"";
    }
}

} // namespace
