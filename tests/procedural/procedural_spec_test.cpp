#include "renderer/scene/procedural/procedural.h"

#include "renderer/core/error.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

ProceduralSpec parsed(const std::string& text) {
    ProceduralSpec spec;
    spec.targetTriangles = 123; // must be overwritten
    spec.seed = 99;
    EXPECT_TRUE(parseProceduralSpec(text, spec)) << text;
    return spec;
}

TEST(ProceduralSpec, ParsesKindsCountsAndSeeds) {
    ProceduralSpec spec = parsed("city");
    EXPECT_EQ(spec.kind, ProceduralKind::City);
    EXPECT_EQ(spec.targetTriangles, 1'000'000u); // defaults
    EXPECT_EQ(spec.seed, 1u);

    spec = parsed("city:2m");
    EXPECT_EQ(spec.targetTriangles, 2'000'000u);
    spec = parsed("interior:500k");
    EXPECT_EQ(spec.kind, ProceduralKind::Interior);
    EXPECT_EQ(spec.targetTriangles, 500'000u);
    spec = parsed("plant:10m:seed=7");
    EXPECT_EQ(spec.kind, ProceduralKind::Plant);
    EXPECT_EQ(spec.targetTriangles, 10'000'000u);
    EXPECT_EQ(spec.seed, 7u);
    EXPECT_EQ(parsed("city:1500000").targetTriangles, 1'500'000u);
    EXPECT_EQ(parsed("city:1.5m").targetTriangles, 1'500'000u);
    EXPECT_EQ(parsed("city:seed=3").seed, 3u);
    EXPECT_EQ(parsed("city:seed=3").targetTriangles, 1'000'000u);
    EXPECT_EQ(parsed("plane-and-box").kind, ProceduralKind::PlaneAndBox);
    EXPECT_EQ(parsed("closed-box").kind, ProceduralKind::ClosedBox);
    EXPECT_EQ(parsed("one-triangle").kind, ProceduralKind::OneTriangle);
}

TEST(ProceduralSpec, FilePathsAreNotSpecs) {
    ProceduralSpec spec;
    spec.seed = 42;
    for (const char* path : {"foo.gltf", "scenes/x.glb", "C:/scenes/city.glb", "city.gltf", "cities:1m", ""}) {
        EXPECT_FALSE(parseProceduralSpec(path, spec)) << path;
        EXPECT_EQ(spec.seed, 42u) << "spec must be untouched for " << path;
    }
}

TEST(ProceduralSpec, MalformedSpecsThrow) {
    ProceduralSpec spec;
    for (const char* bad : {"city:abc", "city:0", "plant:5m:seed=x", "city:1m:bogus=3", "city:", "city:1m:2m",
                            "city:seed=1:seed=2", "city:-5", "city:2000m", "city:seed=99999999999", "city::1m"}) {
        EXPECT_THROW(parseProceduralSpec(bad, spec), InputError) << bad;
    }
}

TEST(ProceduralSpec, CanonicalStringRoundTrips) {
    ProceduralSpec spec;
    spec.kind = ProceduralKind::Plant;
    spec.targetTriangles = 2'500'000;
    spec.seed = 7;
    EXPECT_EQ(toString(spec), "plant:2500000:seed=7");
    EXPECT_EQ(toString(parsed("city")), "city:1000000:seed=1");
    const ProceduralSpec back = parsed(toString(spec));
    EXPECT_EQ(back.kind, spec.kind);
    EXPECT_EQ(back.targetTriangles, spec.targetTriangles);
    EXPECT_EQ(back.seed, spec.seed);
    EXPECT_EQ(toString(parsed("closed-box")), "closed-box");
}

} // namespace
} // namespace chcrt
