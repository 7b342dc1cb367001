// The shafts view's CPU side (app/viewer/shaft_view.h): the picked node is the Line Space node of the build's
// cut that holds the pixel's primary hit, its bits are exactly those of buildLineSpaces with the same N/D/T, and
// the overlay colours each pixel by the bit of its ray's shaft.
#include "app/viewer/shaft_view.h"
#include "linespace/linespace_build.h"
#include "linespace/shaft_index.h"
#include "renderer/bvh/cpu_tracer.h"
#include "renderer/scene/procedural/procedural.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace chcrt::app {
namespace {

struct City {
    Scene scene;
    Bvh bvh;
    Camera camera;
};

const City& city() {
    static const City c = [] {
        City r;
        ProceduralSpec spec;
        EXPECT_TRUE(parseProceduralSpec("city:5k", spec));
        r.scene = generateProceduralScene(spec);
        r.bvh = buildBvh(r.scene);
        r.camera = proceduralNearPath(spec).cameraAtFrame(0);
        return r;
    }();
    return c;
}

TEST(ShaftView, PickedNodeHoldsTheHitAndHasTheBuildsBits) {
    const City& c = city();
    constexpr int w = 64, h = 36;
    const uint32_t n = 4, depth = 6, t = 8;
    ls::LineSpaceParams params;
    params.n = n;
    params.depth = depth;
    params.triangleThreshold = t;
    params.candidates = false;
    const ls::LineSpaces spaces = ls::buildLineSpaces(c.bvh, params);
    int picked = 0;
    for (auto [x, y] : {std::pair{32, 18}, std::pair{4, 32}, std::pair{60, 30}}) {
        const auto pick = pickLineSpaceNode(c.bvh, c.camera, w, h, x, y, n, depth, t);
        Ray ray;
        ray.origin = c.camera.eye;
        ray.direction = primaryRayDirection(c.camera, w, h, float(x), float(y));
        ray.tmax = 1e30f;
        const Hit hit = traceClosestCpu(c.bvh, ray);
        ASSERT_EQ(pick.has_value(), hit.hit());
        if (!pick) continue;
        ++picked;
        EXPECT_EQ(pick->triangleId, hit.triangleId);
        ASSERT_LT(pick->space, spaces.bvhNodes.size());
        EXPECT_EQ(pick->spaceCount, spaces.bvhNodes.size());
        EXPECT_EQ(spaces.bvhNodes[pick->space], pick->bvhNode);
        const uint32_t words = spaces.binaryWordsPerSpace();
        const std::vector<uint32_t> built(spaces.binaryWords.begin() + size_t(pick->space) * words,
                                          spaces.binaryWords.begin() + size_t(pick->space + 1) * words);
        EXPECT_EQ(pick->words, built);
        EXPECT_EQ(pick->shafts, ls::lsShaftCount(n, true));
        EXPECT_GT(pick->filled, 0u);
        // The hit point lies in the node's box (the node's subtree holds the triangle).
        const glm::vec3 p = ray.origin + hit.t * ray.direction;
        const glm::vec3 slack(1e-3f * c.bvh.rootBounds().diagonal());
        EXPECT_TRUE(glm::all(glm::lessThanEqual(pick->box.lower - slack, p)) &&
                    glm::all(glm::lessThanEqual(p, pick->box.upper + slack)));

        // Overlay: over a grey image, pixels whose line meets the box are tinted by their shaft's bit.
        std::vector<float> rgb(size_t(w) * h * 3, 0.5f);
        const uint64_t inside = drawShafts(*pick, c.camera, w, h, rgb);
        EXPECT_GT(inside, 0u);
        uint64_t greens = 0, reds = 0, checked = 0;
        for (int py = 0; py < h; ++py) {
            for (int px = 0; px < w; ++px) {
                const float* col = &rgb[(size_t(py) * w + px) * 3];
                if (col[0] == col[1]) continue; // edges, the cross, darkened pixels (rays not reaching the box)
                const uint32_t shaft = ls::shaftIndexForRay(pick->box, n, true, c.camera.eye,
                                                            primaryRayDirection(c.camera, w, h, float(px), float(py)));
                if (shaft == CHCRT_LS_NO_SHAFT) continue;
                const bool filled = (pick->words[shaft / 32] >> (shaft % 32)) & 1u;
                EXPECT_EQ(col[0] > col[1], filled) << px << "," << py;
                (filled ? reds : greens) += 1;
                ++checked;
            }
        }
        EXPECT_GT(checked, 0u);
    }
    EXPECT_GE(picked, 2);
    // Off the image or on nothing: no pick.
    EXPECT_FALSE(pickLineSpaceNode(c.bvh, c.camera, w, h, w, 0, n, depth, t).has_value());
}

} // namespace
} // namespace chcrt::app
