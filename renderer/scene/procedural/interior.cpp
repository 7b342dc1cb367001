// The Interior: an office-like building with several storeys, each a grid of rooms in "wings" (a row of
// rooms, a corridor, a row of rooms), walls with door openings, pillars at every wall junction and
// furniture stacked in the room corners. From inside almost everything is occluded: the extreme case for
// occlusion culling. The top storey has no ceiling (a cut-away), so that the far view looks into rooms.
//
// Layout guarantees for the near path (ground floor): doors sit in the middle of their wall, furniture
// only in corner zones that end well before any door, corridors are free, and the doors the path uses
// always exist.
//
// Triangle budget: the room count grows with the target (~2,500 triangles per room); furniture boxes (12
// triangles) take all the budget the walls leave, spread evenly over the rooms, so the total lands within
// 12 triangles below the target.
#include "renderer/scene/procedural/procedural_internal.h"

#include <algorithm>
#include <cmath>

namespace chcrt::procedural {

namespace {

constexpr float kRoomHeight = 3.0f;     // floor to ceiling
constexpr float kStoreyHeight = 3.3f;   // with a 0.3 m slab
constexpr float kWall = 0.2f;           // wall thickness
constexpr float kPillar = 0.5f;         // pillar side
constexpr float kCorridor = 2.6f;       // corridor width between wall lines
constexpr float kDoorWidth = 1.1f, kDoorHeight = 2.2f, kLeafWidth = 1.0f;
constexpr float kZoneStart = 0.35f, kZoneSize = 1.3f, kShelfHeight = 2.0f; // furniture corner zones
constexpr uint64_t kTrianglesPerRoom = 2500;

enum class Band { RoomA, Corridor, RoomB };

struct InteriorLayout {
    std::vector<float> xs;  // column boundaries = wall lines along z
    std::vector<float> zs;  // band boundaries = wall lines along x
    std::vector<Band> bands;
    int storeys = 2;
    int pathColumn = 0;     // the near path enters room (pathColumn, band 2) and leaves through pathColumn+1

    int columns() const { return int(xs.size()) - 1; }
    float width() const { return xs.back(); }
    float depth() const { return zs.back(); }
    float middleX(int i) const { return 0.5f * (xs[i] + xs[i + 1]); }
    float middleZ(int b) const { return 0.5f * (zs[b] + zs[b + 1]); }
};

InteriorLayout makeInteriorLayout(const ProceduralSpec& spec) {
    Rng rng(spec.seed, kLayoutStream);
    InteriorLayout layout;
    const uint64_t target = spec.targetTriangles;
    layout.storeys = target < 2'000'000 ? 2 : target < 8'000'000 ? 3 : 4;
    const double roomsPerStorey = double(std::max<uint64_t>(12, target / kTrianglesPerRoom)) / layout.storeys;
    // Wings are ~14.6 m deep and columns ~6 m wide; 2.4 columns per wing keeps the footprint square.
    const int wings = std::max(1, int(std::lround(std::sqrt(roomsPerStorey / 4.8))));
    const int columns = std::max(3, int(std::lround(roomsPerStorey / (2.0 * wings))));
    layout.xs.push_back(0.0f);
    for (int i = 0; i < columns; ++i) layout.xs.push_back(layout.xs.back() + rng.uniform(5.0f, 7.0f));
    layout.zs.push_back(0.0f);
    for (int w = 0; w < wings; ++w) {
        for (Band band : {Band::RoomA, Band::Corridor, Band::RoomB}) {
            layout.bands.push_back(band);
            layout.zs.push_back(layout.zs.back() + (band == Band::Corridor ? kCorridor : rng.uniform(5.0f, 7.0f)));
        }
    }
    layout.pathColumn = rng.range(0, std::min(columns - 3, 3));
    return layout;
}

struct Materials {
    uint32_t floor, ceiling, wall, outerWall, door, pillar;
    uint32_t furniture[3];
};

Materials addMaterials(MeshBuilder& builder) {
    Materials m;
    m.floor = builder.addMaterial("floor", {0.5f, 0.38f, 0.26f});
    m.ceiling = builder.addMaterial("ceiling", {0.9f, 0.9f, 0.88f});
    m.wall = builder.addMaterial("wall", {0.8f, 0.77f, 0.7f});
    m.outerWall = builder.addMaterial("outer-wall", {0.58f, 0.56f, 0.53f});
    m.door = builder.addMaterial("door", {0.45f, 0.25f, 0.12f});
    m.pillar = builder.addMaterial("pillar", {0.45f, 0.47f, 0.52f});
    m.furniture[0] = builder.addMaterial("furniture-blue", {0.25f, 0.4f, 0.6f});
    m.furniture[1] = builder.addMaterial("furniture-red", {0.6f, 0.3f, 0.25f});
    m.furniture[2] = builder.addMaterial("furniture-green", {0.3f, 0.48f, 0.28f});
    return m;
}

// A wall along the `along` axis (0 = x, 2 = z) from a to b at cross-coordinate c, on storey floor y0.
// With a door: two jambs, a lintel (door colour) and the door leaf standing open flat against the wall on
// the `leafSide` (+1/-1 along the cross axis), so the opening itself stays free.
struct WallBuilder {
    MeshBuilder& builder;
    const Materials& m;

