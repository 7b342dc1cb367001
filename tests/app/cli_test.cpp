// The CLI as users and scripts see it: exit codes, one-line errors, no partial output files, and the JSON
// fields other tools rely on. Runs build/bin/chcrt (path injected by CMake) in a temporary directory.
#include "renderer/core/image_io.h"
#include "tests/app/cli_fixture.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace chcrt::clitest;

TEST_F(CliTest, HelpAndVersionSucceed) {
    const Result top = run("--help");
    EXPECT_EQ(top.exitCode, 0);
    for (const char* command : {"demo", "render", "bench", "verify", "info"}) {
        EXPECT_NE(top.output.find(command), std::string::npos) << command;
    }
    for (const char* args : {"render --help", "bench --help", "verify --help", "info --help", "demo --help"}) {
        const Result r = run(args);
        EXPECT_EQ(r.exitCode, 0) << args << "\n" << r.output;
        EXPECT_NE(r.output.find("--scene"), std::string::npos) << args;
    }
    EXPECT_EQ(run("--version").exitCode, 0);
}

TEST_F(CliTest, BadFlagsAreUsageErrors) {
    EXPECT_EQ(run("").exitCode, 2);
    EXPECT_EQ(run("explode").exitCode, 2);
    EXPECT_EQ(run("render --no-such-flag -o x.png").exitCode, 2);
    EXPECT_EQ(run("render --width abc -o x.png").exitCode, 2);
    const Result zero = run(std::string("render --scene one-triangle --width 0 -o x.png -q"));
    EXPECT_EQ(zero.exitCode, 2);
    EXPECT_NE(zero.output.find("image size"), std::string::npos) << zero.output;
    EXPECT_EQ(run("render --scene one-triangle --effects shadow,sparkle -o x.png -q").exitCode, 2);
    EXPECT_EQ(run("verify --scene one-triangle --ray-type gloss -q").exitCode, 2);
    EXPECT_EQ(run("bench --scene one-triangle --method magic -q").exitCode, 2);
    EXPECT_EQ(run("render --scene city:abc -o x.png -q").exitCode, 2);
    EXPECT_EQ(run(std::string("render --scene one-triangle --frames 5 -o x.png ") + kSmall).exitCode, 2);
    EXPECT_EQ(run(std::string("render --scene one-triangle --frames 3-1 -o x.png ") + kSmall).exitCode, 2);
    EXPECT_EQ(run(std::string("render --scene one-triangle --frames all:x -o x.png ") + kSmall).exitCode, 2);
    EXPECT_EQ(run(std::string("render --scene one-triangle --frames spread:0 -o x.png ") + kSmall).exitCode, 2);
    EXPECT_EQ(run(std::string("render --scene one-triangle --uploads-per-trace -3 -o x.png ") + kSmall).exitCode, 2);
    const Result extent =
        run(std::string("render --scene one-triangle --method chcrt --chcrt-ray-extent maybe -o x.png ") + kSmall);
    EXPECT_EQ(extent.exitCode, 2);
    EXPECT_NE(extent.output.find("--chcrt-ray-extent must be on or off"), std::string::npos) << extent.output;
    const Result merged =
        run(std::string("render --scene one-triangle --method chcrt --chcrt-merged-batch 1 -o x.png ") + kSmall);
    EXPECT_EQ(merged.exitCode, 2);
    EXPECT_NE(merged.output.find("--chcrt-merged-batch must be on or off"), std::string::npos) << merged.output;
    EXPECT_EQ(fileCount(), 0u);
}

