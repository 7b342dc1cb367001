// The recommended CHC+RT configuration per GL renderer (recommendedChcrtOptions, culling/chcrt_tracer.h): the one
// place that chooses where cell lists are decided and in which shader stage they are traced.
#include "culling/chcrt_tracer.h"
#include "renderer/render/trace_stage.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

TEST(RecommendedChcrtOptions, SoftwareRenderersDecideListsOnTheCpuAndTraceThemInFragmentPasses) {
    const RendererTraits llvmpipe = rendererTraits("llvmpipe (LLVM 15.0.6, 256 bits)");
    ASSERT_TRUE(llvmpipe.software);
    const ChcrtOptions options = recommendedChcrtOptions(llvmpipe);
    EXPECT_EQ(options.queries, ChcrtQueries::BoundsOnly);
    EXPECT_FALSE(options.computeCellPass);
    EXPECT_EQ(autoTraceStage(llvmpipe), TraceStage::Fragment); // pure BVH's rule agrees
    // Without traits: the software choice (the methods' defaults before a context exists).
    EXPECT_EQ(recommendedChcrtOptions().queries, ChcrtQueries::BoundsOnly);
    EXPECT_FALSE(recommendedChcrtOptions().computeCellPass);
}

TEST(RecommendedChcrtOptions, HardwareRenderersDecideListsOnTheGpuAndTraceThemInComputeDispatches) {
    for (const char* name : {"NVIDIA H200/PCIe/SSE2", "AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6, DRM 3.54)",
                             "Mesa Intel(R) UHD Graphics 630 (CFL GT2)"}) {
        const RendererTraits gpu = rendererTraits(name);
        ASSERT_FALSE(gpu.software) << name;
        const ChcrtOptions options = recommendedChcrtOptions(gpu);
        EXPECT_EQ(options.queries, ChcrtQueries::BoundsGpu) << name;
        EXPECT_TRUE(options.computeCellPass) << name;
        EXPECT_EQ(autoTraceStage(gpu), TraceStage::Compute) << name;
    }
}

TEST(RecommendedChcrtOptions, TheRendererChangesOnlyTheListDecisionsAndTheStage) {
    const ChcrtOptions software = recommendedChcrtOptions(RendererTraits{.software = true});
    const ChcrtOptions hardware = recommendedChcrtOptions(RendererTraits{.software = false});
    for (const ChcrtOptions* o : {&software, &hardware}) {
        EXPECT_EQ(o->partition.maxSubtreeHeight, 12u);
        EXPECT_EQ(o->adaptiveHeights, (std::vector<uint32_t>{10, 14}));
        EXPECT_EQ(o->cellListLimit, 64u);
        EXPECT_EQ(o->bounds.cellSize, 16); // measured on llvmpipe (culling/README.md "Parameters"), on every renderer
        EXPECT_TRUE(o->hitHints);
        EXPECT_TRUE(o->adaptive);
        EXPECT_TRUE(decidesByBounds(o->queries));
    }
}

} // namespace
} // namespace chcrt
