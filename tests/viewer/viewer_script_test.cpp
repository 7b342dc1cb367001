// Viewer scripts: what parses and what is refused (with the step and key named).
#include "app/viewer/viewer_recording.h"
#include "app/viewer/viewer_script.h"
#include "renderer/core/error.h"

#include <gtest/gtest.h>

namespace chcrt::app {
namespace {

TEST(ViewerScript, ParsesEveryStepKind) {
    const auto steps = parseViewerScript(R"([
        {"frames": 3},
        {"key": "W", "frames": 5},
        {"keys": ["A", "SHIFT"]},
        {"mouse": [4, -2], "frames": 2},
        {"scroll": -1.5},
        {"set": {"method": "bvh", "viewMode": "cost"}, "frames": 1, "screenshot": "c.png"},
        {"camera": {"eye": [0, 1, 2], "target": [0, 1, 0], "fov": 45}},
        {"pathFrame": 7, "play": true},
        {"action": "recordStart"}, {"recordStop": "walk.json"},
        {"resize": [320, 200]}, {"loadScene": "city:5k"},
        {"expect": {"cappedRays": 0}}])",
                                         "test");
    ASSERT_EQ(steps.size(), 13u);
    EXPECT_EQ(steps[0].frames, 3);
    EXPECT_TRUE(steps[1].held.forward);
    EXPECT_EQ(steps[1].frames, 5);
    EXPECT_TRUE(steps[2].held.left && steps[2].held.fast);
    EXPECT_EQ(steps[2].frames, 1); // held input without a count lasts one frame
    EXPECT_EQ(steps[3].held.lookPixels, glm::vec2(4, -2));
    EXPECT_EQ(steps[4].scrollSteps, -1.5f);
    EXPECT_EQ(steps[4].frames, 0);
    EXPECT_EQ((*steps[5].set)["viewMode"], "cost");
    EXPECT_EQ(steps[5].screenshot, "c.png");
    EXPECT_EQ(steps[6].camera->fovYDegrees, 45.0f);
    EXPECT_EQ(*steps[7].pathFrame, 7);
    EXPECT_TRUE(*steps[7].play);
    EXPECT_EQ(steps[8].action, "recordStart");
    EXPECT_EQ(steps[9].recordStop, "walk.json");
    EXPECT_EQ(steps[10].resize->first, 320);
    EXPECT_EQ(steps[11].loadScene, "city:5k");
    EXPECT_EQ((*steps[12].expect)["cappedRays"], 0);
    const auto pick = parseViewerScript(R"([{"pick": [12, 34], "frames": 1}])", "pick");
    ASSERT_TRUE(pick[0].pick.has_value());
    EXPECT_EQ(*pick[0].pick, std::make_pair(12, 34));
}

TEST(ViewerScript, RefusesMalformedScriptsNamingTheStep) {
    const char* bad[] = {
        "{\"frames\": 1}",                  // not a list
        "[{\"frames\": -1}]",               // negative
        "[{\"frames\": \"many\"}]",         // wrong type
        "[{\"key\": \"X\"}]",               // unknown key
        "[{\"jump\": true}]",               // unknown step key
        "[{\"mouse\": [1]}]",               // not a pair
        "[{\"camera\": {\"eye\": [0,0,0]}}]", // no target
        "[{\"camera\": {\"eye\": [0,0,0], \"target\": [0,0,0]}}]",
        "[{\"action\": \"explode\"}]",
        "[{\"resize\": [0, 10]}]",
        "[{\"pick\": [3]}]",                // not a pixel
        "[{\"pick\": [-1, 2]}]",
        "[{\"set\": 3}]",
        "[{\"frames\": 1},",                // malformed JSON
    };
    for (const char* text : bad) {
        EXPECT_THROW(parseViewerScript(text, "s.json"), InputError) << text;
    }
    try {
        parseViewerScript("[{\"frames\": 1}, {\"key\": \"X\"}]", "s.json");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("s.json: step 1"), std::string::npos) << e.what();
    }
}