TEST_F(CliTest, BadInputFilesGiveOneLineErrorsAndNoOutput) {
    write("broken.gltf", "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ ");
    write("empty.obj", "# nothing here\n");
    write("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    write("path.json", "{\"version\": 1, \"keyframes\": [");
    write("truncated.glb", std::string("glTF\x02\x00\x00\x00\xff\x00\x00\x00", 12));
    const std::string cases[] = {"--scene missing.glb", "--scene broken.gltf", "--scene empty.obj",
                                 "--scene nan.obj", "--scene truncated.glb", "--scene city:10k --camera-path path.json",
                                 "--scene city:10k --camera-path nowhere.json"};
    for (const std::string& c : cases) {
        const Result r = run("render " + c + " -o out.png " + kSmall);
        EXPECT_EQ(r.exitCode, 2) << c << "\n" << r.output;
        EXPECT_NE(r.output.find("error"), std::string::npos) << c;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << c << ": " << r.output;
        EXPECT_FALSE(exists("out.png")) << c;
    }
    EXPECT_EQ(fileCount(), 5u); // only the inputs
}

TEST_F(CliTest, UnwritableOutputIsAnErrorWithoutPartialFiles) {
    const Result r = run(std::string("render --scene one-triangle -o no/such/dir/out.png ") + kSmall);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    const Result bad = run(std::string("render --scene one-triangle -o out.unknownext ") + kSmall);
    EXPECT_EQ(bad.exitCode, 2) << bad.output;
    EXPECT_EQ(fileCount(), 0u);
}

TEST_F(CliTest, RenderWritesFramesAndStatsJson) {
    const Result r = run(std::string("render --scene plane-and-box --frames 0 -o frame_####.png --stats-json s.json ") +
                         kSmall);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(exists("frame_0000.png"));
    const nlohmann::json j = readJson("s.json");
    EXPECT_EQ(j["width"], 48);
    ASSERT_EQ(j["frames"].size(), 1u);
    EXPECT_GT(j["frames"][0]["ms_total"].get<double>(), 0.0);
    EXPECT_EQ(j["frames"][0]["capped_rays"], 0);
    EXPECT_EQ(j["scene"]["triangles"], 14);
}

TEST_F(CliTest, RenderWritesTheChcrtCostDebugImage) {
    // CHC+RT's traversal steps per pixel (culling/README.md): a heat map over the city, not a black image.
    const std::string city = "render --scene city:10k -o out.png ";
    const Result r = run(city + "--method chcrt --debug-image cost " + kSmall);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const chcrt::ImageRgba32f image = chcrt::readImage(dir_ / "out.png");
    size_t lit = 0;
    for (size_t i = 0; i < image.pixels.size(); ++i) lit += i % 4 != 3 && image.pixels[i] > 0.0f;
    EXPECT_GT(lit, image.pixels.size() / 8) << "mostly black";
    // Only CHC+RT methods have debug images; unknown kinds list the available ones.
    EXPECT_EQ(run(city + "--method bvh --debug-image cost " + kSmall).exitCode, 2);
    const Result bad = run(city + "--method chcrt --debug-image costs " + kSmall);
    EXPECT_EQ(bad.exitCode, 2);
    EXPECT_NE(bad.output.find("batches, cost"), std::string::npos) << bad.output;
}

TEST_F(CliTest, FramesAllWithAStepRendersEveryNthFrame) {
    const Result r = run(std::string("render --scene city:10k --frames all:300 -o f_####.png ") + kSmall);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(exists("f_0000.png"));
    EXPECT_TRUE(exists("f_0300.png")); // near paths last 10-20 s at 30 fps
    EXPECT_FALSE(exists("f_0001.png"));
    EXPECT_FALSE(exists("f_0299.png"));
}

TEST_F(CliTest, VerifyPassesOnACityForAllRayTypes) {
    const Result r = run("verify --scene city:20k --ray-type primary,shadow,ao,diffuse --frames 0,40 --width 64 "
                         "--height 48 -q --stats-json v.json");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("PASS"), std::string::npos) << r.output;
    EXPECT_EQ(readJson("v.json")["differing"], 0);
}

