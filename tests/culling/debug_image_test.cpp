// CHC+RT debug image names and colours (culling/chcrt_tracer.h), without GL: the cost image's layout (steps in
// the low 31 bits, bit 31 = capped) and its log heat ramp.
#include "culling/chcrt_tracer.h"
#include "renderer/core/error.h"
#include "shaders/shared/render_layout.h"

#include <gtest/gtest.h>

#include <bit>

namespace chcrt::test {
namespace {

glm::vec3 colourAt(const std::vector<float>& rgb, int width, int x, int y) { // y from the top
    const float* c = &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3];
    return glm::vec3(c[0], c[1], c[2]);
}

float brightness(const glm::vec3& c) { return c.r + c.g + c.b; }

TEST(ChcrtDebugImageTest, ParsesEveryKindAndRefusesOthers) {
    EXPECT_EQ(parseChcrtDebugImage("overdraw"), ChcrtDebugImage::Overdraw);
    EXPECT_EQ(parseChcrtDebugImage("subtrees"), ChcrtDebugImage::Subtrees);
    EXPECT_EQ(parseChcrtDebugImage("batches"), ChcrtDebugImage::Batches);
    EXPECT_EQ(parseChcrtDebugImage("cost"), ChcrtDebugImage::Cost);
    EXPECT_EQ(parseChcrtDebugImage("bounds"), ChcrtDebugImage::Bounds);
    EXPECT_THROW(parseChcrtDebugImage("Cost"), InputError);
    EXPECT_THROW(parseChcrtDebugImage("costs"), InputError);
    EXPECT_THROW(parseChcrtDebugImage(""), InputError);
}

TEST(ChcrtDebugImageTest, CostColoursMaskTheCappedBitAndUseALogRamp) {
    // GL rows bottom to top: values[0..3] is the bottom row (y = 1 from the top), values[4..7] the top row.
    const uint32_t capped = CHCRT_TRACE_STEPS_CAPPED;
    const std::vector<uint32_t> values = {0u, 1u, 30u, 1000u,                     // bottom row
                                          capped | 5u, capped, 999u, 1000u}; // top row
    const int width = 4, height = 2;
    const std::vector<float> rgb = colorizeChcrtDebugImage(ChcrtDebugImage::Cost, values, width, height);
    ASSERT_EQ(rgb.size(), values.size() * 3);
    const glm::vec3 magenta(1.0f, 0.0f, 1.0f);
    EXPECT_EQ(colourAt(rgb, width, 0, 1), glm::vec3(0.0f)); // 0 steps: black
    EXPECT_EQ(colourAt(rgb, width, 0, 0), magenta);         // capped, with steps
    EXPECT_EQ(colourAt(rgb, width, 1, 0), magenta);         // capped, no steps counted
    // The capped bit does not count towards the maximum: 1000 steps is the top of the ramp (red), so the
    // scale is not 2^31 (which would leave every uncapped pixel near black).
    EXPECT_EQ(colourAt(rgb, width, 3, 0), colourAt(rgb, width, 3, 1));
    EXPECT_GT(colourAt(rgb, width, 3, 1).r, 0.9f);
    EXPECT_LT(colourAt(rgb, width, 3, 1).b, 0.1f);
    // Log scale: 30 steps of 1000 is past the middle of the ramp (log 31 / log 1001 ≈ 0.5), where a linear ramp
    // would show 3% (deep blue).
    const glm::vec3 thirty = colourAt(rgb, width, 2, 1);
    EXPECT_GT(thirty.g, 0.5f);
    EXPECT_LT(thirty.b, 0.5f);
    // One step is not black, and looks different from 30.
    EXPECT_GT(brightness(colourAt(rgb, width, 1, 1)), 0.0f);
    EXPECT_NE(colourAt(rgb, width, 1, 1), colourAt(rgb, width, 2, 1));
}

TEST(ChcrtDebugImageTest, BoundsColoursTheCellExtentOnALogRampBetweenTheImagesExtremes) {
    const uint32_t unbounded = 0xFFFFFFFFu;
    const auto bits = [](float t) { return std::bit_cast<uint32_t>(t); };
    // Bottom row: no ray, t = 1, t = 10, t = 100; top row: unbounded, t = 100, 1, 1.
    const std::vector<uint32_t> values = {0u, bits(1.0f), bits(10.0f), bits(100.0f),
                                          unbounded, bits(100.0f), bits(1.0f), bits(1.0f)};
    const std::vector<float> rgb = colorizeChcrtDebugImage(ChcrtDebugImage::Bounds, values, 4, 2);
    EXPECT_EQ(colourAt(rgb, 4, 0, 1), glm::vec3(0.0f));             // no ray: black
    EXPECT_EQ(colourAt(rgb, 4, 0, 0), glm::vec3(1.0f, 0.0f, 1.0f)); // unbounded: magenta
    EXPECT_EQ(colourAt(rgb, 4, 1, 1), glm::vec3(0.0f, 0.0f, 1.0f)); // the smallest extent: the ramp's blue end
    EXPECT_EQ(colourAt(rgb, 4, 3, 1), glm::vec3(1.0f, 0.0f, 0.0f)); // the largest: its red end
    // 10 lies halfway between 1 and 100 on the log ramp: the middle of the ramp, neither end.
    const glm::vec3 middle = colourAt(rgb, 4, 2, 1);
    EXPECT_NE(middle, colourAt(rgb, 4, 1, 1));
    EXPECT_NE(middle, colourAt(rgb, 4, 3, 1));
    EXPECT_GT(middle.g, 0.5f);
}

TEST(ChcrtDebugImageTest, OtherCountsKeepTheirLinearRampAndUseBit31AsACount) {
    // Overdraw/batches are plain counts: a value with bit 31 set is a (huge) count, not a flag.
    const std::vector<uint32_t> values = {0u, 1u, 0x80000000u};
    const std::vector<float> rgb = colorizeChcrtDebugImage(ChcrtDebugImage::Batches, values, 3, 1);
    EXPECT_NE(colourAt(rgb, 3, 2, 0), glm::vec3(1.0f, 0.0f, 1.0f));
    EXPECT_EQ(colourAt(rgb, 3, 0, 0), glm::vec3(0.0f));
    EXPECT_GT(colourAt(rgb, 3, 1, 0).b, 0.9f); // 1 of 2^31: the bottom of the linear ramp
}

} // namespace
} // namespace chcrt::test