// A step's actions run when it begins, its checks after its frames; a step without frames is checked at once;
// waiting (a scene loads) holds the frames back; a failure ends the script after the failing step's checks.
TEST(ScriptRunner, RunsActionsFramesAndChecksInOrder) {
    ScriptRunner runner(parseViewerScript(R"([{"frames": 2}, {"action": "reset"}, {"loadScene": "x", "frames": 1}])", "s"));
    std::vector<std::string> log;
    bool loading = false;
    const auto actions = [&](const ScriptStep& s) {
        log.push_back("actions " + std::to_string(s.frames));
        loading = !s.loadScene.empty();
    };
    const auto checks = [&](const ScriptStep& s) { log.push_back("checks " + std::to_string(s.frames)); };
    const auto waiting = [&] { return loading; };
    EXPECT_EQ(runner.totalFrames(), 3u); // the viewer reserves its frame times for these
    EXPECT_EQ(runner.advance(actions, checks, waiting), ScriptRunner::Advance::Frame);
    EXPECT_EQ(runner.advance(actions, checks, waiting), ScriptRunner::Advance::Frame);
    EXPECT_EQ(runner.frame(), 2);
    EXPECT_EQ(runner.advance(actions, checks, waiting), ScriptRunner::Advance::Waiting);
    EXPECT_EQ(runner.currentIndex(), 2u);
    loading = false;
    EXPECT_EQ(runner.advance(actions, checks, waiting), ScriptRunner::Advance::Frame);
    EXPECT_EQ(runner.advance(actions, checks, waiting), ScriptRunner::Advance::Ended);
    const std::vector<std::string> expected = {"actions 2", "checks 2", "actions 0", "checks 0", "actions 1",
                                               "checks 1"};
    EXPECT_EQ(log, expected);

    ScriptRunner failing(parseViewerScript(R"([{"frames": 1}, {"frames": 1}])", "s"));
    const auto none = [](const ScriptStep&) {};
    EXPECT_EQ(failing.advance(none, none, [] { return false; }), ScriptRunner::Advance::Frame);
    failing.fail();
    EXPECT_EQ(failing.advance(none, none, [] { return false; }), ScriptRunner::Advance::Ended);
    EXPECT_EQ(failing.failures(), 1);
}

TEST(ScriptExpectations, ReportWhatDiffersAndRefuseUnknownKeys) {
    ScriptObservation seen;
    seen.method = "chcrt";
    seen.width = 64;
    seen.height = 36;
    seen.tracePasses[size_t(RayType::Shadow)] = 1;
    seen.accumulatedFrames = 2;
    const nlohmann::json expect = nlohmann::json::parse(
        R"({"method": "chcrt", "imageSize": [64, 36], "tracePasses": {"shadow": 1, "ao": 0}, "accumulatedFrames": 1})");
    const std::vector<std::string> unmet = unmetExpectations(expect, seen);
    ASSERT_EQ(unmet.size(), 1u);
    EXPECT_EQ(unmet[0], "accumulatedFrames = 2");
    EXPECT_THROW(unmetExpectations(nlohmann::json::parse(R"({"colour": "red"})"), seen), InputError);
}

TEST(PathRecorder, RecordsMovedCamerasAtTheScriptsTimeStep) {
    PathRecorder recorder;
    Camera camera;
    camera.eye = {0, 1, 0};
    camera.target = {0, 1, -5};
    recorder.start(camera, 10);
    recorder.record(camera, true, 11); // not moved
    camera.eye.x = 1;
    recorder.record(camera, true, 12);
    camera.eye.x = 2;
    recorder.record(camera, true, 12); // no time passed
    EXPECT_EQ(recorder.keyframes(), 2u);
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "chcrt_recorder_test.json";
    recorder.stop(file.string());
    EXPECT_FALSE(recorder.recording());
    const CameraPath path = loadCameraPath(file);
    ASSERT_EQ(path.keyframes.size(), 2u);
    EXPECT_DOUBLE_EQ(path.keyframes[1].t, 2 * PathRecorder::kScriptSecondsPerFrame);
    std::filesystem::remove(file);
    EXPECT_THROW(recorder.stop(file.string()), InputError); // no recording
}

} // namespace
} // namespace chcrt::app
