// The residency and lod views' colouring (app/viewer/residency_view.h): pixels are classified by whether their
// primary hit's subtree was resident before the frame (or by the level it was traced at), counted, tinted, darkened
// on subtree boundaries, and the per-pixel subtree image (GL rows, bottom first) lines up with the shaded image (rows
// top first).
#include "app/viewer/residency_view.h"

#include <gtest/gtest.h>

namespace chcrt::app {
namespace {

bool greenish(const float* p) { return p[1] > p[0] + 0.2f && p[1] > p[2] + 0.2f; }
bool orangeish(const float* p) { return p[0] > p[1] + 0.2f && p[0] > p[2] + 0.2f; }

TEST(ResidencyView, ClassifiesCountsAndTintsPixels) {
    const int w = 4, h = 2;
    // GL order: the bottom row first. Bottom row: subtree 3 (resident) x2, subtree 7 (uploaded) x2;
    // top row: no hit, subtree 3, subtree 3, subtree 7.
    const std::vector<uint32_t> subtrees = {4, 4, 8, 8, 0, 4, 4, 8};
    std::vector<uint8_t> resident(8, 0);
    resident[3] = 1;
    std::vector<float> rgb(size_t(w) * h * 3, 1.0f); // a white shaded frame
    const ResidencyCounts c = colourResidency(subtrees, resident, w, h, rgb);
    EXPECT_EQ(c.hitPixels, 7u);
    EXPECT_EQ(c.residentPixels, 4u);
    EXPECT_EQ(c.uploadedPixels, 3u);
    EXPECT_EQ(c.visibleSubtrees, 2u);
    const auto px = [&](int x, int yFromTop) { return &rgb[(size_t(yFromTop) * w + x) * 3]; };
    // Top row (rgb row 0) is the GL row 1: no hit, then 3, 3, 7.
    EXPECT_FALSE(greenish(px(0, 0)) || orangeish(px(0, 0)));
    EXPECT_NEAR(px(0, 0)[0], px(0, 0)[1], 1e-6f); // grey
    EXPECT_TRUE(greenish(px(1, 0)));
    EXPECT_TRUE(orangeish(px(3, 0)));
    // Bottom row: 3, 3, 7, 7.
    EXPECT_TRUE(greenish(px(0, 1)));
    EXPECT_TRUE(orangeish(px(2, 1)));
    // (2, top) lies on the boundary with subtree 7 to its right: darker than (1, bottom), which is interior of 3
    // (its right neighbour is 3, it has no row below).
    EXPECT_LT(px(2, 0)[1], px(0, 1)[1] * 0.5f);
    // Subtrees past the residency vector count as uploaded; a size mismatch leaves the image untouched.
    std::vector<float> same(size_t(w) * h * 3, 0.5f);
    EXPECT_EQ(colourResidency(subtrees, {}, w, h, same).uploadedPixels, 7u);
    std::vector<float> untouched(3, 0.5f);
    EXPECT_EQ(colourResidency(subtrees, resident, w, h, untouched).hitPixels, 0u);
    EXPECT_EQ(untouched[0], 0.5f);
}

TEST(ResidencyView, DarkerShadingGivesDarkerTints) {
    const std::vector<uint32_t> subtrees = {1, 1};
    const std::vector<uint8_t> resident = {1};
    std::vector<float> rgb = {1, 1, 1, 0.1f, 0.1f, 0.1f};
    colourResidency(subtrees, resident, 2, 1, rgb);
    EXPECT_TRUE(greenish(&rgb[0]));
    EXPECT_GT(rgb[1], rgb[4]); // the bright pixel's tint is brighter
}

TEST(LodView, CountsAndTintsPixelsByTheirSubtreesLevel) {
    const int w = 4, h = 2;
    // GL order, bottom row first: subtrees 0 (level 0) x2, 1 (level 1), 2 (level 3); top: no hit, 2, 5 (past the
    // levels: the last level), 1.
    const std::vector<uint32_t> subtrees = {1, 1, 2, 3, 0, 3, 6, 2};
    const std::vector<uint8_t> levels = {0, 1, 3};
    std::vector<float> rgb(size_t(w) * h * 3, 1.0f);
    const LodCounts c = colourLod(subtrees, levels, w, h, rgb);
    EXPECT_EQ(c.hitPixels, 7u);
    EXPECT_EQ(c.visibleSubtrees, 4u);
    EXPECT_EQ(c.pixelsPerLevel[0], 2u);
    EXPECT_EQ(c.pixelsPerLevel[1], 2u);
    EXPECT_EQ(c.pixelsPerLevel[2], 0u);
    EXPECT_EQ(c.pixelsPerLevel[3], 2u);
    EXPECT_EQ(c.pixelsPerLevel[kLodViewLevels - 1], 1u);
    uint64_t sum = 0;
    for (uint64_t n : c.pixelsPerLevel) sum += n;
    EXPECT_EQ(sum, c.hitPixels);
    const auto px = [&](int x, int yFromTop) { return &rgb[(size_t(yFromTop) * w + x) * 3]; };
    // Every pixel here but (0, bottom) lies on a subtree boundary (darkened): compare channels by ratio.
    const auto dominant = [](const float* p, int ch) {
        return p[ch] > 1.5f * p[(ch + 1) % 3] && p[ch] > 1.5f * p[(ch + 2) % 3];
    };
    EXPECT_TRUE(dominant(px(2, 1), 1));                       // level 1 is green
    EXPECT_TRUE(dominant(px(3, 0), 1));
    EXPECT_TRUE(dominant(px(3, 1), 0));                       // level 3 is orange
    EXPECT_GT(px(0, 1)[2], px(0, 1)[0]);                      // level 0 is grey-blue
    EXPECT_NEAR(px(0, 0)[0], px(0, 0)[1], 1e-6f);            // no hit: grey
    std::vector<float> untouched(3, 0.5f);
    EXPECT_EQ(colourLod(subtrees, levels, w, h, untouched).hitPixels, 0u);
    EXPECT_EQ(untouched[0], 0.5f);
}

} // namespace
} // namespace chcrt::app
