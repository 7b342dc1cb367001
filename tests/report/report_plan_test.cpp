// The plan of `chcrt report` (app/report_plan.h): presets become the groups their studies promise, flags override
// them, and every bad name is refused before anything runs (so that bad input writes nothing).
#include "app/report_plan.h"
#include "renderer/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace chcrt::app {
namespace {

size_t countStudy(const std::vector<ReportGroup>& groups, const std::string& study) {
    return size_t(std::count_if(groups.begin(), groups.end(), [&](const ReportGroup& g) { return g.study == study; }));
}

bool hasWords(const std::vector<std::string>& command, const std::vector<std::string>& words) {
    return std::search(command.begin(), command.end(), words.begin(), words.end()) != command.end();
}

TEST(ReportPlan, QuickPresetMakesEveryStudysGroupsWithUniqueOutputs) {
    const std::vector<ReportGroup> groups = planReport(presetSettings("quick"), "out/r");
    // Per scene (3): one compare bench (1 spp for all ray types), 3 thresholds, 3 rotations, 2 depths, 1 images.
    EXPECT_EQ(groups.size(), 30u);
    EXPECT_EQ(countStudy(groups, "compare"), 3u);
    EXPECT_EQ(countStudy(groups, "aggressive"), 9u);
    EXPECT_EQ(countStudy(groups, "rotation"), 9u);
    EXPECT_EQ(countStudy(groups, "ls-rc"), 6u);
    EXPECT_EQ(countStudy(groups, "images"), 3u);
    std::set<std::string> ids;
    for (const ReportGroup& g : groups) {
        EXPECT_TRUE(ids.insert(g.id).second) << g.id;
        EXPECT_GT(g.cost, 0);
        if (g.images) continue;
        ASSERT_EQ(g.commands.size(), 1u);
        EXPECT_EQ(g.commands[0].front(), "bench");
        EXPECT_TRUE(hasWords(g.commands[0], {"--json", "out/r/data/" + g.id + ".json"})) << g.id;
    }
    const ReportGroup& compare = *std::find_if(groups.begin(), groups.end(),
                                               [](const ReportGroup& g) { return g.study == "compare"; });
    EXPECT_TRUE(hasWords(compare.commands[0], {"--method", "bvh,chcrt,chcrt-noadapt,chcrt-aggressive,bvh+ls"}));
    EXPECT_TRUE(hasWords(compare.commands[0], {"--ray-type", "primary,shadow,ao,diffuse"}));
    EXPECT_TRUE(hasWords(compare.commands[0], {"--steps"}));
    const ReportGroup& images = groups.back();
    ASSERT_TRUE(images.images);
    for (const char* key : {"bvh", "overdraw", "subtrees", "batches", "cost", "chcrt-aggressive", "bvh+ls"}) {
        EXPECT_TRUE(images.files.count(key)) << key;
    }
    EXPECT_EQ(images.commands.size(), images.files.size());
}

TEST(ReportPlan, FlagsOverrideThePresetAndSppSplitsBenches) {
    ReportOptions o;
    o.preset = "paper";
    o.scenes = "city:50k";
    o.studies = "compare";
    o.methods = "chcrt";
    o.size = 32;
    const ReportSettings s = reportSettings(o);
    EXPECT_EQ(s.size, 32);
    const std::vector<ReportGroup> groups = planReport(s, "r");
    // near and far; primary 1 spp, shadow 16, AO and diffuse 20: three benches per path.
    ASSERT_EQ(groups.size(), 6u);
    for (const ReportGroup& g : groups) {
        EXPECT_TRUE(hasWords(g.commands[0], {"--method", "bvh,chcrt"})) << g.id; // bvh is always the reference
        EXPECT_TRUE(hasWords(g.commands[0], {"--width", "32"}));
    }
    EXPECT_TRUE(hasWords(groups[2].commands[0], {"--ray-type", "ao,diffuse", "--spp", "20"}));
    o.spp = "ao=4";
    EXPECT_EQ(reportSettings(o).spp.at("ao"), 4);
    EXPECT_EQ(reportSettings(o).spp.at("shadow"), 16);
}

TEST(ReportPlan, BadNamesAreRefusedBeforeAnythingRuns) {
    EXPECT_THROW(presetSettings("nosuch"), InputError);
    auto plan = [](auto change) {
        ReportOptions o;
        change(o);
        return planReport(reportSettings(o), "r");
    };
    EXPECT_THROW(plan([](ReportOptions& o) { o.scenes = "nosuch"; }), InputError);
    EXPECT_THROW(plan([](ReportOptions& o) { o.scenes = "city:10k@sideways"; }), InputError);
    EXPECT_THROW(plan([](ReportOptions& o) { o.methods = "bvh,nosuch"; }), InputError);
    EXPECT_THROW(plan([](ReportOptions& o) { o.rayTypes = "primary,gamma"; }), InputError);
    EXPECT_THROW(plan([](ReportOptions& o) { o.studies = "compare,nosuch"; }), InputError);
    EXPECT_THROW(plan([](ReportOptions& o) { o.thresholds = "20,x"; }), InputError);
    EXPECT_THROW(plan([](ReportOptions& o) { o.lsNtree = "6"; }), InputError);
    EXPECT_THROW(plan([](ReportOptions& o) { o.spp = "ao=0"; }), InputError);
    EXPECT_NO_THROW(plan([](ReportOptions& o) { o.scenes = "city:10k@far"; }));
}

TEST(ReportPlan, SceneLabelsAreFileNameSafe) {
    EXPECT_EQ(sceneLabel("city:200k"), "city-200k");
    EXPECT_EQ(sceneLabel("plant:500k:seed=3"), "plant-500k-seed-3");
    EXPECT_EQ(sceneLabel("../scenes/castle.gltf"), "castle");
}

} // namespace
} // namespace chcrt::app
