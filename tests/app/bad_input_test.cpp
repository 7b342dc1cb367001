// Bad input found by trying the CLI as a new user would (issue list of docs/cli.md's exit codes): each is a
// one-line error with exit 2 before any work is done, or a named warning, and leaves no output behind.
#include "tests/app/cli_fixture.h"

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <functional>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace {

using namespace chcrt::clitest;

// Inverts the byte in the middle of a file: for a prepared scene, inside a subtree's checksummed data.
void flipByteInTheMiddle(const fs::path& file) {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(0, std::ios::end);
    const std::streamoff middle = f.tellg() / 2;
    f.seekg(middle);
    const char byte = char(f.get() ^ 0xff);
    f.seekp(middle);
    f.put(byte);
}

constexpr const char* kCity = "--scene city:10k --width 32 --height 24 -q ";

// exit 2, the message contains `expected`, and the command did no work (no summary, no files).
void expectRefused(const Result& r, const std::string& expected) {
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("render:"), std::string::npos) << "rendered before refusing:\n" << r.output;
    EXPECT_EQ(r.output.find("bench:"), std::string::npos) << "benchmarked before refusing:\n" << r.output;
}

TEST_F(CliTest, NegativeCountsCannotSwitchVerifyOff) {
    for (const char* flag : {"--max-diff -1", "--show-diff -1"}) {
        const Result r = run(std::string("verify ") + kCity + flag);
        expectRefused(r, "must not be negative");
        EXPECT_EQ(r.output.find("0000000"), std::string::npos) << "no 300-digit range:\n" << r.output;
    }
}

TEST_F(CliTest, EmptyFramesAndDuplicateListItemsAreErrors) {
    expectRefused(run(std::string("render ") + kCity + "--frames '' -o a.png"), "--frames is empty");
    expectRefused(run(std::string("bench ") + kCity + "--method bvh,chcrt,bvh --ray-type shadow"),
                  "'bvh' is listed twice");
    expectRefused(run(std::string("bench ") + kCity + "--method bvh --ray-type ao,ao"), "'ao' is listed twice");
    EXPECT_EQ(fileCount(), 0u);
}

TEST_F(CliTest, OutOfCoreFlagsWithoutOutOfCoreAreNamedAsIneffective) {
    const Result r = run(std::string("render ") + kCity + "--gpu-cache-mb 100 --cache-policy lru -o a.png");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("warning: --gpu-cache-mb has no effect without --out-of-core"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("warning: --cache-policy has no effect without --out-of-core"), std::string::npos) << r.output;
    const Result quiet = run(std::string("render ") + kCity + "-o b.png");
    EXPECT_EQ(withoutSoftwareRendererWarning(quiet.output).find("warning"), std::string::npos) << quiet.output;
}

// Cell intersection is a choice of batched queries only: asked for with another query mode it is refused, not ignored.
TEST_F(CliTest, CellIntersectionOutsideBatchedQueriesIsRefused) {
    expectRefused(run(std::string("render ") + kCity + "--method chcrt-noadapt --chcrt-cell-intersect on -o a.png -q"),
                  "--chcrt-cell-intersect on applies to --chcrt-queries batched, not bounds-only");
    EXPECT_FALSE(exists("a.png"));
    const Result batched = run(std::string("render ") + kCity +
                               "--method chcrt-noadapt --chcrt-queries batched --chcrt-cell-intersect on -o b.png -q");
    EXPECT_EQ(batched.exitCode, 0) << batched.output;
}

TEST_F(CliTest, ScenesThatAreNeitherFilesNorGeneratorsSaySo) {
    const Result town = run("render --scene town:10k -o a.png -q");
    expectRefused(town, "town:10k: neither a scene file (no such file) nor a generator (city, interior");
    fs::create_directories(dir_ / "scenes");
    expectRefused(run("render --scene scenes -o a.png -q"), "scenes: is a directory, not a scene file");
    EXPECT_FALSE(exists("a.png"));
}

