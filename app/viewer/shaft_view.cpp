#include "app/viewer/shaft_view.h"

#include "linespace/binary_linespace.h"
#include "linespace/linespace_build.h"
#include "linespace/shaft_geometry.h"
#include "linespace/shaft_index.h"
#include "renderer/bvh/cpu_tracer.h"
#include "renderer/render/camera_math.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

namespace chcrt::app {
namespace {

// Does the subtree of `node` hold the triangle with original id `id`? (Iterative DFS; whole-tree cost at worst.)
bool subtreeHolds(const Bvh& bvh, uint32_t node, uint32_t id, uint32_t& triangles) {
    std::vector<uint32_t> stack = {node};
    bool found = false;
    triangles = 0;
    while (!stack.empty()) {
        const uint32_t i = stack.back();
        stack.pop_back();
        const BvhNodeGpu& nd = bvh.nodes[i];
        if (nd.triCount != 0) {
            triangles += nd.triCount;
            for (uint32_t t = nd.leftFirst; t < nd.leftFirst + nd.triCount; ++t) found |= bvh.triangles[t].originalId == id;
        } else {
            stack.push_back(nd.leftFirst);
            stack.push_back(nd.leftFirst + 1);
        }
    }
    return found;
}

// Slab test of the whole line (both directions): the entry and exit parameters, false when it misses the box.
bool lineBox(const Aabb& box, const glm::vec3& o, const glm::vec3& d, float& t0, float& t1) {
    t0 = -std::numeric_limits<float>::infinity();
    t1 = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0f) {
            if (o[a] < box.lower[a] || o[a] > box.upper[a]) return false;
            continue;
        }
        float ta = (box.lower[a] - o[a]) / d[a], tb = (box.upper[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

// Is point p (on the box's surface) within `tolerance` of one of the box's 12 edges?
bool nearEdge(const Aabb& box, const glm::vec3& p, float tolerance) {
    int onBoundary = 0;
    for (int a = 0; a < 3; ++a) {
        onBoundary += std::abs(p[a] - box.lower[a]) <= tolerance || std::abs(p[a] - box.upper[a]) <= tolerance;
    }
    return onBoundary >= 2;
}

} // namespace

glm::vec3 primaryRayDirection(const Camera& camera, int width, int height, float x, float y) {
    const CameraFrame f = makeCameraFrame(camera, width, height);
    const float ndcX = (x + 0.5f) / float(width) * 2.0f - 1.0f;
    const float ndcY = (float(height - 1) - y + 0.5f) / float(height) * 2.0f - 1.0f; // GL rows bottom to top
    return glm::normalize(f.forward + ndcX * f.right * f.tanHalfFovY * f.aspect + ndcY * f.up * f.tanHalfFovY);
}

std::optional<ShaftPick> pickLineSpaceNode(const Bvh& bvh, const Camera& camera, int width, int height, int x, int y,
                                           uint32_t n, uint32_t depth, uint32_t triangleThreshold) {
    if (x < 0 || y < 0 || x >= width || y >= height || bvh.nodes.empty()) return std::nullopt;
    Ray ray;
    ray.origin = camera.eye;
    ray.direction = primaryRayDirection(camera, width, height, float(x), float(y));
    ray.tmin = 0.0f;
    ray.tmax = std::numeric_limits<float>::max();
    const Hit hit = traceClosestCpu(bvh, ray);
    if (!hit.hit()) return std::nullopt;
    const auto start = std::chrono::steady_clock::now();
    ShaftPick pick;
    pick.pixelX = x;
    pick.pixelY = y;
    pick.triangleId = hit.triangleId;
    pick.n = n;
    pick.depth = depth;
    pick.triangleThreshold = triangleThreshold;
    // The cut of linespace_build.h covers the tree: exactly one Line Space node holds the triangle.
    const std::vector<uint32_t> cut = ls::selectLineSpaceNodes(bvh, depth, triangleThreshold);
    pick.spaceCount = uint32_t(cut.size());
    bool found = false;
    for (uint32_t s = 0; s < cut.size() && !found; ++s) {
        if (subtreeHolds(bvh, cut[s], hit.triangleId, pick.subtreeTriangles)) {
            found = true;
            pick.space = s;
            pick.bvhNode = cut[s];
        }
    }
    if (!found) return std::nullopt;
    const BvhNodeGpu& node = bvh.nodes[pick.bvhNode];
    pick.box = Aabb{node.boundsMin, node.boundsMax};
    // Same bits as buildLineSpaces (linespace_build.cpp: node bounds, scene dilation).
    pick.words = ls::computeBinaryLineSpace(bvh, pick.bvhNode, n, ls::shaftDilationForScene(bvh.rootBounds()));
    pick.shafts = ls::lsShaftCount(n, true);
    pick.pickedShaft = ls::shaftIndexForRay(pick.box, n, true, camera.eye, ray.direction);
    for (uint32_t w : pick.words) pick.filled += uint64_t(std::popcount(w));
    pick.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return pick;
}

uint64_t drawShafts(const ShaftPick& pick, const Camera& camera, int width, int height, std::vector<float>& rgb) {
    const CameraFrame f = makeCameraFrame(camera, width, height);
    const float pixelAngle = 2.0f * f.tanHalfFovY / float(height); // world size of a pixel at distance 1
    uint64_t inside = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            float* c = &rgb[(size_t(y) * width + x) * 3];
            const glm::vec3 d = primaryRayDirection(camera, width, height, float(x), float(y));
            float t0 = 0, t1 = 0;
            const uint32_t shaft = ls::shaftIndexForRay(pick.box, pick.n, true, camera.eye, d);
            // Only rays that reach the box (exit in front of the eye) can traverse the node.
            if (shaft == CHCRT_LS_NO_SHAFT || !lineBox(pick.box, camera.eye, d, t0, t1) || t1 <= 0.0f) {
                for (int k = 0; k < 3; ++k) c[k] *= 0.12f; // linear display values: about a third in sRGB
                continue;
            }
            ++inside;
            const bool filled = (pick.words[shaft / 32] >> (shaft % 32)) & 1u;
            const float tint[3] = {filled ? 1.0f : 0.1f, filled ? 0.15f : 0.9f, 0.1f};
            for (int k = 0; k < 3; ++k) c[k] = 0.45f * c[k] + 0.55f * tint[k];
            if (shaft == pick.pickedShaft) c[2] = 1.0f; // the rays sharing the picked ray's shaft
            // Edges: the entry (front) or exit (back) point lies on two faces within ~1.5 pixels.
            bool edge = false;
            for (float t : {t0, t1}) {
                if (t <= 0.0f) continue;
                edge |= nearEdge(pick.box, camera.eye + t * d, 1.5f * pixelAngle * t);
            }
            if (edge) c[0] = c[1] = c[2] = 1.0f;
        }
    }
    // The picked pixel: a small white cross.
    for (int k = -3; k <= 3; ++k) {
        for (auto [px, py] : {std::pair{pick.pixelX + k, pick.pixelY}, std::pair{pick.pixelX, pick.pixelY + k}}) {
            if (px < 0 || py < 0 || px >= width || py >= height) continue;
            float* c = &rgb[(size_t(py) * width + px) * 3];
            c[0] = c[1] = c[2] = 1.0f;
        }
    }
    return inside;
}

} // namespace chcrt::app
