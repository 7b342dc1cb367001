#include "tests/bvh/bvh_test_scenes.h"

#include "shaders/shared/intersect.h"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace chcrt::test {

namespace {

glm::vec3 randomIn(std::mt19937& rng, const glm::vec3& lower, const glm::vec3& upper) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    return lower + (upper - lower) * glm::vec3(unit(rng), unit(rng), unit(rng));
}

void addSmallTriangle(Scene& scene, std::mt19937& rng, const glm::vec3& centre, float size) {
    const glm::vec3 half(0.5f * size);
    addTriangle(scene, centre + randomIn(rng, -half, half), centre + randomIn(rng, -half, half),
                centre + randomIn(rng, -half, half));
}

Scene makeEmptyScene(const std::string& name) {
    Scene scene;
    scene.name = name;
    scene.materials.push_back(Material{});
    return scene;
}

bool sameVec(const glm::vec3& a, const glm::vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// ostringstream rather than string operator+: GCC 12 at -O3 emits a false -Wrestrict for the latter.
std::string describe(const glm::vec3& v) {
    std::ostringstream text;
    text.precision(9);
    text << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return text.str();
}

} // namespace

void addTriangle(Scene& scene, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const auto first = uint32_t(scene.positions.size());
    scene.positions.insert(scene.positions.end(), {a, b, c});
    scene.triangles.emplace_back(first, first + 1, first + 2);
    scene.triangleMaterials.push_back(0);
}

Scene makeTriangleSoup(uint32_t count, uint32_t seed, float extent, float size) {
    Scene scene = makeEmptyScene("soup");
    std::mt19937 rng(seed);
    scene.positions.reserve(3 * size_t(count));
    scene.triangles.reserve(count);
    scene.triangleMaterials.reserve(count);
    for (uint32_t i = 0; i < count; ++i) {
        addSmallTriangle(scene, rng, randomIn(rng, glm::vec3(-extent), glm::vec3(extent)), size);
    }
    return scene;
}

Scene makeClusteredSoup(uint32_t count, uint32_t clusters, uint32_t seed) {
    Scene scene = makeEmptyScene("clustered");
    std::mt19937 rng(seed);
    std::vector<glm::vec3> centres;
    for (uint32_t c = 0; c < clusters; ++c) {
        centres.push_back(randomIn(rng, glm::vec3(-1000.0f), glm::vec3(1000.0f)));
    }
    std::normal_distribution<float> spread(0.0f, 5.0f);
    for (uint32_t i = 0; i < count; ++i) {
        const glm::vec3 offset(spread(rng), spread(rng), spread(rng));
        addSmallTriangle(scene, rng, centres[i % clusters] + offset, 0.5f);
    }
    return scene;
}

Scene makeHeightfield(uint32_t cells, uint32_t seed) {
    Scene scene = makeEmptyScene("heightfield");
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-0.05f, 0.05f);
    const uint32_t side = cells + 1;
    scene.positions.reserve(size_t(side) * side);
    for (uint32_t z = 0; z < side; ++z) {
        for (uint32_t x = 0; x < side; ++x) {
            const float y = 2.0f * std::sin(0.05f * float(x)) * std::cos(0.07f * float(z)) + noise(rng);
            scene.positions.emplace_back(float(x), y, float(z));
        }
    }
    scene.triangles.reserve(2 * size_t(cells) * cells);
    for (uint32_t z = 0; z < cells; ++z) {
        for (uint32_t x = 0; x < cells; ++x) {
            const uint32_t i = z * side + x;
            scene.triangles.emplace_back(i, i + 1, i + side);
            scene.triangles.emplace_back(i + 1, i + side + 1, i + side);
        }
    }
    scene.triangleMaterials.assign(scene.triangles.size(), 0);
    return scene;
}

Scene makeExponentialRow(uint32_t count) {
    Scene scene = makeEmptyScene("exponential");
    for (uint32_t i = 0; i < count; ++i) {
        // From 2^-120 to 2^120: the widest span float allows, so the peeling continues for as many levels as
        // possible (each binned split can only remove one factor binCount of the remaining range).
        const float x = std::exp2(-120.0f + 240.0f * float(i) / float(std::max(count, 2u) - 1));
        const float s = 0.25f * x; // size proportional to position, so no triangle degenerates in float
        addTriangle(scene, glm::vec3(x, 0.0f, 0.0f), glm::vec3(x + s, s, 0.0f), glm::vec3(x, s, s));
    }
    return scene;
}

