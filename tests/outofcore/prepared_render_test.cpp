// A prepared scene loaded in core renders exactly like the scene it was prepared from (issue #5, task 5):
// city:20k prepared with small subtrees (so the BVH is spliced from many of them), then primary, shadow and AO
// hits traced on the GPU from the generated scene and from the .chs are compared bit for bit.
#include "renderer/outofcore/chs_file.h"
#include "tests/outofcore/outofcore_test_util.h"
#include "tests/render/render_fixture.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

using PreparedRenderTest = test::RenderTest;

std::vector<std::vector<Hit>> traceAll(Renderer& renderer, const CameraPath& path) {
    std::vector<std::vector<Hit>> all;
    for (int frame : {0, path.frameCount() / 2}) {
        const Camera camera = path.cameraAtFrame(frame);
        FrameStats stats;
        renderer.renderGBuffer(camera, stats);
        for (RayType type : {RayType::Primary, RayType::Shadow, RayType::Ao}) {
            renderer.generateRayPass(camera, type, 0, stats);
            renderer.traceRayPass(camera, type, 0, stats);
            all.push_back(renderer.readHits(0));
        }
    }
    return all;
}

TEST_F(PreparedRenderTest, HitsFromPreparedFileEqualHitsFromSpec) {
    test::ScratchDir dir;
    const auto file = dir.file("city.chs");
    const outofcore::PrepareReport report = test::prepareSmall("city:20k", file, 1000);
    ASSERT_GT(report.subtrees, 10u);
    const RenderSettings settings = test::smallTraceSettings();
    Renderer& fromSpec = makeProceduralRenderer("city:20k", settings);
    const CameraPath path = proceduralNearPath(spec_);
    const std::vector<std::vector<Hit>> expected = traceAll(fromSpec, path);
    renderer_.reset();

    const outofcore::LoadedPreparedScene loaded = outofcore::loadPreparedScene(file);
    Renderer fromFile(loaded.scene, loaded.bvh, loaded.light, settings);
    const std::vector<std::vector<Hit>> actual = traceAll(fromFile, path);
    ASSERT_EQ(actual.size(), expected.size());
    uint64_t hits = 0;
    for (size_t set = 0; set < expected.size(); ++set) {
        ASSERT_EQ(actual[set].size(), expected[set].size());
        for (size_t i = 0; i < expected[set].size(); ++i) {
            ASSERT_EQ(actual[set][i].triangleId, expected[set][i].triangleId) << "set " << set << " pixel " << i;
            ASSERT_EQ(actual[set][i].t, expected[set][i].t) << "set " << set << " pixel " << i;
            hits += expected[set][i].hit();
        }
    }
    EXPECT_GT(hits, 1000u);
}

} // namespace
} // namespace chcrt
