#include "renderer/scene/procedural/mesh_builder.h"

#include <cassert>
#include <cmath>

namespace chcrt::procedural {

void MeshBuilder::reserve(uint64_t triangles, uint64_t vertices) {
    scene_.triangles.reserve(scene_.triangles.size() + triangles);
    scene_.triangleMaterials.reserve(scene_.triangleMaterials.size() + triangles);
    scene_.positions.reserve(scene_.positions.size() + vertices);
    scene_.normals.reserve(scene_.normals.size() + vertices);
}

uint32_t MeshBuilder::addMaterial(const std::string& name, const glm::vec3& linearColor) {
    Material material;
    material.baseColorFactor = glm::vec4(linearColor, 1.0f);
    material.name = name;
    scene_.materials.push_back(material);
    return uint32_t(scene_.materials.size() - 1);
}

void MeshBuilder::addQuad(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3,
                          uint32_t material) {
    const glm::vec3 normal = glm::normalize(glm::cross(p1 - p0, p3 - p0));
    const uint32_t base = uint32_t(scene_.positions.size());
    scene_.positions.push_back(p0);
    scene_.positions.push_back(p1);
    scene_.positions.push_back(p2);
    scene_.positions.push_back(p3);
    for (int i = 0; i < 4; ++i) scene_.normals.push_back(normal);
    scene_.triangles.emplace_back(base, base + 1, base + 2);
    scene_.triangles.emplace_back(base, base + 2, base + 3);
    scene_.triangleMaterials.push_back(material);
    scene_.triangleMaterials.push_back(material);
    reportProgress();
}

// Every 64k triangles: often enough for a smooth bar, rare enough to cost nothing per primitive.
void MeshBuilder::reportProgress() {
    const uint64_t triangles = scene_.triangles.size();
    if (triangles < nextReport_) return;
    progress_.update(triangles);
    nextReport_ = triangles + (uint64_t(1) << 16);
}

void MeshBuilder::addBox(const glm::vec3& lower, const glm::vec3& upper, uint32_t material, uint32_t faces) {
    assert(lower.x < upper.x && lower.y < upper.y && lower.z < upper.z);
    const glm::vec3 center = 0.5f * (lower + upper);
    const glm::vec3 half = 0.5f * (upper - lower);
    const glm::vec3 hx(half.x, 0.0f, 0.0f), hy(0.0f, half.y, 0.0f), hz(0.0f, 0.0f, half.z);
    // Each face: outward half-axis n and tangents (s, t) with cross(s, t) along n, so the corner order
    // n-s-t, n+s-t, n+s+t, n-s+t is counter-clockwise seen from outside.
    struct Face { uint32_t bit; glm::vec3 n, s, t; };
    const Face table[6] = {
        {kPosX, hx, hy, hz},  {kNegX, -hx, hz, hy}, {kPosY, hy, hz, hx},
        {kNegY, -hy, hx, hz}, {kPosZ, hz, hx, hy},  {kNegZ, -hz, hy, hx},
    };
    for (const Face& f : table) {
        if (!(faces & f.bit)) continue;
        const glm::vec3 c = center + f.n;
        addQuad(c - f.s - f.t, c + f.s - f.t, c + f.s + f.t, c - f.s + f.t, material);
    }
}

void MeshBuilder::addOrientedBox(const glm::vec3& center, const glm::vec3& halfX, const glm::vec3& halfY,
                                 const glm::vec3& halfZ, uint32_t material) {
    const glm::vec3 table[6][3] = {
        {halfX, halfY, halfZ},  {-halfX, halfZ, halfY}, {halfY, halfZ, halfX},
        {-halfY, halfX, halfZ}, {halfZ, halfX, halfY},  {-halfZ, halfY, halfX},
    };
    for (const auto& f : table) {
        const glm::vec3 c = center + f[0];
        addQuad(c - f[1] - f[2], c + f[1] - f[2], c + f[1] + f[2], c - f[1] + f[2], material);
    }
}

const std::vector<glm::vec2>& MeshBuilder::circle(uint32_t segments) {
    if (circles_.size() <= segments) circles_.resize(segments + 1);
    std::vector<glm::vec2>& table = circles_[segments];
    if (table.empty()) {
        table.resize(segments + 1);
        for (uint32_t i = 0; i <= segments; ++i) {
            const double angle = 2.0 * 3.14159265358979323846 * double(i % segments) / double(segments);
            table[i] = glm::vec2(float(std::cos(angle)), float(std::sin(angle)));
        }
    }
    return table;
}

void MeshBuilder::addCylinder(const glm::vec3& a, const glm::vec3& b, float radius, uint32_t segments,
                              uint32_t material, bool caps) {
    assert(segments >= 3 && radius > 0.0f);
    // Frame (u, v, w) with cross(u, v) = w: the rim d(angle) = cos u + sin v runs counter-clockwise about w.
    const glm::vec3 w = glm::normalize(b - a);
    const glm::vec3 helper = std::fabs(w.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 u = glm::normalize(glm::cross(helper, w));
    const glm::vec3 v = glm::cross(w, u);
    const std::vector<glm::vec2>& table = circle(segments);
    auto rim = [&](uint32_t i) { return radius * (table[i].x * u + table[i].y * v); };

    for (uint32_t i = 0; i < segments; ++i) {
        const glm::vec3 d0 = rim(i), d1 = rim(i + 1);
        addQuad(a + d0, a + d1, b + d1, b + d0, material); // outward: cross(d1 - d0, w) points along d
    }
    if (!caps) return;
    // Fans from rim vertex 0: counter-clockwise about w at b (normal +w), reversed at a (normal -w).
    for (int end = 0; end < 2; ++end) {
        const glm::vec3 center = end == 0 ? b : a;
        const glm::vec3 normal = end == 0 ? w : -w;
        const uint32_t base = uint32_t(scene_.positions.size());
        for (uint32_t i = 0; i < segments; ++i) {
            scene_.positions.push_back(center + rim(i));
            scene_.normals.push_back(normal);
        }
        for (uint32_t i = 1; i + 1 < segments; ++i) {
            if (end == 0) scene_.triangles.emplace_back(base, base + i, base + i + 1);
            else scene_.triangles.emplace_back(base, base + i + 1, base + i);
            scene_.triangleMaterials.push_back(material);
        }
    }
    reportProgress();
}

} // namespace chcrt::procedural