testing::AssertionResult checkBvhInvariants(const Bvh& bvh, const Scene& scene, uint32_t maxLeafTriangles,
                                            bool checkBounds) {
    const size_t triangleCount = scene.triangles.size();
    if (bvh.nodes.empty() || bvh.triangles.size() != triangleCount) {
        return testing::AssertionFailure() << "sizes: " << bvh.nodes.size() << " nodes, " << bvh.triangles.size()
                                           << " triangles for " << triangleCount;
    }
    std::vector<uint8_t> nodeSeen(bvh.nodes.size(), 0);
    std::vector<uint8_t> slotCovered(triangleCount, 0);
    std::vector<uint8_t> idSeen(triangleCount, 0);
    struct Entry {
        uint32_t node;
        uint32_t depth;
    };
    std::vector<Entry> stack{{0, 0}};
    while (!stack.empty()) {
        const Entry entry = stack.back();
        stack.pop_back();
        if (entry.node >= bvh.nodes.size() || nodeSeen[entry.node]) {
            return testing::AssertionFailure() << "node " << entry.node << " out of range or reached twice";
        }
        nodeSeen[entry.node] = 1;
        if (entry.depth >= CHCRT_MAX_BVH_DEPTH) {
            return testing::AssertionFailure() << "node " << entry.node << " at depth " << entry.depth;
        }
        const BvhNodeGpu& node = bvh.nodes[entry.node];
        Aabb expected;
        if (node.triCount != 0) {
            if (node.triCount > maxLeafTriangles || size_t(node.leftFirst) + node.triCount > triangleCount) {
                return testing::AssertionFailure() << "leaf " << entry.node << " holds [" << node.leftFirst << ", +"
                                                   << node.triCount << ")";
            }
            for (uint32_t i = node.leftFirst; i < node.leftFirst + node.triCount; ++i) {
                const TriangleGpu& tri = bvh.triangles[i];
                if (slotCovered[i] || tri.originalId >= triangleCount || idSeen[tri.originalId]) {
                    return testing::AssertionFailure() << "triangle slot " << i << " (id " << tri.originalId
                                                       << ") in two leaves, or id out of range or repeated";
                }
                slotCovered[i] = 1;
                idSeen[tri.originalId] = 1;
                const glm::uvec3 t = scene.triangles[tri.originalId];
                const bool sameVertices = sameVec(tri.v0, scene.positions[t.x]) && sameVec(tri.v1, scene.positions[t.y]) &&
                                          sameVec(tri.v2, scene.positions[t.z]);
                if ((checkBounds && !sameVertices) || tri.materialId != scene.triangleMaterials[tri.originalId]) {
                    return testing::AssertionFailure() << "triangle slot " << i << " does not match scene triangle "
                                                       << tri.originalId;
                }
                expected.grow(tri.v0);
                expected.grow(tri.v1);
                expected.grow(tri.v2);
            }
        } else {
            if (node.leftFirst == 0 || size_t(node.leftFirst) + 1 >= bvh.nodes.size()) {
                return testing::AssertionFailure() << "inner node " << entry.node << " has children at " << node.leftFirst;
            }
            for (uint32_t c = node.leftFirst; c <= node.leftFirst + 1; ++c) {
                const BvhNodeGpu& child = bvh.nodes[c];
                const Aabb childBox{child.boundsMin, child.boundsMax};
                if (checkBounds && !Aabb{node.boundsMin, node.boundsMax}.contains(childBox)) {
                    return testing::AssertionFailure() << "child " << c << " sticks out of node " << entry.node;
                }
                expected.grow(childBox);
                stack.push_back({c, entry.depth + 1});
            }
        }
        if (checkBounds && !(sameVec(expected.lower, node.boundsMin) && sameVec(expected.upper, node.boundsMax))) {
            return testing::AssertionFailure() << "node " << entry.node << " bounds " << describe(node.boundsMin) << " - "
                                               << describe(node.boundsMax) << " are not the union "
                                               << describe(expected.lower) << " - " << describe(expected.upper);
        }
    }
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        if (!nodeSeen[i]) {
            return testing::AssertionFailure() << "node " << i << " unreachable";
        }
    }
    for (size_t i = 0; i < triangleCount; ++i) {
        if (!slotCovered[i] || !idSeen[i]) {
            return testing::AssertionFailure() << "triangle slot/id " << i << " not in any leaf";
        }
    }
    return testing::AssertionSuccess();
}

Hit traceBruteForce(const Scene& scene, const Ray& ray, bool anyHit) {
    Hit best;
    if (!(ray.tmax > ray.tmin) || ray.tmax == 0.0f) {
        return best;
    }
    for (uint32_t id = 0; id < scene.triangles.size(); ++id) {
        const glm::uvec3 t = scene.triangles[id];
        const glm::vec3 tuv = gpu::intersectRayTriangle(ray.origin, ray.direction, scene.positions[t.x],
                                                        scene.positions[t.y], scene.positions[t.z]);
        // Ids ascend, so an equal t never replaces the earlier (lower) id: the tie-break holds by order.
        if (tuv.x >= ray.tmin && tuv.x <= ray.tmax && tuv.x < best.t) {
            best = Hit{tuv.x, id, tuv.y, tuv.z};
            if (anyHit) {
                return best;
            }
        }
    }
    return best;
}

Ray makeRandomRay(std::mt19937& rng, const Aabb& box, float margin) {
    const glm::vec3 grow(margin * box.diagonal());
    const glm::vec3 origin = randomIn(rng, box.lower - grow, box.upper + grow);
    const glm::vec3 target = randomIn(rng, box.lower, box.upper);
    Ray ray;
    ray.origin = origin;
    ray.direction = glm::normalize(target - origin);
    ray.tmin = 0.0f;
    ray.tmax = 1e30f;
    return ray;
}

} // namespace chcrt::test
