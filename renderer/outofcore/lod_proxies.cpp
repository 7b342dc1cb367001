#include "renderer/outofcore/lod_proxies.h"

#include "renderer/outofcore/compact_subtree.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace chcrt::outofcore {
namespace {

// The subtree's triangle soup welded on positions: corner 3t + c of triangle t is vertex cornerVertex[3t + c];
// cornersOf lists each vertex's corners (CSR), for normals and representative ids.
struct WeldedSoup {
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> cornerVertex;
    std::vector<uint32_t> cornerBegin, corners; // corners of vertex v: corners[cornerBegin[v] .. cornerBegin[v + 1])
};

WeldedSoup weld(const std::vector<TriangleGpu>& triangles) {
    const size_t cornerCount = triangles.size() * 3;
    WeldedSoup w;
    weldCorners(triangles, w.positions, w.cornerVertex);
    const size_t unique = w.positions.size();
    w.cornerBegin.assign(unique + 1, 0);
    for (uint32_t v : w.cornerVertex) ++w.cornerBegin[v + 1];
    for (size_t v = 0; v < unique; ++v) w.cornerBegin[v + 1] += w.cornerBegin[v];
    w.corners.resize(cornerCount);
    std::vector<uint32_t> fill(w.cornerBegin.begin(), w.cornerBegin.end() - 1);
    for (uint32_t c = 0; c < cornerCount; ++c) w.corners[fill[w.cornerVertex[c]]++] = c;
    return w;
}

// One material's part of a level: welded vertex indices, 3 per triangle.
struct MaterialGroup {
    uint32_t material;
    std::vector<uint32_t> indices;
};

// Simplifies every group as far as a relative error of `targetError` allows (meshopt_simplify: edge collapses that
// keep the topology); returns the largest error reached (relative to the mesh extent).
float simplifyGroups(std::vector<MaterialGroup>& groups, const WeldedSoup& w, float targetError) {
    float worst = 0.0f;
    std::vector<uint32_t> out;
    for (MaterialGroup& g : groups) {
        out.resize(g.indices.size());
        float error = 0.0f;
        const size_t kept = meshopt_simplify(out.data(), g.indices.data(), g.indices.size(), &w.positions[0].x,
                                             w.positions.size(), sizeof(glm::vec3), 0, targetError, 0, &error);
        if (kept == 0) continue; // a group that would vanish keeps its finer triangles (a hole is worse)
        out.resize(kept);
        g.indices.swap(out);
        worst = std::max(worst, error);
    }
    return worst;
}

// Reduces every group to about `ratio` of its triangles by vertex clustering
// (meshopt_simplifySloppy; Rossignac & Borrel 1993), which merges disconnected parts; returns the largest error.
float clusterGroups(std::vector<MaterialGroup>& groups, const WeldedSoup& w, float ratio) {
    float worst = 0.0f;
    std::vector<uint32_t> out;
    for (MaterialGroup& g : groups) {
        const size_t target = std::max<size_t>(1, size_t(float(g.indices.size() / 3) * ratio)) * 3;
        if (g.indices.size() <= target) continue;
        out.resize(g.indices.size());
        float error = 0.0f;
        const size_t kept = meshopt_simplifySloppy(out.data(), g.indices.data(), g.indices.size(), &w.positions[0].x,
                                                   w.positions.size(), sizeof(glm::vec3), target, 1.0f, &error);
        if (kept == 0 || kept >= g.indices.size()) continue;
        out.resize(kept);
        g.indices.swap(out);
        worst = std::max(worst, error);
    }
    return worst;
}

// A kept level as a BVH blob: per proxy triangle a representative original id (same material, unique, touching
// one of its corners when possible) and corner normals; then the proxy's own SAH BVH, whose node order (root 0,
// children after their parent, siblings adjacent) is already the blob's local layout.
LodProxy makeProxy(const std::vector<MaterialGroup>& groups, const WeldedSoup& w, const std::vector<TriangleGpu>& source,
                   const std::vector<glm::vec3>& normals, const std::vector<glm::vec2>& texcoords, float errorWorld) {
    Scene scene;
    std::vector<uint32_t> representative;
    std::vector<uint8_t> used(source.size(), 0);
    // The source triangles of each material in order: the fallback when no triangle at the corners is free.
    std::vector<std::vector<uint32_t>> byMaterial;
    for (uint32_t t = 0; t < source.size(); ++t) {
        if (source[t].materialId >= byMaterial.size()) byMaterial.resize(source[t].materialId + 1);
        byMaterial[source[t].materialId].push_back(t);
    }
    std::vector<size_t> nextFree(byMaterial.size(), 0);
    uint32_t maxMaterial = 0;
    for (const MaterialGroup& g : groups) {
        for (size_t i = 0; i + 2 < g.indices.size(); i += 3) {
            const uint32_t v[3] = {g.indices[i], g.indices[i + 1], g.indices[i + 2]};
            uint32_t pick = UINT32_MAX;
            for (int c = 0; c < 3 && pick == UINT32_MAX; ++c) {
                for (uint32_t k = w.cornerBegin[v[c]]; k < w.cornerBegin[v[c] + 1]; ++k) {
                    const uint32_t t = w.corners[k] / 3;
                    if (!used[t] && source[t].materialId == g.material) {
                        pick = t;
                        break;
                    }
                }
            }
            if (pick == UINT32_MAX) { // simplification never adds triangles: a free one of this material is left
                const std::vector<uint32_t>& list = byMaterial[g.material];
                size_t& next = nextFree[g.material];
                while (next < list.size() && used[list[next]]) ++next;
                if (next == list.size()) throw std::logic_error("LOD proxy: more proxy triangles than source triangles");
                pick = list[next];
            }
            used[pick] = 1;
            representative.push_back(pick);
            const glm::vec3 p[3] = {w.positions[v[0]], w.positions[v[1]], w.positions[v[2]]};
            glm::vec3 face = glm::cross(p[1] - p[0], p[2] - p[0]);
            const float area = glm::length(face);
            face = area > 0.0f ? face / area : glm::vec3(0.0f, 1.0f, 0.0f);
            const auto base = uint32_t(scene.positions.size());
            for (int c = 0; c < 3; ++c) {
                // The original normal at this corner that agrees best with the proxy face (box edges stay sharp).
                glm::vec3 best = face;
                float bestDot = 0.7f; // below ~45 degrees of agreement the face normal is the better guess
                uint32_t uvCorner = w.corners[w.cornerBegin[v[c]]];
                for (uint32_t k = w.cornerBegin[v[c]]; k < w.cornerBegin[v[c] + 1]; ++k) {
                    const glm::vec3& n = normals[w.corners[k]];
                    const float d = glm::dot(n, face);
                    if (d > bestDot) bestDot = d, best = n, uvCorner = w.corners[k];
                }
                scene.positions.push_back(p[c]);
                scene.normals.push_back(best);
                if (!texcoords.empty()) scene.texcoords.push_back(texcoords[uvCorner]);
            }
            scene.triangles.emplace_back(base, base + 1, base + 2);
            scene.triangleMaterials.push_back(g.material);
            maxMaterial = std::max(maxMaterial, g.material);
        }
    }
    scene.materials.resize(maxMaterial + 1);
    BvhBuildOptions options;
    options.threads = 1; // thousands of small builds: threads would cost more than they save
    const Bvh bvh = buildBvh(scene, options);
    LodProxy proxy;
    proxy.errorWorld = errorWorld;
    proxy.nodes = bvh.nodes;
    proxy.triangles = bvh.triangles;
    for (TriangleGpu& t : proxy.triangles) {
        const uint32_t local = t.originalId; // index into scene.triangles
        for (int c = 0; c < 3; ++c) {
            proxy.normals.push_back(scene.normals[local * 3 + c]);
            if (!texcoords.empty()) proxy.texcoords.push_back(scene.texcoords[local * 3 + c]);
        }
        t.originalId = source[representative[local]].originalId;
        t.pad = 0;
    }
    return proxy;
}

} // namespace

