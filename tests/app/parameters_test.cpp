// The parameter table (app/parameters.h) and the method registry (app/methods.h) without GL: every flag parses its
// own default back, viewer settings round-trip, validation names the flag, method defaults apply to what is not
// given, and docs/cli.md has the method table.
#include "app/methods.h"
#include "app/parameters.h"
#include "app/report.h"
#include "renderer/core/error.h"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

namespace chcrt::app {
namespace {

// Parses `arguments` as a command with every shared flag would (the CLI's own registration).
CommonOptions parse(const std::vector<std::string>& arguments) {
    CommonOptions o;
    CLI::App app{"test"};
    addCommonOptions(app, o, kShadedCommands | kHeadlessCommands);
    std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());
    app.parse(reversed);
    return o;
}

std::string inputError(const std::vector<std::string>& arguments) {
    try {
        parse(arguments);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(ParameterTable, FlagsAndKeysAreUniqueAndDescribed) {
    std::set<std::string> flags, keys;
    for (const Parameter& p : parameterTable()) {
        EXPECT_TRUE(flags.insert(p.flag).second) << p.flag;
        if (!p.key.empty()) {
            EXPECT_TRUE(keys.insert(p.key).second) << p.key;
        }
        EXPECT_FALSE(p.help.empty()) << p.flag;
        EXPECT_TRUE(p.parseText && p.parseJson && p.text && p.json && p.copy) << p.flag;
        if (p.widget.kind != ParameterWidget::Kind::None) {
            EXPECT_FALSE(p.key.empty()) << p.flag << ": a widget needs a key";
        }
    }
    EXPECT_EQ(findParameter("--chcrt-multi-query")->key, "chcrtMultiQuery");
    EXPECT_EQ(findParameterByKey("lsNtreeLevel")->flag, "--ls-ntree-level");
    EXPECT_EQ(findParameter("--no-such-flag"), nullptr);
}

TEST(ParameterTable, EveryValueReadsBackItsOwnText) {
    const CommonOptions defaults;
    for (const Parameter& p : parameterTable()) {
        CommonOptions o;
        const std::string text = p.text(defaults);
        if (p.isFlag || text.empty()) continue;
        setParameter(o, p, text);
        EXPECT_EQ(p.text(o), text) << p.flag;
        EXPECT_TRUE(o.isGiven(p.flag)) << p.flag;
        if (p.key.empty()) continue;
        CommonOptions fromJson;
        setParameter(fromJson, p, p.json(defaults));
        EXPECT_EQ(p.text(fromJson), text) << p.key;
    }
}

TEST(ParameterTable, GlDeviceTakesAnIndexOrAutoAndShaderStageAStage) {
    EXPECT_EQ(parse({}).glDevice, kAutoGlDevice);
    EXPECT_EQ(parse({"--gl-device", "auto"}).glDevice, kAutoGlDevice);
    EXPECT_EQ(parse({"--gl-device", "2"}).glDevice, 2);
    EXPECT_EQ(findParameter("--gl-device")->text(parse({})), "auto");
    EXPECT_NE(inputError({"--gl-device", "gpu0"}).find("--gl-device must be auto or an EGL device index"),
              std::string::npos);
    EXPECT_EQ(parse({}).shaderStage, TraceStage::Auto);
    EXPECT_EQ(parse({"--shader-stage", "compute"}).shaderStage, TraceStage::Compute);
    EXPECT_EQ(parse({"--shader-stage", "fragment"}).shaderStage, TraceStage::Fragment);
    EXPECT_NE(inputError({"--shader-stage", "vertex"}).find("--shader-stage must be auto, fragment or compute, not 'vertex'"),
              std::string::npos);
}

TEST(ParameterTable, TheCommandLineSetsTheTypedFields) {
    const CommonOptions o = parse({"--chcrt-min-tile", "16", "--chcrt-leaf-cache", "on", "--ls-depth", "5",
                                   "--ls-ntree", "4:2", "--ls-ntree-start", "exact", "--gpu-cache-mb", "3",
                                   "--cache-policy", "round-robin", "--spp", "7", "--effects", "shadow", "--primary",
                                   "traced", "--out-of-core", "-q", "--chcrt-queries", "bounds-only"});
    EXPECT_EQ(o.chcrt.pairs.minTileSize, 16);
    EXPECT_TRUE(o.chcrt.leafCache);
    EXPECT_EQ(o.chcrt.queries, ChcrtQueries::BoundsOnly);
    EXPECT_EQ(o.lineSpace.depth, 5u);
    EXPECT_EQ(o.ntree.n, 4u);
    EXPECT_EQ(o.ntree.depth, 2u);
    EXPECT_TRUE(o.ntreeShadow.startExact);
    EXPECT_EQ(o.outOfCore.gpuCacheBytes, 3ull << 20);
    EXPECT_EQ(o.outOfCore.policy, outofcore::CachePolicy::RoundRobin);
    EXPECT_EQ(o.render.samplesPerPixel, 7);
    EXPECT_TRUE(o.render.effects.shadows && !o.render.effects.ao && !o.render.effects.diffuse);
    EXPECT_EQ(o.render.primaryVisibility, PrimaryVisibility::Traced);
    EXPECT_TRUE(o.outOfCoreScene.enabled);
    EXPECT_TRUE(o.quiet);
    EXPECT_TRUE(o.isGiven("--chcrt-min-tile"));
    EXPECT_FALSE(o.isGiven("--chcrt-height"));
    EXPECT_EQ(toRenderSettings(o, 1).samplesPerPixel, 7);
    EXPECT_EQ(toRenderSettings(parse({}), 3).samplesPerPixel, 3); // the command's default without --spp
}

TEST(ParameterTable, BadValuesNameTheFlag) {
    EXPECT_NE(inputError({"--chcrt-ray-extent", "maybe"}).find("--chcrt-ray-extent must be on or off"), std::string::npos);
    EXPECT_NE(inputError({"--spp", "0"}).find("--spp must be at least 1"), std::string::npos);
    EXPECT_NE(inputError({"--ls-angle", "200"}).find("--ls-angle must be between 0 and 180"), std::string::npos);
    EXPECT_NE(inputError({"--gpu-cache-mb", "0"}).find("--gpu-cache-mb must be at least 1"), std::string::npos);
    // Megabytes whose bytes would not fit 64 bits are refused, not wrapped around to a small budget.
    EXPECT_NE(inputError({"--host-cache-mb", "1000000000000000"}).find("--host-cache-mb"), std::string::npos);
    EXPECT_EQ(parse({"--host-cache-mb", "1000000000000"}).outOfCore.hostCacheBytes, uint64_t(1e12) << 20);
    EXPECT_NE(inputError({"--cache-policy", "fifo"}).find("round-robin or lru"), std::string::npos);
    EXPECT_NE(inputError({"--chcrt-height", "tall"}).find("--chcrt-height expects a whole number"), std::string::npos);
    EXPECT_NE(inputError({"--ls-ntree", "1:2"}).find("N"), std::string::npos);
    EXPECT_NE(inputError({"--ls-modes", "ao=sometimes"}).find("sometimes"), std::string::npos);
    EXPECT_EQ(inputError({"--chcrt-height", "12"}), "");
}

TEST(ParameterTable, MinusOneGivesAMethodParameterBack) {
    CommonOptions o = parse({"--chcrt-threshold", "5", "--ls-ntree-level", "2"});
    EXPECT_TRUE(o.isGiven("--chcrt-threshold"));
    setParameter(o, *findParameterByKey("chcrtThreshold"), nlohmann::json(-1));
    setParameter(o, *findParameter("--ls-ntree-level"), std::string("-1"));
    EXPECT_FALSE(o.isGiven("--chcrt-threshold"));
    EXPECT_FALSE(o.isGiven("--ls-ntree-level"));
    EXPECT_EQ(o.chcrt.visibleThreshold, 0u);
}

TEST(ParameterTable, CommandLinesCarryTheParametersThatApply) {
    const CommonOptions o = parse({"--chcrt-multi-query", "2", "--ls-n", "3", "--spp", "2", "--bvh-bins", "8"});
    const auto only = [](std::set<ParameterArea> areas) {
        return [areas](ParameterArea a) { return !isMethodArea(a) || areas.count(a); };
    };
    const std::string chcrt = commandLineArguments(o, only({ParameterArea::Chcrt}));
    EXPECT_NE(chcrt.find(" --chcrt-multi-query 2"), std::string::npos) << chcrt;
    EXPECT_EQ(chcrt.find("--ls-n"), std::string::npos) << chcrt;
    EXPECT_EQ(chcrt.find("--chcrt-height"), std::string::npos) << chcrt << ": not given";
    EXPECT_NE(chcrt.find(" --spp 2"), std::string::npos) << chcrt;
    EXPECT_NE(chcrt.find(" --bvh-bins 8"), std::string::npos) << chcrt;
    EXPECT_EQ(chcrt.find("--bvh-leaf-size"), std::string::npos) << chcrt << ": the default";
    EXPECT_EQ(chcrt.find("--out-of-core"), std::string::npos) << chcrt;
    const std::string lineSpace = commandLineArguments(o, only({ParameterArea::LineSpace}));
    EXPECT_NE(lineSpace.find(" --ls-n 3"), std::string::npos) << lineSpace;
    EXPECT_EQ(lineSpace.find("--chcrt"), std::string::npos) << lineSpace;
    EXPECT_EQ(givenParameters(o, [](const Parameter& p) { return isMethodArea(p.area); }),
              "--chcrt-multi-query=2 --ls-n=3");
}

TEST(MethodRegistry, NamesAreUniqueAndErrorsListThem) {
    std::set<std::string> names;
    for (const MethodInfo& m : methodRegistry()) EXPECT_TRUE(names.insert(m.name).second) << m.name;
    EXPECT_EQ(methodRegistry().front().name, kPureBvhMethod);
    EXPECT_FALSE(findMethod("embree").gpu);
    EXPECT_TRUE(findMethod("chcrt").outOfCoreForm);
    EXPECT_FALSE(findMethod("chcrt+ls").outOfCoreForm);
    EXPECT_TRUE(findMethod("chcrt+ls").reads(ParameterArea::LineSpace));
    EXPECT_FALSE(findMethod("chcrt+ls").reads(ParameterArea::LineSpaceModes));
    try {
        findMethod("warp");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("available: bvh, chcrt"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("embree"), std::string::npos) << e.what();
    }
    EXPECT_THROW(findGpuMethod("embree"), InputError);
}

// The method's own defaults apply to what the user did not give; what the user gave wins.
TEST(MethodRegistry, MethodDefaultsApplyToParametersNotGiven) {
    const MethodInfo& aggressive = findMethod("chcrt-aggressive");
    EXPECT_EQ(resolveMethodOptions(aggressive, parse({}), 0).chcrt.visibleThreshold, 20u);
    EXPECT_FALSE(resolveMethodOptions(aggressive, parse({}), 0).chcrt.adaptive);
    EXPECT_EQ(resolveMethodOptions(aggressive, parse({"--chcrt-threshold", "3"}), 0).chcrt.visibleThreshold, 3u);
    EXPECT_EQ(resolveMethodOptions(findMethod("chcrt"), parse({}), 0).chcrt.visibleThreshold, 0u);
    EXPECT_TRUE(resolveMethodOptions(findMethod("chcrt"), parse({}), 0).chcrt.adaptive);
    EXPECT_FALSE(resolveMethodOptions(findMethod("chcrt-noadapt"), parse({}), 0).chcrt.adaptive);
    // chcrt in core: the recommended configuration; a given height leaves no other height to try.
    const CommonOptions recommended = resolveMethodOptions(findMethod("chcrt"), parse({}), 0);
    EXPECT_EQ(recommended.chcrt.queries, ChcrtQueries::BoundsOnly);
    EXPECT_EQ(recommended.chcrt.partition.maxSubtreeHeight, 12u);
    EXPECT_EQ(recommended.chcrt.adaptiveHeights, (std::vector<uint32_t>{10, 14}));
    EXPECT_EQ(recommended.chcrt.cellListLimit, 64u);
    EXPECT_TRUE(recommended.chcrt.hitHints);
    EXPECT_FALSE(resolveMethodOptions(findMethod("chcrt"), parse({"--chcrt-hints", "off"}), 0).chcrt.hitHints);
    EXPECT_FALSE(resolveMethodOptions(findMethod("chcrt-aggressive"), parse({}), 0).chcrt.hitHints);
    const CommonOptions forced = resolveMethodOptions(findMethod("chcrt"), parse({"--chcrt-height", "8"}), 0);
    EXPECT_EQ(forced.chcrt.partition.maxSubtreeHeight, 8u);
    EXPECT_TRUE(forced.chcrt.adaptiveHeights.empty());
    EXPECT_EQ(resolveMethodOptions(findMethod("chcrt"), parse({"--chcrt-cell-list-limit", "0"}), 0).chcrt.cellListLimit,
              0u);
    EXPECT_EQ(resolveMethodOptions(findMethod("chcrt-aggressive"), parse({}), 0).chcrt.queries, ChcrtQueries::Gl);
    // Out of core: batched queries, rounds intersected by cells of the recommended size; a given size wins.
    const CommonOptions outOfCore = resolveMethodOptions(findMethod("chcrt"), parse({"--out-of-core"}), 0);
    EXPECT_EQ(outOfCore.chcrt.queries, ChcrtQueries::Batched);
    EXPECT_TRUE(outOfCore.chcrt.cellIntersect);
    EXPECT_EQ(outOfCore.chcrt.bounds.cellSize, kRecommendedBoundsCellSize);
    // ... and hit hints with the hint pass, which stops only above half the rays left (culling/README.md, "Hit hints
    // out of core"; a quarter in core); --chcrt-hints off still turns them off.
    EXPECT_TRUE(outOfCore.chcrt.hitHints);
    EXPECT_TRUE(outOfCore.chcrt.hintPass);
    EXPECT_EQ(outOfCore.chcrt.hintPassMaxLeft, 0.5f);
    EXPECT_EQ(recommended.chcrt.hintPassMaxLeft, 0.25f);
    EXPECT_FALSE(resolveMethodOptions(findMethod("chcrt"), parse({"--out-of-core", "--chcrt-hints", "off"}), 0).chcrt.hitHints);
    EXPECT_TRUE(resolveMethodOptions(findMethod("chcrt-noadapt"), parse({"--out-of-core"}), 0).chcrt.hitHints);
    EXPECT_EQ(resolveMethodOptions(findMethod("chcrt-lod"), parse({"--out-of-core"}), 0).chcrt.bounds.cellSize, 16);
    EXPECT_EQ(resolveMethodOptions(findMethod("chcrt"), parse({"--out-of-core", "--chcrt-bounds-cell", "8"}), 0)
                  .chcrt.bounds.cellSize, 8);
    // The worked example's path (docs/architecture.md): a --chcrt-* flag reaches the ChcrtOptions field.
    EXPECT_EQ(resolveMethodOptions(findMethod("chcrt"), parse({"--chcrt-min-tile", "16"}), 0).chcrt.pairs.minTileSize, 16);
    // ntree+ls: shadow level d - 1 of the given N-tree, unless given.
    EXPECT_EQ(resolveMethodOptions(findMethod("ntree+ls"), parse({"--ls-ntree", "4:2"}), 0).ntreeShadow.shadowLevel, 1u);
    EXPECT_EQ(resolveMethodOptions(findMethod("ntree+ls"), parse({}), 0).ntreeShadow.shadowLevel, 2u);
    EXPECT_EQ(resolveMethodOptions(findMethod("ntree+ls"), parse({"--ls-ntree-level", "5"}), 0).ntreeShadow.shadowLevel, 5u);
}

// bvh+ls starts from the configuration linespace/README.md measured good on every scene (app/methods.cpp): D = 6
// up to 1.5M triangles, deeper for larger scenes; diffuse candidates, everything else without Line Spaces.
// The old defaults (D = 9, shadow termination, AO off) stay one set of flags away.
TEST(MethodRegistry, LineSpaceDefaultsAreTheRecommendedConfiguration) {
    const MethodInfo& ls = findMethod("bvh+ls");
    EXPECT_EQ(resolveMethodOptions(ls, parse({}), 871'306).lineSpace.depth, 6u); // the dragon
    EXPECT_EQ(resolveMethodOptions(ls, parse({}), 1'000'000).lineSpace.depth, 6u);
    EXPECT_EQ(resolveMethodOptions(ls, parse({}), 2'000'000).lineSpace.depth, 7u);
    EXPECT_EQ(resolveMethodOptions(ls, parse({}), 10'000'000).lineSpace.depth, 9u);
    EXPECT_EQ(resolveMethodOptions(ls, parse({}), 4'000'000'000ull).lineSpace.depth, 12u);
    EXPECT_EQ(resolveMethodOptions(ls, parse({"--ls-depth", "9"}), 1'000'000).lineSpace.depth, 9u);
    EXPECT_EQ(resolveMethodOptions(findMethod("bvh+ls-exact"), parse({}), 1'000'000).lineSpace.depth, 9u);
    CommonOptions resolved = resolveMethodOptions(ls, parse({}), 1'000'000);
    ls::LineSpaceModes modes = resolved.lineSpaceTracing.baseModes;
    EXPECT_EQ(modes.diffuse, ls::LineSpaceMode::Candidate);
    EXPECT_EQ(modes.ao, ls::LineSpaceMode::Off);
    EXPECT_EQ(modes.shadow, ls::LineSpaceMode::Off);
    EXPECT_EQ(modes.bounceShadow, ls::LineSpaceMode::Off);
    EXPECT_EQ(modes.primary, ls::LineSpaceMode::Off);
    // --ls-modes applies on top of the method's modes.
    resolved = resolveMethodOptions(ls, parse({"--ls-modes", "ao=candidate"}), 1'000'000);
    modes = resolved.lineSpaceTracing.baseModes;
    modes.parse(resolved.lineSpaceTracing.modes);
    EXPECT_EQ(modes.ao, ls::LineSpaceMode::Candidate);
    EXPECT_EQ(modes.diffuse, ls::LineSpaceMode::Candidate);
    EXPECT_EQ(modes.shadow, ls::LineSpaceMode::Off);
}

// bench traces pure BVH first and the other methods in an order reversed every pass, so that over a run each method
// follows pure BVH and each other method equally often (benchTraceOrder; docs/benchmarks.md, 2026-12-07).
TEST(MethodRegistry, BenchAlternatesTheOrderOfTheMethodsAfterPureBvh) {
    using Order = std::vector<std::string>;
    const Order methods = {kPureBvhMethod, "chcrt", "chcrt-noadapt", "chcrt-aggressive"};
    EXPECT_EQ(benchTraceOrder(methods, 0), methods);
    EXPECT_EQ(benchTraceOrder(methods, 1), (Order{kPureBvhMethod, "chcrt-aggressive", "chcrt-noadapt", "chcrt"}));
    EXPECT_EQ(benchTraceOrder(methods, 2), methods);
    EXPECT_EQ(benchTraceOrder(methods, 7), benchTraceOrder(methods, 1));
    // Out of core there is no pure BVH: every method alternates.
    EXPECT_EQ(benchTraceOrder(Order{"chcrt", "chcrt-lod"}, 1), (Order{"chcrt-lod", "chcrt"}));
    EXPECT_TRUE(benchTraceOrder(Order{}, 1).empty());
}

std::string readDoc(const char* relative) {
    std::ifstream in(std::string(CHCRT_SOURCE_DIR) + "/" + relative);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// docs/cli.md carries the table `chcrt methods --markdown` prints. (Flags are not checked here: `--help` is their
// complete reference, generated from the table, so that a new parameter needs no docs edit.)
TEST(Docs, CliReferenceHasTheMethodTable) {
    const std::string cli = readDoc("docs/cli.md");
    ASSERT_FALSE(cli.empty());
    EXPECT_NE(cli.find(methodTable().toMarkdown()), std::string::npos)
        << "docs/cli.md's method table differs from `build/bin/chcrt methods --markdown`:\n" << methodTable().toMarkdown();
}

} // namespace
} // namespace chcrt::app