TEST_F(CliTest, BenchWritesTheDocumentedJsonSchema) {
    const Result r = run("bench --scene city:20k --ray-type primary,ao --method bvh,embree --frames 0 --runs 2 "
                         "--warmup 1 --width 48 --height 32 -q --json b.json --csv b.csv");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const nlohmann::json j = readJson("b.json");
    // The header line names the machine the JSON records.
    const std::string machine = " on " + j["machine"]["cpu"].get<std::string>() + ", " +
                                std::to_string(j["machine"]["cores"].get<unsigned>()) + " cores\n";
    EXPECT_NE(r.output.find(machine), std::string::npos) << r.output;
    ASSERT_EQ(j["rows"].size(), 4u);
    for (const auto& row : j["rows"]) {
        for (const char* field : {"scene", "path", "ray_type", "method", "width", "height", "spp", "ms_median",
                                  "mrays_per_s", "speedup_vs_bvh", "diff_pixels", "psnr_db"}) {
            EXPECT_TRUE(row.contains(field)) << field;
        }
        EXPECT_EQ(row["diff_pixels"], 0);
        // The derived columns follow from the measured ones: the median of the runs' times, active rays per frame
        // over it, the median of the runs' ratios of the bvh row's time to this row's (each run's methods traced the
        // same passes one after the other), and the bvh row's median over this row's.
        const std::vector<double> runs = row["ms_runs"].get<std::vector<double>>();
        ASSERT_EQ(runs.size(), 2u);
        const double ms = row["ms_median"].get<double>();
        EXPECT_DOUBLE_EQ(ms, 0.5 * (runs[0] + runs[1]));
        ASSERT_GT(ms, 0.0);
        const double activeRays = row["active_rays_per_frame"].get<double>();
        EXPECT_GT(activeRays, 0.0);
        EXPECT_LE(activeRays, 48.0 * 32.0);
        EXPECT_DOUBLE_EQ(row["mrays_per_s"].get<double>(), activeRays / (ms * 1000.0));
        const nlohmann::json& bvhRow = j["rows"][row["ray_type"] == "primary" ? 0 : 2];
        ASSERT_EQ(bvhRow["method"], "bvh");
        EXPECT_EQ(row["active_rays_per_frame"], bvhRow["active_rays_per_frame"]); // the same rays for every method
        const std::vector<double> bvhRuns = bvhRow["ms_runs"].get<std::vector<double>>();
        ASSERT_EQ(bvhRuns.size(), 2u);
        EXPECT_DOUBLE_EQ(row["speedup_vs_bvh"].get<double>(), 0.5 * (bvhRuns[0] / runs[0] + bvhRuns[1] / runs[1]));
        EXPECT_DOUBLE_EQ(row["speedup_of_medians"].get<double>(), bvhRow["ms_median"].get<double>() / ms);
    }
    EXPECT_EQ(j["rows"][0]["active_rays_per_frame"], 48 * 32); // every primary ray is active
    EXPECT_DOUBLE_EQ(j["rows"][0]["speedup_vs_bvh"].get<double>(), 1.0);
    EXPECT_TRUE(exists("b.csv"));
}

