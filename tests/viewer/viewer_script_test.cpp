// Viewer scripts: what parses and what is refused (with the step and key named).
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

} // namespace
} // namespace chcrt::app