std::vector<LodProxy> buildLodProxies(const std::vector<TriangleGpu>& triangles, const std::vector<glm::vec3>& normals,
                                      const std::vector<glm::vec2>& texcoords, uint32_t levels) {
    std::vector<LodProxy> proxies(levels);
    if (levels == 0 || triangles.empty()) return proxies;
    const WeldedSoup w = weld(triangles);
    const float scale = meshopt_simplifyScale(&w.positions[0].x, w.positions.size(), sizeof(glm::vec3));
    std::vector<MaterialGroup> groups;
    for (uint32_t t = 0; t < triangles.size(); ++t) {
        const uint32_t m = triangles[t].materialId;
        auto g = std::find_if(groups.begin(), groups.end(), [m](const MaterialGroup& x) { return x.material == m; });
        if (g == groups.end()) g = groups.insert(groups.end(), MaterialGroup{m, {}});
        for (int c = 0; c < 3; ++c) g->indices.push_back(w.cornerVertex[t * 3 + c]);
    }
    std::sort(groups.begin(), groups.end(), [](const MaterialGroup& a, const MaterialGroup& b) { return a.material < b.material; });
    auto countTriangles = [](const std::vector<MaterialGroup>& gs) {
        size_t n = 0;
        for (const MaterialGroup& g : gs) n += g.indices.size() / 3;
        return n;
    };
    size_t finer = triangles.size();
    float errorRelative = 0.0f;
    for (uint32_t level = 1; level <= levels; ++level) {
        // Each level from the previous one: cheaper than from the full subtree, and the errors add up to a bound.
        if (level < levels) {
            errorRelative += simplifyGroups(groups, w, kLodBaseRelativeError * std::pow(kLodErrorStep, float(level - 1)));
        } else {
            // The coarsest level: edge collapses that keep the topology stop at a few per cent of a city's triangles
            // (every facade detail is a closed part of its own), so it clusters vertices instead, towards
            // 1 / kLodCoarsestRatio of the subtree: metres of error, for views where a pixel covers metres.
            const size_t now = countTriangles(groups);
            const float ratio = float(triangles.size()) / float(kLodCoarsestRatio) / float(std::max<size_t>(1, now));
            if (ratio < 1.0f) errorRelative += clusterGroups(groups, w, ratio);
        }
        const size_t count = countTriangles(groups);
        if (count == 0 || float(count) > kLodMaxKeptShare * float(finer)) continue;
        proxies[level - 1] = makeProxy(groups, w, triangles, normals, texcoords, errorRelative * scale);
        finer = count;
    }
    // Collapses move vertices onto existing ones: a proxy cannot leave the subtree's box (the culling hierarchy's
    // boxes bound it, CHC+RT §5.1). Checked, since the tracer's correctness relies on it.
    Aabb box;
    for (const TriangleGpu& t : triangles) box.grow(t.v0), box.grow(t.v1), box.grow(t.v2);
    for (const LodProxy& p : proxies) {
        for (const TriangleGpu& t : p.triangles) {
            for (const glm::vec3& v : {t.v0, t.v1, t.v2}) {
                if (glm::any(glm::lessThan(v, box.lower)) || glm::any(glm::greaterThan(v, box.upper))) {
                    throw std::logic_error("LOD proxy vertex outside its subtree's bounds");
                }
            }
        }
    }
    return proxies;
}

} // namespace chcrt::outofcore
