// The prefetch policy's choice (culling/outofcore/subtree_prefetch.h) on a hand-made hierarchy: boxes against a
// camera's frustum, the front's subtrees below an upper node, ranking nearest first, subtrees that need no read.
#include "culling/outofcore/subtree_prefetch.h"

#include <gtest/gtest.h>

namespace chcrt {
namespace {

Camera lookingAlongZ() {
    Camera c;
    c.eye = glm::vec3(0.0f);
    c.target = glm::vec3(0.0f, 0.0f, 1.0f); // forward +z, 90° vertical field of view
    c.fovYDegrees = 90.0f;
    return c;
}

TEST(SubtreePrefetch, BoxesAgainstTheFrustum) {
    const CameraFrame f = makeCameraFrame(lookingAlongZ(), 100, 100);
    const auto meets = [&](glm::vec3 lo, glm::vec3 hi) { return outofcore::boxMeetsFrustum(f, lo, hi); };
    EXPECT_TRUE(meets({-1, -1, 5}, {1, 1, 6}));        // straight ahead
    EXPECT_FALSE(meets({-1, -1, -6}, {1, 1, -5}));     // behind
    EXPECT_FALSE(meets({8, -1, 5}, {9, 1, 6}));        // right of the 45° half angle (x > z)
    EXPECT_TRUE(meets({4, -1, 5}, {9, 1, 6}));         // straddles the right plane
    EXPECT_FALSE(meets({-1, 8, 5}, {1, 9, 6}));        // above
    EXPECT_TRUE(meets({-1, -1, -1}, {1, 1, 1}));       // around the eye
    const CameraFrame wide = makeCameraFrame(lookingAlongZ(), 200, 100); // aspect 2: x up to 2z
    EXPECT_TRUE(outofcore::boxMeetsFrustum(wide, {8, -1, 5}, {9, 1, 6}));
}

// Root 0 -> {1, 2}, inner node 1 -> {3, 4}; the terminal nodes 3, 4 and 2 hold subtrees 0 (far ahead), 1 (near
// ahead) and 2 (behind the camera).
CullingHierarchy threeSubtrees() {
    CullingHierarchy h;
    h.nodes.resize(5);
    h.nodes[0].firstChild = 1;
    h.nodes[1].firstChild = 3;
    const auto terminal = [&](uint32_t node, uint32_t subtree, float z) {
        h.nodes[node].subtree = subtree;
        h.nodes[node].boxMin = glm::vec3(-1, -1, z);
        h.nodes[node].boxMax = glm::vec3(1, 1, z + 1);
    };
    terminal(3, 0, 20.0f); // subtree 0: far ahead
    terminal(4, 1, 5.0f);  // subtree 1: near ahead
    terminal(2, 2, -10.0f); // subtree 2: behind the camera
    h.nodes[1].boxMin = glm::vec3(-1, -1, 5);
    h.nodes[1].boxMax = glm::vec3(1, 1, 21);
    h.nodes[0].boxMin = glm::vec3(-1, -1, -10);
    h.nodes[0].boxMax = glm::vec3(1, 1, 21);
    h.subtrees = {{3, 1, 10, 0}, {4, 1, 10, 0}, {2, 1, 10, 0}};
    return h;
}

TEST(SubtreePrefetch, ChoosesTheFrontAndTheLookAheadNearestFirst) {
    const CullingHierarchy h = threeSubtrees();
    outofcore::PrefetchRequest request;
    request.current = lookingAlongZ();
    request.width = request.height = 64;

    // Nothing given: nothing chosen.
    EXPECT_TRUE(outofcore::choosePrefetchSubtrees(h, request, nullptr).empty());

    // The front's termination roots (nodes 3 and 4: subtrees 0 and 1), nearest first; its upper node 1 adds nothing.
    const std::vector<uint32_t> front = {1, 3, 4, 3};
    request.frontNodes = front;
    EXPECT_EQ(outofcore::choosePrefetchSubtrees(h, request, nullptr), (std::vector<uint32_t>{1, 0}));
    const std::vector<uint32_t> upperOnly = {1, 0};
    request.frontNodes = upperOnly;
    EXPECT_TRUE(outofcore::choosePrefetchSubtrees(h, request, nullptr).empty());
    request.frontNodes = front;

    // A next camera that sees what the current one sees adds only what the current frame asked for (a cache smaller
    // than the frame's working set evicted it): a subtree in the current frustum that it did not ask for is hidden,
    // and the front covers what turns visible.
    const std::vector<Camera> same = {lookingAlongZ()};
    request.frontNodes = {};
    request.next = same;
    EXPECT_TRUE(outofcore::choosePrefetchSubtrees(h, request, nullptr).empty());
    request.usedNow = [](uint32_t s) { return s == 0; };
    EXPECT_EQ(outofcore::choosePrefetchSubtrees(h, request, nullptr), (std::vector<uint32_t>{0}));
    request.usedNow = nullptr;
    request.frontNodes = front;

    // A next camera turned around sees only subtree 2, which enters the view; it is ranked from its own eye
    // (distance 9 < 20 of subtree 0).
    Camera back = lookingAlongZ();
    back.target = glm::vec3(0, 0, -1);
    const std::vector<Camera> next = {back};
    request.next = next;
    EXPECT_EQ(outofcore::choosePrefetchSubtrees(h, request, nullptr), (std::vector<uint32_t>{1, 2, 0}));

    // Subtrees that need no read (resident in the GPU cache) are left out.
    EXPECT_EQ(outofcore::choosePrefetchSubtrees(h, request, [](uint32_t s) { return s == 1; }),
              (std::vector<uint32_t>{2, 0}));
}

} // namespace
} // namespace chcrt