TEST_F(CliTest, MistypedCommandsSuggestTheNearest) {
    expectRefused(run("rendr"), "unknown command 'rendr' of chcrt (did you mean 'render'?)");
    expectRefused(run("farm sumbit --frames 0"), "unknown command 'sumbit' of chcrt farm (did you mean 'submit'?)");
    const Result far = run("explode");
    EXPECT_EQ(far.exitCode, 2);
    EXPECT_EQ(far.output.find("did you mean"), std::string::npos) << "no suggestion more than two edits away:\n" << far.output;
    EXPECT_NE(far.output.find("commands: demo, render"), std::string::npos) << far.output;
}

TEST_F(CliTest, EveryOutputPathIsCheckedBeforeTheWork) {
    write("file", "a file, not a directory");
    expectRefused(run(std::string("render ") + kCity + "-o file/a.png"), "\"file\" is a file, not a directory");
    expectRefused(run(std::string("render ") + kCity + "-o a.png --stats-json missing/s.json"),
                  "missing/s.json: directory \"missing\" does not exist");
    expectRefused(run(std::string("render ") + kCity + "-o a.png --records missing/r.jsonl"),
                  "directory \"missing\" does not exist");
    expectRefused(run(std::string("render ") + kCity + "-o a.xyz"), "unsupported image extension");
    expectRefused(run(std::string("bench ") + kCity + "--method bvh --ray-type shadow --csv missing/t.csv"),
                  "missing/t.csv");
    expectRefused(run(std::string("verify ") + kCity + "--stats-json file/v.json"), "is a file, not a directory");
    expectRefused(run("prepare --scene city:10k -q -o missing/c.chs"), "directory \"missing\" does not exist");
    EXPECT_FALSE(exists("a.png"));
    EXPECT_EQ(fileCount(), 1u); // only "file"
}

TEST_F(CliTest, AWalkthroughTooLongForItsFrameListIsRefused) {
    write("long.json", R"({"version": 1, "fps": 1e9, "keyframes": [{"t": 0, "eye": [0, 1, 0], "target": [0, 1, -1]},
                         {"t": 1e9, "eye": [0, 1, 5], "target": [0, 1, -1]}]})");
    const Result r = run(std::string("render ") + kCity + "--camera-path long.json --frames all -o a.png");
    expectRefused(r, "more than the 10000000 a walkthrough may have");
    EXPECT_FALSE(exists("a.png"));
}

// Sizes a run could not allocate are refused before the work that would allocate them (docs/robustness.md, "Sizes
// from untrusted input"): an image side beyond what a texture may have, and estimates beyond --max-memory-mb.
TEST_F(CliTest, SizesThatCannotBeAllocatedAreRefusedBeforeTheWork) {
    expectRefused(run("render --scene city:10k --width 100000 --height 100000 -q -o a.png"),
                  "image size must be between 1 and 16384 pixels per side");
    // Render targets and a generator's scene are estimated before anything is generated.
    const Result targets = run("render --scene city:10k --width 16384 --height 16384 --max-memory-mb 1024 -q -o a.png");
    expectRefused(targets, "this run needs at least ");
    EXPECT_NE(targets.output.find("render targets 16384x16384: "), std::string::npos) << targets.output;
    EXPECT_NE(targets.output.find("more than the 1,024 MiB --max-memory-mb allows"), std::string::npos) << targets.output;
    expectRefused(run("render --scene city:10m --width 32 --height 24 -q --max-memory-mb 1000 -o a.png"),
                  "scene and BVH of 11000000 triangles: ");
    // A scene file once it is loaded, before its BVH is built: 3000 triangles at 400 bytes each exceed 1 MiB.
    std::string obj;
    for (int i = 0; i < 3000; ++i) {
        obj += "v " + std::to_string(i) + " 0 0\nv " + std::to_string(i) + " 1 0\nv " + std::to_string(i) + " 0 1\n";
        obj += "f " + std::to_string(3 * i + 1) + " " + std::to_string(3 * i + 2) + " " + std::to_string(3 * i + 3) + "\n";
    }
    write("many.obj", obj);
    expectRefused(run("render --scene many.obj --width 32 --height 24 -q --max-memory-mb 1 -o a.png"),
                  "scene and BVH of 3000 triangles: ");
    // Line Spaces: the cut's nodes times N^4 bits, on the host and on the GPU.
    const Result spaces = run(std::string("render ") + kCity +
                              "--method bvh+ls-exact --ls-n 16 --ls-depth 12 --ls-cache '' --max-memory-mb 64 -o a.png");
    expectRefused(spaces, "Line Spaces (N=16 D=12 T=8");
    EXPECT_NE(spaces.output.find("--max-memory-mb allows"), std::string::npos) << spaces.output;
    expectRefused(run(std::string("render ") + kCity + "--max-memory-mb 0 -o a.png"), "--max-memory-mb must be at least 1");
    EXPECT_FALSE(exists("a.png"));
    EXPECT_EQ(fileCount(), 1u); // many.obj
    // Within the budget the same flags render.
    EXPECT_EQ(run(std::string("render ") + kCity + "--max-memory-mb 64 -o a.png").exitCode, 0);
}

} // namespace

