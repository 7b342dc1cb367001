// What a GPU run relies on, through build/bin/chcrt: the EGL device list and the device flag (chcrt info --devices,
// --gl-device N|auto), the software-renderer warning and the GL fields of every JSON the tools write, and the
// compute stage of pure BVH tracing (--shader-stage), verified bit for bit against the fragment stage, and the stage
// and list decisions of CHC+RT's cell passes.
#include "tests/app/cli_fixture.h"

namespace chcrt::clitest {
namespace {

constexpr const char* kScene = "--scene city:10k --width 40 --height 28 --frames 0 -q ";
constexpr const char* kSoftwareWarning = "warning: OpenGL renders on the software renderer";

// The GL fields every JSON carries (app/report.h glJson); returns whether the renderer is software.
bool expectGlFields(const nlohmann::json& j, const std::string& what) {
    for (const char* key : {"gl_vendor", "gl_renderer", "gl_version"}) {
        EXPECT_TRUE(j.contains(key) && j[key].is_string() && !j[key].get<std::string>().empty()) << what << ": " << key;
    }
    EXPECT_TRUE(j.contains("software_renderer") && j["software_renderer"].is_boolean()) << what;
    return j.value("software_renderer", false);
}

TEST_F(CliTest, InfoDevicesListsTheEglDevicesAndWhatAutoPicks) {
    const Result r = run("info --devices --stats-json d.json -q");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("EGL devices: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--gl-device auto picks:"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("Scene "), std::string::npos) << "--devices reads no scene\n" << r.output;
    const nlohmann::json j = readJson("d.json");
    const bool software = expectGlFields(j, "info");
    EXPECT_EQ(r.output.find(kSoftwareWarning), std::string::npos) << "-q: errors only\n" << r.output;
    // Without -q a software renderer is said on stderr.
    const Result loud = run("info --no-scene");
    ASSERT_EQ(loud.exitCode, 0) << loud.output;
    EXPECT_EQ(loud.output.find(kSoftwareWarning) != std::string::npos, software) << loud.output;
    ASSERT_TRUE(j["devices"].is_array());
    for (size_t i = 0; i < j["devices"].size(); ++i) {
        const nlohmann::json& d = j["devices"][i];
        EXPECT_EQ(d["index"], i);
        EXPECT_TRUE(d["software"].is_boolean());
        EXPECT_NE(r.output.find("  device " + std::to_string(i) + "  "), std::string::npos) << r.output;
    }
}

TEST_F(CliTest, GlDeviceValuesAreCheckedAndADeviceOutsideTheListIsRefused) {
    const Result word = run("info --no-scene --gl-device gpu0 -q");
    EXPECT_EQ(word.exitCode, 2) << word.output;
    EXPECT_NE(word.output.find("--gl-device must be auto or an EGL device index"), std::string::npos) << word.output;
    const Result far = run("info --no-scene --gl-device 1000 -q");
    EXPECT_EQ(far.exitCode, 3) << far.output; // an OpenGL error: that device does not exist (or no device platform)
    EXPECT_EQ(run("info --no-scene --gl osmesa --gl-device 0 -q").exitCode, 2);
    EXPECT_EQ(run("info --no-scene --gl-device auto -q").exitCode, 0);
    const Result stage = run("info --no-scene --shader-stage vertex -q");
    EXPECT_EQ(stage.exitCode, 2) << stage.output;
    EXPECT_NE(stage.output.find("--shader-stage must be auto, fragment or compute"), std::string::npos) << stage.output;
}

TEST_F(CliTest, EveryJsonCarriesTheGlRendererAndSoftwareIsSaidLoudly) {
    const Result render = run(std::string("render ") + kScene + "-o a.png --stats-json r.json --shader-stage compute");
    ASSERT_EQ(render.exitCode, 0) << render.output;
    const nlohmann::json r = readJson("r.json");
    const bool software = expectGlFields(r, "render");
    EXPECT_EQ(r["shader_stage"], "compute");
    EXPECT_EQ(render.output.find(kSoftwareWarning), std::string::npos) << "-q: errors only\n" << render.output;

    const Result bench = run(std::string("bench ") + kScene + "--method bvh --ray-type ao --runs 1 --warmup 0 --json b.json");
    ASSERT_EQ(bench.exitCode, 0) << bench.output;
    const nlohmann::json b = readJson("b.json");
    EXPECT_EQ(expectGlFields(b, "bench"), software);
    EXPECT_TRUE(b["settings"]["shader_stage"] == "fragment" || b["settings"]["shader_stage"] == "compute");
    EXPECT_EQ(bench.output.find(kSoftwareWarning), std::string::npos) << "-q: errors only\n" << bench.output;

    const Result verify = run(std::string("verify ") + kScene + "--stats-json v.json");
    ASSERT_EQ(verify.exitCode, 0) << verify.output;
    const nlohmann::json v = readJson("v.json");
    EXPECT_EQ(expectGlFields(v, "verify"), software);
    EXPECT_EQ(v["reference"], "embree");
}

// The compute stage traces the fragment stage's hits, bit for bit, for every ray type (verify's exact comparison),
// and renders the same image file.
TEST_F(CliTest, ComputeStageEqualsFragmentStageBitForBit) {
    const Result verify = run(std::string("verify ") + kScene +
                              "--method bvh --shader-stage compute --reference fragment --ray-type primary,shadow,ao,diffuse "
                              "--stats-json v.json");
    ASSERT_EQ(verify.exitCode, 0) << verify.output;
    EXPECT_NE(verify.output.find("method bvh (compute stage) against pure BVH tracing (exact, fragment stage)"),
              std::string::npos)
        << verify.output;
    const nlohmann::json v = readJson("v.json");
    EXPECT_EQ(v["shader_stage"], "compute");
    EXPECT_EQ(v["reference"], "bvh-fragment");
    EXPECT_EQ(v["differing"], 0);
    uint64_t active = 0;
    for (const nlohmann::json& row : v["frames"]) active += row["active_rays"].get<uint64_t>();
    EXPECT_GT(active, 40u * 28u); // primary rays alone are all active

    for (const char* stage : {"fragment", "compute"}) {
        const Result r = run(std::string("render ") + kScene + "--spp 2 --primary traced --shader-stage " + stage + " -o " +
                             stage + ".png");
        ASSERT_EQ(r.exitCode, 0) << r.output;
    }
    EXPECT_EQ(readFile("fragment.png"), readFile("compute.png"));
}

// CHC+RT's cell passes run in the stage --shader-stage names, and the recommended configuration decides its lists by
// the renderer (bounds-only on a software renderer, bounds-gpu on others) unless --chcrt-queries is given; the
// compute cell passes find pure BVH's hits (verify's exact comparison, the culling path forced).
TEST_F(CliTest, ChcrtCellPassesFollowTheShaderStageAndListsTheRenderer) {
    const auto chcrtOptions = [&](const std::string& flags, bool& software) {
        const Result r = run(std::string("bench ") + kScene + "--method chcrt-noadapt --ray-type shadow --runs 1 "
                             "--warmup 0 --json b.json " + flags);
        EXPECT_EQ(r.exitCode, 0) << r.output;
        const nlohmann::json b = readJson("b.json");
        software = b.value("software_renderer", false);
        for (const nlohmann::json& row : b["rows"]) {
            if (row["method"] == "chcrt-noadapt") return row["chcrt"]["options"];
        }
        ADD_FAILURE() << "no chcrt-noadapt row";
        return nlohmann::json();
    };
    bool software = false;
    const nlohmann::json compute = chcrtOptions("--shader-stage compute", software);
    EXPECT_EQ(compute["cell_pass"], "compute");
    EXPECT_EQ(compute["queries"], software ? "bounds-only" : "bounds-gpu");
    const nlohmann::json fragment = chcrtOptions("--shader-stage fragment --chcrt-queries bounds-gpu", software);
    EXPECT_EQ(fragment["cell_pass"], "fragment");
    EXPECT_EQ(fragment["queries"], "bounds-gpu");
    const nlohmann::json automatic = chcrtOptions("--shader-stage auto", software);
    EXPECT_EQ(automatic["cell_pass"], software ? "fragment" : "compute");

    for (const char* queries : {"bounds-only", "bounds-gpu"}) {
        const Result verify = run(std::string("verify ") + kScene + "--method chcrt --shader-stage compute "
                                  "--chcrt-queries " + queries + " --ray-type primary,shadow,ao,diffuse");
        EXPECT_EQ(verify.exitCode, 0) << queries << "\n" << verify.output;
    }
}

} // namespace
} // namespace chcrt::clitest
