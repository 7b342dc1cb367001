// The viewer's settings through the parameter table (app/viewer/viewer_settings.h): script keys set the same typed
// fields as the flags, with the same checks, and the copied command lines carry what applies to the method.
#include "app/viewer/viewer_settings.h"

#include "renderer/core/error.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

namespace chcrt::app {
namespace {

Camera testCamera() {
    Camera c;
    c.eye = {1, 2, 3};
    c.target = {1, 2, -3};
    return c;
}

TEST(ViewerSettings, KeysSetTheParametersOfTheTable) {
    ViewerSettings s;
    applySettings(s, {{"method", "chcrt"}, {"chcrtMinTile", 32}, {"chcrtTighterBounds", false}, {"lsNtree", "4:2"},
                      {"spp", 3}, {"effects", "shadow,ao"}, {"primary", "traced"}, {"renderScale", 0.25}});
    EXPECT_EQ(s.method, "chcrt");
    EXPECT_EQ(s.common.chcrt.pairs.minTileSize, 32);
    EXPECT_FALSE(s.common.chcrt.tighterBounds);
    EXPECT_EQ(s.common.ntree.n, 4u);
    EXPECT_EQ(s.common.render.samplesPerPixel, 3);
    EXPECT_TRUE(s.common.render.effects.ao && !s.common.render.effects.diffuse);
    EXPECT_EQ(s.common.render.primaryVisibility, PrimaryVisibility::Traced);
    EXPECT_FLOAT_EQ(s.renderScale, 0.25f);
    EXPECT_EQ(methodParameters(s.common), "--chcrt-min-tile=32 --chcrt-tighter-bounds=off --ls-ntree=4:2");
    applySettings(s, {{"chcrtMinTile", -1}}); // back to the method's default
    EXPECT_EQ(methodParameters(s.common), "--chcrt-tighter-bounds=off --ls-ntree=4:2");
}

TEST(ViewerSettings, BadSettingsChangeNothing) {
    ViewerSettings s;
    for (const char* bad : {R"({"spp": 0})", R"({"lsNtree": "4"})", R"({"lsNtreeStart": "maybe"})",
                            R"({"lsNtreeLevel": -2})", R"({"lsNtreeNear": -1})", R"({"chcrtRayExtent": "on"})",
                            R"({"method": "warp"})", R"({"fly": 1})", R"({"renderScale": 9})"}) {
        ViewerSettings before = s;
        EXPECT_THROW(applySettings(s, nlohmann::json::parse(bad)), InputError) << bad;
        EXPECT_EQ(methodParameters(s.common), methodParameters(before.common)) << bad;
        EXPECT_EQ(s.common.render.samplesPerPixel, before.common.render.samplesPerPixel) << bad;
    }
    // Everything is checked before anything changes: a good key before a bad one is not applied either.
    EXPECT_THROW(applySettings(s, {{"lsN", 3}, {"zoom", 1}}), InputError);
    EXPECT_EQ(s.common.lineSpace.n, 6u);
}

TEST(ViewerSettings, CommandLinesCarryTheMethodsParameters) {
    ViewerSettings s;
    applySettings(s, {{"method", "chcrt-aggressive"}, {"chcrtThreshold", 7}, {"chcrtHeight", 12}, {"lsN", 3}});
    const std::string render = renderCommandLine(s, testCamera(), 64, 32);
    EXPECT_EQ(render.rfind("chcrt render --scene city --eye 1,2,3 --target 1,2,-3 --fov 60 --width 64 --height 32", 0), 0u)
        << render;
    for (const char* word : {" --chcrt-threshold 7", " --chcrt-height 12", " --method chcrt-aggressive", " --spp 4",
                             " --effects shadow,ao,diffuse", " -o view.png"}) {
        EXPECT_NE(render.find(word), std::string::npos) << word << " in " << render;
    }
    EXPECT_EQ(render.find("--ls-n"), std::string::npos) << "chcrt-aggressive reads no Line Spaces: " << render;
    applySettings(s, {{"method", "raster"}});
    const std::string raster = renderCommandLine(s, testCamera(), 64, 32);
    EXPECT_NE(raster.find(" --method bvh --effects none"), std::string::npos) << raster;
    EXPECT_EQ(raster.find("--chcrt"), std::string::npos) << raster;
    applySettings(s, {{"method", "bvh+ls"}, {"effects", "ao"}});
    const std::string bench = benchCommandLine(s, testCamera(), 64, 32);
    EXPECT_NE(bench.find(" --ls-n 3 "), std::string::npos) << bench;
    EXPECT_NE(bench.find(" --method bvh+ls --ray-type ao"), std::string::npos) << bench;
}

} // namespace
} // namespace chcrt::app
