// The ray-distance -> depth mapping of the generalized occlusion queries (CHC+RT §4.1) must be conservative:
// entry <= hit t implies depth(entry) <= depth(hit t), so the GL_LEQUAL test never culls a box that could
// hold a hit at the current nearest t (entry equal to the hit, rays starting inside the box, rounding).
#include "shaders/shared/culling_layout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace chcrt {
namespace {

using gpu::depthFromDistance;

TEST(DepthMapping, ScaleIsExactlyTwoToTheMinus64) {
    EXPECT_EQ(float(CHCRT_CULLING_DEPTH_SCALE), std::ldexp(1.0f, -64));
}

TEST(DepthMapping, MonotoneOnRandomPairs) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> exponent(-30.0f, 40.0f);
    std::uniform_int_distribution<int> ulps(0, 4);
    for (int i = 0; i < 200000; ++i) {
        float a = std::exp2(exponent(rng));
        float b = a;
        for (int k = ulps(rng); k > 0; --k) b = std::nextafter(b, std::numeric_limits<float>::infinity());
        if (i % 3 == 0) b = std::exp2(exponent(rng));
        if (i % 7 == 0) a = -a; // entry behind the origin (ray starts inside the box)
        const float entry = std::min(a, b), hit = std::max(a, b);
        ASSERT_LE(depthFromDistance(entry), depthFromDistance(hit)) << entry << " " << hit;
    }
}

TEST(DepthMapping, StrictlyMonotoneInTheSceneRangeAndClampedOutside) {
    // Distinct distances stay distinct (no lost culling from rounding) for every normal t in [2^-62, 2^64).
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> exponent(-60.0f, 63.0f);
    for (int i = 0; i < 100000; ++i) {
        const float t = std::exp2(exponent(rng));
        const float next = std::nextafter(t, std::numeric_limits<float>::infinity());
        ASSERT_LT(depthFromDistance(t), depthFromDistance(next));
    }
    EXPECT_EQ(depthFromDistance(-5.0f), 0.0f);
    EXPECT_EQ(depthFromDistance(0.0f), 0.0f);
    EXPECT_EQ(depthFromDistance(3.402823466e+38f), 1.0f);
    EXPECT_EQ(depthFromDistance(std::numeric_limits<float>::infinity()), 1.0f);
    EXPECT_EQ(depthFromDistance(1.0f), std::ldexp(1.0f, -64));
}

} // namespace
} // namespace chcrt