    void box(int along, float a0, float a1, float c0, float c1, float y0, float y1, uint32_t material) {
        if (along == 0) builder.addBox({a0, y0, c0}, {a1, y1, c1}, material, kNoBottom);
        else builder.addBox({c0, y0, a0}, {c1, y1, a1}, material, kNoBottom);
    }
    void wall(int along, float a, float b, float c, float y0, float height, uint32_t material) {
        box(along, a, b, c - 0.5f * kWall, c + 0.5f * kWall, y0, y0 + height, material);
    }
    void doorWall(int along, float a, float b, float c, float y0, float leafSide) {
        const float middle = 0.5f * (a + b), half = 0.5f * kDoorWidth;
        const float c0 = c - 0.5f * kWall, c1 = c + 0.5f * kWall;
        box(along, a, middle - half, c0, c1, y0, y0 + kRoomHeight, m.wall);
        box(along, middle + half, b, c0, c1, y0, y0 + kRoomHeight, m.wall);
        box(along, middle - half, middle + half, c0, c1, y0 + kDoorHeight, y0 + kRoomHeight, m.door);
        const float face = c + leafSide * (0.5f * kWall + 0.01f);
        box(along, middle + half, middle + half + kLeafWidth, std::min(face, face + leafSide * 0.04f),
            std::max(face, face + leafSide * 0.04f), y0, y0 + kDoorHeight - 0.05f, m.door);
    }
};

void addStoreyShell(MeshBuilder& builder, const InteriorLayout& layout, const Materials& m, Rng& rng, int storey) {
    const float y0 = kStoreyHeight * float(storey);
    const bool top = storey + 1 == layout.storeys;
    const float W = layout.width(), D = layout.depth();
    const int nc = layout.columns(), nb = int(layout.bands.size());
    builder.addQuad({0.0f, y0, 0.0f}, {0.0f, y0, D}, {W, y0, D}, {W, y0, 0.0f}, m.floor);
    if (!top) builder.addQuad({0.0f, y0 + kRoomHeight, 0.0f}, {W, y0 + kRoomHeight, 0.0f},
                              {W, y0 + kRoomHeight, D}, {0.0f, y0 + kRoomHeight, D}, m.ceiling);
    // Outer walls of lower storeys run through the slab so the facade has no slit.
    const float outerHeight = top ? kRoomHeight : kStoreyHeight;
    const float p = 0.5f * kPillar;
    WallBuilder walls{builder, m};

    for (int b = 0; b <= nb; ++b)
        for (int i = 0; i <= nc; ++i)
            builder.addBox({layout.xs[i] - p, y0, layout.zs[b] - p}, {layout.xs[i] + p, y0 + kRoomHeight, layout.zs[b] + p},
                           m.pillar, kNoBottom);
    // Walls along x (on band boundaries): outer, corridor (a door per room) or back-to-back (some doors).
    for (int b = 0; b <= nb; ++b) {
        const bool outer = b == 0 || b == nb;
        const bool corridorBelow = b > 0 && layout.bands[b - 1] == Band::Corridor;
        const bool corridorAbove = b < nb && layout.bands[b] == Band::Corridor;
        for (int i = 0; i < nc; ++i) {
            const float a = layout.xs[i] + p, e = layout.xs[i + 1] - p, z = layout.zs[b];
            if (outer) walls.wall(0, a, e, z, y0, outerHeight, m.outerWall);
            else if (corridorBelow || corridorAbove) walls.doorWall(0, a, e, z, y0, corridorAbove ? -1.0f : 1.0f);
            else if (rng.chance(0.3f)) walls.doorWall(0, a, e, z, y0, 1.0f);
            else walls.wall(0, a, e, z, y0, kRoomHeight, m.wall);
        }
    }
    // Walls along z (on column boundaries): outer walls close every band; inner ones divide room rows.
    for (int i = 0; i <= nc; ++i) {
        for (int b = 0; b < nb; ++b) {
            const float a = layout.zs[b] + p, e = layout.zs[b + 1] - p, x = layout.xs[i];
            if (i == 0 || i == nc) {
                walls.wall(2, a, e, x, y0, outerHeight, m.outerWall);
                continue;
            }
            if (layout.bands[b] == Band::Corridor) continue;
            const bool pathDoor = storey == 0 && b == 2 && i == layout.pathColumn + 1;
            if (rng.chance(0.4f) || pathDoor) walls.doorWall(2, a, e, x, y0, 1.0f);
            else walls.wall(2, a, e, x, y0, kRoomHeight, m.wall);
        }
    }
}

// Exactly `count` boxes stacked like shelves in one corner zone [x0, x0+size] x [z0, z0+size].
void addCornerStack(MeshBuilder& builder, float x0, float z0, float y0, uint64_t count, uint32_t material) {
    if (count == 0) return;
    const uint64_t side = std::max<uint64_t>(1, uint64_t(std::ceil(std::sqrt(double(count) / 3.0))));
    const uint64_t layers = (count + side * side - 1) / (side * side);
    const float cell = kZoneSize / float(side), layer = std::min(1.0f, kShelfHeight / float(layers));
    for (uint64_t k = 0; k < count; ++k) {
        const uint64_t level = k / (side * side), rest = k % (side * side);
        const float x = x0 + float(rest % side) * cell, z = z0 + float(rest / side) * cell;
        const float y = y0 + float(level) * layer;
        builder.addBox({x + 0.05f * cell, y, z + 0.05f * cell}, {x + 0.95f * cell, y + 0.9f * layer, z + 0.95f * cell},
                       material);
    }
}

void addFurniture(MeshBuilder& builder, const InteriorLayout& layout, const Materials& m, uint64_t boxes) {
    std::vector<glm::ivec3> rooms; // (column, band, storey)
    for (int s = 0; s < layout.storeys; ++s)
        for (int b = 0; b < int(layout.bands.size()); ++b)
            if (layout.bands[b] != Band::Corridor)
                for (int i = 0; i < layout.columns(); ++i) rooms.emplace_back(i, b, s);
    const uint64_t perRoom = boxes / rooms.size(), extra = boxes % rooms.size();
    for (size_t r = 0; r < rooms.size(); ++r) {
        const glm::ivec3 room = rooms[r];
        const uint64_t count = perRoom + (r < extra ? 1 : 0);
        const float x0 = layout.xs[room.x] + kZoneStart, x1 = layout.xs[room.x + 1] - kZoneStart - kZoneSize;
        const float z0 = layout.zs[room.y] + kZoneStart, z1 = layout.zs[room.y + 1] - kZoneStart - kZoneSize;
        const float y0 = kStoreyHeight * float(room.z);
        const float cornersX[4] = {x0, x1, x0, x1}, cornersZ[4] = {z0, z0, z1, z1};
        for (uint64_t c = 0; c < 4; ++c)
            addCornerStack(builder, cornersX[c], cornersZ[c], y0, count / 4 + (c < count % 4 ? 1 : 0),
                           m.furniture[(r + c) % 3]);
    }
}

} // namespace

void generateInterior(const ProceduralSpec& spec, MeshBuilder& builder) {
    const InteriorLayout layout = makeInteriorLayout(spec);
    const uint64_t target = spec.targetTriangles;
    builder.reserve(target + 64, 2 * target + 256);
    const Materials materials = addMaterials(builder);
    Rng rng(spec.seed, kDetailStream);
    for (int s = 0; s < layout.storeys; ++s) addStoreyShell(builder, layout, materials, rng, s);
    const uint64_t used = builder.triangleCount(), boxCost = MeshBuilder::boxCost();
    addFurniture(builder, layout, materials, target > used ? (target - used) / boxCost : 0);
}

InteriorSummary summarizeInterior(const ProceduralSpec& spec) {
    const InteriorLayout layout = makeInteriorLayout(spec);
    // Ground floor, first wing: bands 0 (rooms A), 1 (corridor), 2 (rooms B).
    const int c1 = layout.pathColumn, c2 = c1 + 2;
    const float zA = layout.middleZ(0), zC = layout.middleZ(1), zB = layout.middleZ(2);
    InteriorSummary summary;
    summary.pathCorners = {
        {0.8f, zC},                      // west end of the corridor
        {layout.middleX(c1), zC},        // turn into room (c1, B) ...
        {layout.middleX(c1), zB},        // ... its centre; east through the partition door
        {layout.middleX(c1 + 1), zB},    // room (c1+1, B); back out to the corridor
        {layout.middleX(c1 + 1), zC},
        {layout.middleX(c2), zC},        // on along the corridor, into room (c2, A)
        {layout.middleX(c2), zA},
    };
    summary.pathGates = {
        {layout.middleX(c1), layout.zs[2]},
        {layout.xs[c1 + 1], zB},
        {layout.middleX(c1 + 1), layout.zs[2]},
        {layout.middleX(c2), layout.zs[1]},
    };
    summary.lightRoomCenter = {layout.middleX(c1), zB};
    summary.ceilingHeight = kRoomHeight;
    summary.bounds.grow(glm::vec3(-0.5f * kPillar, 0.0f, -0.5f * kPillar));
    summary.bounds.grow(glm::vec3(layout.width() + 0.5f * kPillar, kStoreyHeight * float(layout.storeys - 1) + kRoomHeight,
                                  layout.depth() + 0.5f * kPillar));
    return summary;
}

} // namespace chcrt::procedural