// An interrupted prepare leaves no F.chs.tmp: the signal skips the writer's destructor, RemoveOnSignal's handler removes it.
TEST_F(CliTest, AnInterruptedPrepareLeavesNoTemporaryFile) {
    const std::string command = "cd '" + dir_.string() + "' && ('" CHCRT_BINARY "' prepare --scene city:3m -o big.chs -q & "
                                "pid=$!; for i in $(seq 600); do [ -e big.chs.tmp ] && break; sleep 0.05; done; "
                                "[ -e big.chs.tmp ] || exit 90; kill -TERM $pid; wait $pid; exit $?)";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_NE(WEXITSTATUS(status), 90) << "prepare never created its temporary file";
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << "ended by the signal, not by an exit of its own";
    EXPECT_FALSE(exists("big.chs.tmp"));
    EXPECT_FALSE(exists("big.chs"));
}

// Opening a .chs checks its header and metadata only; `info --check` reads every subtree, so a flipped byte in
// the middle of the file is found (exit 4, the subtree named) instead of "exit 0".
TEST_F(CliTest, InfoCheckFindsAFlippedByteInAPreparedScene) {
    ASSERT_EQ(run("prepare --scene city:50k --subtree-triangles 2000 -o s.chs -q").exitCode, 0);
    EXPECT_EQ(run("info --scene s.chs --check").exitCode, 0);
    flipByteInTheMiddle(dir_ / "s.chs");
    const Result r = run("info --scene s.chs --check");
    EXPECT_EQ(r.exitCode, 4) << r.output;
    EXPECT_NE(r.output.find("checksum mismatch"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1 failed"), std::string::npos) << r.output;
    expectRefused(run("info --scene city:10k --check"), "--check reads prepared scenes");
}

// Broken inputs are not rendered as if nothing were wrong: faces of fewer than 3 vertices and a file cut
// mid-line are named as warnings, and --strict refuses them.
TEST_F(CliTest, ObjFacesThatVanishAndTruncatedFilesAreWarnedAbout) {
    write("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4\nf 2 4 3");
    const std::string info = "info --scene t.obj";
    const Result r = run(info);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("warning: t.obj: 1 face(s) with fewer than 3 vertices skipped"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("warning: t.obj: the last line has no line end (is the file truncated?)"), std::string::npos)
        << r.output;
    const Result strict = run(info + " --strict");
    EXPECT_EQ(strict.exitCode, 2) << strict.output;
    EXPECT_NE(strict.output.find("(and 1 more warning(s)) [--strict]"), std::string::npos) << strict.output;
    write("clean.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Result clean = run("info --scene clean.obj --strict");
    EXPECT_EQ(clean.exitCode, 0) << clean.output;
    EXPECT_EQ(withoutSoftwareRendererWarning(clean.output).find("warning"), std::string::npos) << clean.output;
}

// A file whose content announces another format than its name is named as such, not parsed as garbage.
TEST_F(CliTest, AFileNamedAsAnotherFormatSaysWhatItIs) {
    write("mesh.obj", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nend_header\n");
    expectRefused(run("info --scene mesh.obj"), "mesh.obj: is a ply file by its content, not OBJ: rename it .ply");
    write("scene.ply", "glTF\x02");
    expectRefused(run("info --scene scene.ply"), "is a glb file by its content, not PLY");
}

// The viewer's flags are checked before a window is opened: a bad size is a usage error, not a failed window.
TEST_F(CliTest, ViewRefusesBadSizesBeforeOpeningAWindow) {
    expectRefused(run("view --width 0", "DISPLAY="), "image size must be between 1 and 16384");
    expectRefused(run("view --render-scale 9", "DISPLAY="), "--render-scale must be in [0.05, 2]");
}

// A full disk, simulated by a file size limit (ulimit -f, with SIGXFSZ ignored so that writes fail with EFBIG as
// on ENOSPC): every writer fails with exit 2 and leaves neither a short file nor its temporary file. A PNG used
// to be written short and renamed into place with success.
TEST_F(CliTest, AFullDiskFailsCleanlyWithoutShortFiles) {
    auto limited = [&](const std::string& arguments) {
        const std::string command = "cd '" + dir_.string() + "' && bash -c \"trap '' XFSZ; ulimit -f 1; '" CHCRT_BINARY
                                    "' " + arguments + "\" > out.log 2>&1";
        const int status = std::system(command.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    };
    EXPECT_EQ(limited("render --scene city:10k --width 256 --height 256 --spp 1 -q -o img.png"), 2) << readFile("out.log");
    EXPECT_NE(readFile("out.log").find("img.png: write failed: File too large"), std::string::npos) << readFile("out.log");
    EXPECT_EQ(limited("render --scene city:10k --width 256 --height 256 --spp 1 -q -o img.exr"), 2) << readFile("out.log");
    EXPECT_EQ(limited("prepare --scene city:200k -q -o big.chs"), 2) << readFile("out.log");
    EXPECT_EQ(limited("bench --scene city:10k --width 64 --height 64 --method bvh --ray-type ao --frames 0-4 -q "
                      "--json b.json"), 2) << readFile("out.log");
    fs::remove(dir_ / "out.log");
    EXPECT_EQ(fileCount(), 0u) << "short or temporary files left";
}

// A subtree that fails its checksum when an out-of-core render first reads it: the render stops with the file and
// subtree named, and the frame that needed it is not written.
TEST_F(CliTest, ACorruptSubtreeFailsTheOutOfCoreFrameThatReadsIt) {
    ASSERT_EQ(run("prepare --scene city:200k --subtree-triangles 4000 -o c.chs -q").exitCode, 0);
    flipByteInTheMiddle(dir_ / "c.chs");
    const Result r = run("render --scene c.chs --out-of-core --load-in-core off --method chcrt --width 64 --height 48 "
                         "--frames 0-2 -o f_####.png -q");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("c.chs: corrupted prepared scene (subtree "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("checksum mismatch)"), std::string::npos) << r.output;
    EXPECT_FALSE(exists("f_0000.png"));
}

namespace {

using namespace chcrt::clitest;

// Runs build/bin/chcrt with `arguments` in `dir`, stdout and stderr into out.log, with CHCRT_FAULT_STOP_AFTER_FRAME
// = `stopAfterFrame`: when the render stops itself there, `whileStopped` changes its files and the render goes on.
// Returns the exit code; `stopped` says whether the render reached the stop.
int runStoppingAfterFrame(const fs::path& dir, const std::vector<std::string>& arguments, int stopAfterFrame,
                          const std::function<void()>& whileStopped, bool& stopped) {
    stopped = false;
    const pid_t pid = ::fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        if (::chdir(dir.c_str()) != 0) ::_exit(126);
        const int log = ::open("out.log", O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(log, 1);
        ::dup2(log, 2);
        ::setenv("CHCRT_FAULT_STOP_AFTER_FRAME", std::to_string(stopAfterFrame).c_str(), 1);
        std::vector<char*> argv{const_cast<char*>(CHCRT_BINARY)};
        for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(CHCRT_BINARY, argv.data());
        ::_exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, WUNTRACED);
    if (WIFSTOPPED(status)) {
        stopped = true;
        whileStopped();
        ::kill(pid, SIGCONT);
        ::waitpid(pid, &status, 0);
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// An out-of-core walkthrough whose prepared scene changes under it: rendered through a GPU cache of 2 slots and a host
// store of 1 MB, so that every frame reads subtrees from the file again.
// Without prefetch: its background reads would make which read a frame does, and when, depend on timing (a subtree
// read ahead before the file changes, a prefetch read that meets the injected error and is dropped).
std::vector<std::string> outOfCoreWalk(const std::string& scene) {
    return {"render", "--scene", scene, "--out-of-core", "--load-in-core", "off", "--method", "chcrt", "--gpu-cache-mb",
            "1", "--host-cache-mb", "1", "--prefetch-frames", "0", "--width", "64", "--height", "48", "--frames", "0-3",
            "-o", "f_####.png", "-q"};
}

// A prepared scene truncated or overwritten in place by another process while a walkthrough renders it: the first
// frame that reads a subtree after the change fails, naming the frame, the file and the subtree, and is not written
// (nor are the frames after it); the frames before stay. Replaced by a rename (a new file under the same name), the
// render keeps reading the file it opened and finishes with the same images.
TEST_F(CliTest, APreparedSceneTruncatedOrOverwrittenWhileItRendersFailsTheFrameThatReadsIt) {
    ASSERT_EQ(run("prepare --scene city:200k --subtree-triangles 4000 -o c.chs -q").exitCode, 0);
    ASSERT_EQ(run("prepare --scene city:200k:seed=9 --subtree-triangles 4000 -o other.chs -q").exitCode, 0);
    const auto removeFrames = [&] {
        for (int f = 0; f < 4; ++f) fs::remove(dir_ / ("f_000" + std::to_string(f) + ".png"));
    };
    bool stopped = false;
    ASSERT_EQ(runStoppingAfterFrame(dir_, outOfCoreWalk("c.chs"), 99, [] {}, stopped), 0) << readFile("out.log");
    std::vector<std::string> reference;
    for (int f = 0; f < 4; ++f) reference.push_back(readFile("f_000" + std::to_string(f) + ".png"));
    removeFrames();

    struct Change {
        const char* name;
        std::function<void(const fs::path&)> apply;
        const char* message; // empty: the render finishes
    };
    const std::vector<Change> changes = {
        {"truncated", [](const fs::path& f) { fs::resize_file(f, 4096); }, "file is truncated"},
        {"overwritten", [](const fs::path& f) { // same size, zeros after the header: another file's bytes
             std::fstream out(f, std::ios::in | std::ios::out | std::ios::binary);
             const std::string zeros(fs::file_size(f) - 4096, '\0');
             out.seekp(4096);
             out.write(zeros.data(), std::streamsize(zeros.size()));
         }, "checksum mismatch"},
        {"replaced", [&](const fs::path& f) { fs::rename(dir_ / "other.chs", f); }, ""},
    };
    for (const Change& change : changes) {
        SCOPED_TRACE(change.name);
        fs::copy_file(dir_ / "c.chs", dir_ / "s.chs", fs::copy_options::overwrite_existing);
        const int code = runStoppingAfterFrame(dir_, outOfCoreWalk("s.chs"), 0, [&] { change.apply(dir_ / "s.chs"); },
                                               stopped);
        const std::string log = readFile("out.log");
        ASSERT_TRUE(stopped) << log;
        EXPECT_EQ(readFile("f_0000.png"), reference[0]) << "the frame before the change stays";
        if (*change.message == '\0') {
            EXPECT_EQ(code, 0) << log;
            for (int f = 1; f < 4; ++f) EXPECT_EQ(readFile("f_000" + std::to_string(f) + ".png"), reference[size_t(f)]);
        } else {
            EXPECT_EQ(code, 2) << log;
            EXPECT_NE(log.find("chcrt: error: frame 1 not rendered: s.chs: "), std::string::npos) << log;
            EXPECT_NE(log.find("subtree "), std::string::npos) << log;
            EXPECT_NE(log.find(change.message), std::string::npos) << log;
            for (int f = 1; f < 4; ++f) EXPECT_FALSE(exists("f_000" + std::to_string(f) + ".png")) << f;
        }
        removeFrames();
    }
}

// A read error of the disk, injected into the subtree reads (CHCRT_FAULT_CHS_EIO=FIRST-: every read from the
// FIRST-th on fails with EIO in pread): the frame that reads then fails naming file and subtree, and is not written.
TEST_F(CliTest, AnInjectedReadErrorFailsTheOutOfCoreFrameNamingFileAndSubtree) {
    ASSERT_EQ(run("prepare --scene city:200k --subtree-triangles 4000 -o c.chs -q").exitCode, 0);
    std::string walk;
    for (const std::string& word : outOfCoreWalk("c.chs")) walk += word + " ";
    const Result clean = run(walk + "--stats-json s.json");
    ASSERT_EQ(clean.exitCode, 0) << clean.output;
    // Reads of frames 0-2 (the warm-up frame before frame 0 reads too): the read numbered so fails in frame 1 or 2.
    uint64_t reads = 0;
    for (int f = 0; f < 3; ++f) reads += readJson("s.json")["frames"][f]["outofcore"]["host_reads"].get<uint64_t>();
    ASSERT_GT(reads, 0u);
    for (int f = 0; f < 4; ++f) fs::remove(dir_ / ("f_000" + std::to_string(f) + ".png"));

    const Result r = run(walk, "CHCRT_FAULT_CHS_EIO=" + std::to_string(reads) + "-");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    const size_t at = r.output.find("chcrt: error: frame ");
    ASSERT_NE(at, std::string::npos) << r.output;
    const int failed = std::atoi(r.output.c_str() + at + std::strlen("chcrt: error: frame "));
    EXPECT_GE(failed, 1) << r.output;
    EXPECT_NE(r.output.find(" not rendered: c.chs: reading subtree "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(": Input/output error"), std::string::npos) << r.output;
    for (int f = 0; f < 4; ++f) EXPECT_EQ(exists("f_000" + std::to_string(f) + ".png"), f < failed) << f;

    // From the first read on: the warm-up frame fails, nothing is written.
    for (int f = 0; f < 4; ++f) fs::remove(dir_ / ("f_000" + std::to_string(f) + ".png"));
    const Result first = run(walk, "CHCRT_FAULT_CHS_EIO=0-");
    EXPECT_EQ(first.exitCode, 2) << first.output;
    EXPECT_NE(first.output.find("c.chs: reading subtree "), std::string::npos) << first.output;
    EXPECT_FALSE(exists("f_0000.png"));
}

// A full disk, for real: a 1 MiB tmpfs mounted in a private mount namespace (unshare; skipped where user and mount
// namespaces are not allowed, AFullDiskFailsCleanlyWithoutShortFiles simulates it with a file size limit). prepare and
// a float image fail with ENOSPC, exit 2, and leave nothing on the disk.
TEST_F(CliTest, PrepareAndRenderOnAFullDiskLeaveNothingBehind) {
    fs::create_directories(dir_ / "disk");
    write("disk.sh", "mount -t tmpfs -o size=1m tmpfs disk || exit 97\ncd disk\n"
                     "'" CHCRT_BINARY "' prepare --scene city:200k -o c.chs -q; echo \"prepare exit $?\"\n"
                     "'" CHCRT_BINARY "' render --scene city:10k --width 1024 --height 1024 --spp 1 -q -o big.exr\n"
                     "echo \"render exit $?\"\necho left: $(ls -A)\n");
    const std::string command = "cd '" + dir_.string() + "' && unshare -rm sh disk.sh > out.log 2>&1";
    const int status = std::system(command.c_str());
    const std::string log = readFile("out.log");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        GTEST_SKIP() << "no private tmpfs here (unshare -rm and mount -t tmpfs): " << log;
    }
    EXPECT_NE(log.find("No space left on device"), std::string::npos) << log;
    EXPECT_NE(log.find("prepare exit 2"), std::string::npos) << log;
    EXPECT_NE(log.find("render exit 2"), std::string::npos) << log;
    EXPECT_NE(log.find("left:\n"), std::string::npos) << "files left on the full disk:\n" << log;
}

} // namespace
