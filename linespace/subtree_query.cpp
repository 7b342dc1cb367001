#include "linespace/subtree_query.h"

#include "shaders/shared/intersect.h"

#include <stdexcept>

namespace chcrt::ls {

namespace {
// Two children pushed per inner node on a depth-first walk: depth + 1 entries suffice (depth < 64).
constexpr int kStackSize = 2 * CHCRT_MAX_BVH_DEPTH + 2;
} // namespace

bool subtreeOverlapsShaft(const Bvh& bvh, uint32_t node, const ShaftVolume& shaft) {
    uint32_t stack[kStackSize];
    int size = 0;
    stack[size++] = node;
    while (size > 0) {
        const BvhNodeGpu& n = bvh.nodes[stack[--size]];
        if (!shaftOverlapsBox(shaft, glm::dvec3(n.boundsMin), glm::dvec3(n.boundsMax))) {
            continue;
        }
        if (n.triCount != 0) {
            for (uint32_t i = 0; i < n.triCount; ++i) {
                const TriangleGpu& t = bvh.triangles[n.leftFirst + i];
                if (shaftOverlapsTriangle(shaft, t.v0, t.v1, t.v2)) {
                    return true;
                }
            }
        } else {
            stack[size++] = n.leftFirst + 1;
            stack[size++] = n.leftFirst;
        }
    }
    return false;
}

uint32_t subtreeClosestHit(const Bvh& bvh, uint32_t node, const glm::vec3& origin, const glm::vec3& direction,
                           float tmin, float tmax, float* tHit) {
    const glm::vec3 invDir = gpu::safeInverseDirection(direction);
    uint32_t stack[kStackSize];
    int size = 0;
    stack[size++] = node;
    uint32_t best = kNoTriangle, bestId = CHCRT_NO_HIT_ID;
    float bestT = tmax;
    while (size > 0) {
        const BvhNodeGpu& n = bvh.nodes[stack[--size]];
        if (!gpu::rayHitsAabb(gpu::intersectRayAabb(origin, invDir, n.boundsMin, n.boundsMax), tmin, bestT)) {
            continue;
        }
        if (n.triCount != 0) {
            for (uint32_t i = 0; i < n.triCount; ++i) {
                const TriangleGpu& t = bvh.triangles[n.leftFirst + i];
                const float th = gpu::intersectRayTriangle(origin, direction, t.v0, t.v1, t.v2).x;
                if (th >= tmin && th <= bestT && (th < bestT || best == kNoTriangle || t.originalId < bestId)) {
                    best = n.leftFirst + i;
                    bestId = t.originalId;
                    bestT = th;
                }
            }
        } else {
            stack[size++] = n.leftFirst + 1;
            stack[size++] = n.leftFirst;
        }
    }
    if (tHit != nullptr) {
        *tHit = bestT;
    }
    return best;
}

std::vector<TriangleRange> subtreeTriangleRanges(const Bvh& bvh) {
    std::vector<TriangleRange> ranges(bvh.nodes.size());
    // Post-order without recursion: visit a node after both children (second visit).
    std::vector<std::pair<uint32_t, bool>> stack{{0u, false}};
    while (!stack.empty()) {
        auto [node, childrenDone] = stack.back();
        stack.pop_back();
        const BvhNodeGpu& n = bvh.nodes[node];
        if (n.triCount != 0) {
            ranges[node] = {n.leftFirst, n.triCount};
        } else if (!childrenDone) {
            stack.push_back({node, true});
            stack.push_back({n.leftFirst + 1, false});
            stack.push_back({n.leftFirst, false});
        } else {
            const TriangleRange& a = ranges[n.leftFirst];
            const TriangleRange& b = ranges[n.leftFirst + 1];
            if (a.first + a.count != b.first && b.first + b.count != a.first) {
                throw std::logic_error("BVH subtree triangles are not contiguous");
            }
            ranges[node] = {std::min(a.first, b.first), a.count + b.count};
        }
    }
    return ranges;
}

} // namespace chcrt::ls