// --steps counts work next to time. With the whole BVH as one termination subtree and the query testing the
// subtree root's own box, CHC+RT traverses exactly what pure BVH does per ray (tests/culling/
// chcrt_cost_image_test.cpp), so the two counts must agree; with more subtrees they may not, nor with hit hints
// (shadow rays that hit their hinted leaf skip the traversal).
TEST_F(CliTest, BenchStepsOfOneSubtreeChcrtEqualPureBvhSteps) {
    const std::string common = "bench --scene city:30k --ray-type primary,shadow --method bvh,chcrt-noadapt --frames 0,2 "
                               "--runs 1 --warmup 0 --width 64 --height 48 --chcrt-height 64 --chcrt-tighter-bounds off "
                               "--chcrt-min-tile 16 --chcrt-hints off --chcrt-pass-timer-interval 1 -q ";
    const Result r = run(common + "--steps --json s.json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("steps/ray"), std::string::npos);
    const nlohmann::json j = readJson("s.json");
    ASSERT_EQ(j["rows"].size(), 4u);
    for (size_t i = 0; i < 4; i += 2) {
        const nlohmann::json& pure = j["rows"][i];
        const nlohmann::json& culled = j["rows"][i + 1];
        ASSERT_EQ(pure["method"], "bvh");
        ASSERT_EQ(culled["method"], "chcrt-noadapt");
        EXPECT_GT(pure["steps_per_ray"].get<double>(), 1.0) << pure["ray_type"];
        EXPECT_EQ(pure["steps_per_ray"].get<double>(), culled["steps_per_ray"].get<double>()) << pure["ray_type"];
        // Step costs: pure BVH's trace time per step, CHC+RT's subtree passes (GPU timer) per step, which cannot
        // take longer than its whole traces.
        const double pureMsPerStep = pure["ms_per_step"].get<double>();
        const double traces = culled["frames"].get<double>() * culled["runs"].get<double>(); // frames of all runs
        const double steps = culled["steps_per_ray"].get<double>() * culled["active_rays_per_frame"].get<double>();
        EXPECT_NEAR(pureMsPerStep * pure["steps_per_ray"].get<double>() * pure["active_rays_per_frame"].get<double>(),
                    pure["ms_median"].get<double>(), 1e-6 * pure["ms_median"].get<double>());
        const double subtreeMs = culled["chcrt"]["sum"]["subtree_pass_ms"].get<double>();
        EXPECT_GT(subtreeMs, 0.0);
        // Hints off: no hint pass, so none of the subtree passes' time is the hint pass's.
        EXPECT_EQ(culled["chcrt"]["sum"]["hint_pass_ms"].get<double>(), 0.0);
        EXPECT_LE(subtreeMs, culled["chcrt"]["sum"]["phase1_ms"].get<double>() + culled["chcrt"]["sum"]["phase2_ms"].get<double>() +
                                 culled["chcrt"]["sum"]["phase3_ms"].get<double>() + 1.0);
        EXPECT_NEAR(culled["subtree_ms_per_step"].get<double>() * steps, subtreeMs / traces, 1e-6 * subtreeMs);
        EXPECT_NEAR(culled["step_cost_vs_bvh"].get<double>(), culled["subtree_ms_per_step"].get<double>() / pureMsPerStep,
                    1e-9);
        EXPECT_TRUE(pure["subtree_ms_per_step"].is_null());
    }
    const Result plain = run(common + "--json p.json");
    ASSERT_EQ(plain.exitCode, 0) << plain.output;
    EXPECT_EQ(plain.output.find("steps/ray"), std::string::npos);
    EXPECT_TRUE(readJson("p.json")["rows"][0]["steps_per_ray"].is_null());
}

// The viewer is a program of its own (build/bin/chcrt-view, which `chcrt view` runs): the CLI links no GLFW and no
// Dear ImGui, and no OSMesa (opened with dlopen for --gl osmesa). (libX11 still comes in through OpenImageIO's
// dependencies on Debian; a build with CHCRT_WITH_OIIO=OFF has neither, docs/gpu.md.)
TEST_F(CliTest, TheCliLinksNoWindowSystemAndListsItsMethods) {
    FILE* pipe = ::popen("ldd '" CHCRT_BINARY "' 2>&1", "r");
    ASSERT_NE(pipe, nullptr);
    std::string libraries;
    std::array<char, 4096> buffer;
    while (size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) libraries.append(buffer.data(), n);
    ::pclose(pipe);
    ASSERT_NE(libraries.find("libEGL"), std::string::npos) << libraries;
    EXPECT_EQ(libraries.find("libglfw"), std::string::npos) << libraries;
    EXPECT_EQ(libraries.find("imgui"), std::string::npos) << libraries;
    EXPECT_EQ(libraries.find("libOSMesa"), std::string::npos) << libraries;
    const Result methods = run("methods --markdown");
    ASSERT_EQ(methods.exitCode, 0) << methods.output;
    for (const char* row : {"| bvh | pure BVH", "| bvh+ls | BVH + Line Space", "| reference (CPU) |", "| approximate |"}) {
        EXPECT_NE(methods.output.find(row), std::string::npos) << row << "\n" << methods.output;
    }
    const Result view = run("view --help");
    EXPECT_EQ(view.exitCode, 0) << view.output;
    EXPECT_NE(view.output.find("--view-mode"), std::string::npos) << view.output;
    EXPECT_EQ(run("view --no-such-flag").exitCode, 2);
}

TEST_F(CliTest, InfoReportsGlAndScene) {
    const Result r = run("info --scene interior:20k -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("  version      4."), std::string::npos) << r.output; // 4.5 or later
    EXPECT_NE(r.output.find("triangles"), std::string::npos);
    void* osMesaLibrary = dlopen("libOSMesa.so.8", RTLD_LAZY | RTLD_LOCAL);
    if (osMesaLibrary != nullptr) { // the OSMesa backend's runtime; absent next to a GPU driver alone
        dlclose(osMesaLibrary);
        const Result osmesa = run("info --no-scene --gl osmesa -q");
        EXPECT_EQ(osmesa.exitCode, 0) << osmesa.output;
    }
    EXPECT_EQ(run("info --no-scene --gl vulkan -q").exitCode, 2);
}

// OSMesa is loaded only when --gl osmesa asks for it: without the library that flag fails with one line naming it
// (exit 3, a context that cannot be made), and EGL is unaffected.
TEST_F(CliTest, AMissingOsMesaLibraryFailsOnlyGlOsMesaWithOneLine) {
    const std::string missing = "CHCRT_OSMESA_LIBRARY=" + (dir_ / "no" / "libOSMesa.so.8").string();
    const Result osmesa = run("info --no-scene --gl osmesa -q", missing);
    EXPECT_EQ(osmesa.exitCode, 3) << osmesa.output;
    EXPECT_NE(osmesa.output.find("--gl osmesa: cannot load OSMesa"), std::string::npos) << osmesa.output;
    EXPECT_NE(osmesa.output.find("libosmesa6"), std::string::npos) << osmesa.output;
    EXPECT_EQ(std::count(osmesa.output.begin(), osmesa.output.end(), '\n'), 1) << osmesa.output;
    const Result egl = run("info --no-scene -q", missing);
    EXPECT_EQ(egl.exitCode, 0) << egl.output;
}

} // namespace

namespace {

using namespace chcrt::clitest;

// Every file a command writes is named in its output, caches included (a Line Space cache is megabytes that must
// not land in a folder silently, even under -q); a cache that was only read is not announced under -q.
TEST_F(CliTest, CommandsNameTheFilesTheyWrite) {
    const std::string bench = "bench --scene city:10k --width 32 --height 24 --ray-type ao --frames 0 -q ";
    const Result tables = run(bench + "--method bvh --json b.json --markdown b.md");
    ASSERT_EQ(tables.exitCode, 0) << tables.output;
    EXPECT_NE(tables.output.find("wrote b.json, b.md"), std::string::npos) << tables.output;
    const Result built = run(bench + "--method bvh+ls --ls-cache lscache");
    ASSERT_EQ(built.exitCode, 0) << built.output;
    EXPECT_NE(built.output.find("bvh+ls: Line Spaces built, stored in lscache/"), std::string::npos) << built.output;
    const Result loaded = run(bench + "--method bvh+ls --ls-cache lscache");
    ASSERT_EQ(loaded.exitCode, 0) << loaded.output;
    EXPECT_EQ(loaded.output.find("Line Spaces"), std::string::npos) << loaded.output;
    const Result render = run("render --scene city:10k --width 32 --height 24 -q -o f.png --stats-json s.json");
    EXPECT_NE(render.output.find("statistics in s.json"), std::string::npos) << render.output;
}

} // namespace

namespace {

using namespace chcrt::clitest;

// An out-of-core render says what it traced: the file's triangle count (not the in-core stand-in's one triangle),
// the cache, and frames that the per-trace upload limit left incomplete.
TEST_F(CliTest, OutOfCoreRenderSummaryNamesTheCacheAndIncompleteFrames) {
    ASSERT_EQ(run("prepare --scene city:200k --subtree-triangles 4000 -o c.chs -q").exitCode, 0);
    const std::string render = "render --scene c.chs --out-of-core --load-in-core off --method chcrt --width 48 "
                               "--height 32 --spp 1 --effects shadow -o o.png --gpu-cache-mb 64 ";
    const Result complete = run(render);
    ASSERT_EQ(complete.exitCode, 0) << complete.output;
    EXPECT_NE(complete.output.find("triangles in the prepared file, not loaded in core"), std::string::npos)
        << complete.output;
    EXPECT_EQ(complete.output.find(" 1 triangles"), std::string::npos) << complete.output;
    EXPECT_NE(complete.output.find("out of core: GPU cache 64 MB (lru)"), std::string::npos) << complete.output;
    EXPECT_EQ(complete.output.find("incomplete"), std::string::npos) << complete.output;
    const Result limited = run(render + "--uploads-per-trace 1");
    ASSERT_EQ(limited.exitCode, 0) << limited.output;
    EXPECT_NE(limited.output.find("warning: 1 frame(s) incomplete (0)"), std::string::npos) << limited.output;
    // bench marks its out-of-core rows (the in-core bvh reference beside them is not).
    const Result bench = run("bench --scene c.chs --out-of-core --method bvh,chcrt --ray-type shadow --width 32 "
                             "--height 24 --frames 0 -q --json b.json");
    ASSERT_EQ(bench.exitCode, 0) << bench.output;
    EXPECT_NE(bench.output.find("chcrt (out of core)"), std::string::npos) << bench.output;
    const nlohmann::json rows = readJson("b.json")["rows"];
    ASSERT_EQ(rows.size(), 2u);
    for (const nlohmann::json& row : rows) EXPECT_EQ(row["out_of_core"], row["method"] == "chcrt") << row.dump();
}

} // namespace

namespace {

using namespace chcrt::clitest;

// The bench table labels what each error column measures: per-ray-type differing pixels beside a whole-frame PSNR.
TEST_F(CliTest, BenchTableSaysWhatItsErrorColumnsMeasure) {
    const Result r = run("bench --scene city:10k --width 32 --height 24 --frames 0 --method bvh+ls --ray-type ao -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("frame PSNR dB"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("frame PSNR: the whole shaded frame (all --effects)"), std::string::npos) << r.output;
    const Result exact = run("bench --scene city:10k --width 32 --height 24 --frames 0 --method bvh --ray-type ao -q");
    EXPECT_EQ(exact.output.find("frame PSNR:"), std::string::npos) << "no footnote without image errors\n" << exact.output;
}

} // namespace

namespace {

using namespace chcrt::clitest;

// A scene file that stores a camera is seen through it by default (its author framed it); one without falls back
// to the camera framing the bounds.
TEST_F(CliTest, AStoredGltfCameraIsTheDefaultView) {
    write("tri.gltf", R"({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.3, 0.3, 3]}], "scenes": [{"nodes": [0, 1]}], "scene": 0})");
    const Result withCamera = run("info --scene tri.gltf");
    ASSERT_EQ(withCamera.exitCode, 0) << withCamera.output;
    EXPECT_NE(withCamera.output.find("Camera path gltf-camera-0"), std::string::npos) << withCamera.output;
    write("plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_NE(run("info --scene plain.obj").output.find("Camera path default-camera"), std::string::npos);
}

} // namespace

namespace {

using namespace chcrt::clitest;

// Two processes building the same Line Space cache at once (two farm tasks) leave one whole file: each writes a
// temporary file of its own and renames it into place, so the next run loads it instead of rebuilding.
TEST_F(CliTest, TwoProcessesBuildingTheSameCacheLeaveAValidFile) {
    const std::string bench = "'" CHCRT_BINARY "' bench --scene city:20k --width 32 --height 24 --frames 0 --method "
                              "bvh+ls --ray-type diffuse --ls-cache lscache -q";
    const std::string both = "cd '" + dir_.string() + "' && (" + bench + " > a.log 2>&1 & a=$!; " + bench +
                             " > b.log 2>&1 & b=$!; wait $a && wait $b)";
    ASSERT_EQ(std::system(both.c_str()), 0) << readFile("a.log") << readFile("b.log");
    size_t files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(dir_ / "lscache")) {
        if (!entry.is_regular_file()) continue;
        ++files;
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "a temporary file was left: " << entry.path();
    }
    EXPECT_EQ(files, 1u);
    const Result third = run("bench --scene city:20k --width 32 --height 24 --frames 0 --method bvh+ls --ray-type "
                             "diffuse --ls-cache lscache");
    ASSERT_EQ(third.exitCode, 0) << third.output;
    EXPECT_NE(third.output.find("Line Spaces loaded from cache"), std::string::npos) << third.output;
}

} // namespace
