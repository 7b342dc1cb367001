// The City: a 2.5D downtown like the CityEngine models of CHC+RT §6 (City-10/City-200). A grid of blocks
// separated by 16 m streets (10 m road, 3 m raised sidewalks); each block is split into 2x2..3x3 lots whose
// buildings fill the lot up to the sidewalk, so at street level the view is walled in on both sides and
// heavily occluded, while from above it is open. Towers (podium + set-back shaft) cluster near the centre.
//
// Triangle budget: the number of blocks grows with the target (~25k triangles per block); the facade detail
// (windows, ribbon windows, balconies, cornices: one 5-faced box each, 10 triangles) takes all that the
// blocks and buildings leave, spread over street-facing facades in proportion to their area, so the total
// lands within 10 triangles below the target.
#include "renderer/scene/procedural/procedural_internal.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace chcrt::procedural {

namespace {

constexpr float kStreetWidth = 16.0f;  // between block edges
constexpr float kSidewalk = 3.0f;      // raised sidewalk along each block; the road between is 10 m
constexpr float kSidewalkHeight = 0.15f;
constexpr float kTowerInset = 3.0f;    // tower shaft set back from the podium's edges
constexpr float kMaxHeight = 200.0f;
constexpr uint64_t kTrianglesPerBlock = 25000;
constexpr int kFacadeColours = 5;

struct Building {
    float x0, x1, z0, z1;
    float height;
    float podium;          // 0: a plain box; otherwise the podium height of a tower
    uint32_t streetSides;  // BoxFace bits of the sides facing a street
    uint32_t style;        // facade detail style, 0..3
    uint32_t colour;       // facade colour, 0..kFacadeColours-1
};

struct Park { float x0, x1, z0, z1; };

struct CityLayout {
    StreetGrid grid;
    std::vector<Building> buildings;
    std::vector<Park> parks;
    float maxHeight = 0.0f;
};

int blocksPerSide(uint64_t target) {
    return std::clamp(int(std::lround(std::sqrt(double(target) / double(kTrianglesPerBlock)))), 2, 60);
}

// Splits [lo, hi] into `parts` lots with jittered boundaries (three parts keep a central courtyard lot).
std::vector<float> splitSpan(Rng& rng, float lo, float hi, int parts) {
    const float width = hi - lo;
    if (parts == 2) return {lo, lo + width * rng.uniform(0.38f, 0.62f), hi};
    const float middle = rng.uniform(0.28f, 0.4f), shift = rng.uniform(-0.05f, 0.05f);
    return {lo, lo + width * (0.5f - 0.5f * middle + shift), lo + width * (0.5f + 0.5f * middle + shift), hi};
}

Building makeBuilding(Rng& rng, float x0, float x1, float z0, float z1, uint32_t sides, float centrality) {
    Building b{x0, x1, z0, z1, 0.0f, 0.0f, sides, rng.below(4), rng.below(kFacadeColours)};
    const float u = rng.uniform();
    b.height = (9.0f + 25.0f * u * u) * (1.0f + 1.2f * centrality);
    const bool roomForTower = std::min(x1 - x0, z1 - z0) >= 16.0f;
    if (roomForTower && rng.chance(0.08f + 0.2f * centrality)) {
        b.podium = rng.uniform(8.0f, 16.0f);
        b.height = std::min(kMaxHeight, 50.0f + rng.uniform() * (60.0f + 90.0f * centrality));
    }
    return b;
}

CityLayout makeCityLayout(const ProceduralSpec& spec) {
    Rng rng(spec.seed, kLayoutStream);
    CityLayout city;
    const int n = blocksPerSide(spec.targetTriangles);
    city.grid = makeStreetGrid(rng, n, n, 45.0f, 75.0f, kStreetWidth);
    const StreetGrid& g = city.grid;
    const float cornerDistance = std::hypot(g.maxX(), g.maxZ());
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const float bx0 = g.cellX0(i), bx1 = g.cellX1(i), bz0 = g.cellZ0(j), bz1 = g.cellZ1(j);
            const float centrality =
                1.0f - std::min(1.0f, std::hypot(0.5f * (bx0 + bx1), 0.5f * (bz0 + bz1)) / cornerDistance);
            const std::vector<float> xs = splitSpan(rng, bx0, bx1, rng.chance(0.5f) ? 3 : 2);
            const std::vector<float> zs = splitSpan(rng, bz0, bz1, rng.chance(0.5f) ? 3 : 2);
            const int kx = int(xs.size()) - 1, kz = int(zs.size()) - 1;
            for (int b = 0; b < kz; ++b) {
                for (int a = 0; a < kx; ++a) {
                    if (kx == 3 && kz == 3 && a == 1 && b == 1) {
                        city.parks.push_back({xs[1], xs[2], zs[1], zs[2]}); // inner courtyard: a park
                        continue;
                    }
                    uint32_t sides = 0;
                    if (a == 0) sides |= kNegX;
                    if (a == kx - 1) sides |= kPosX;
                    if (b == 0) sides |= kNegZ;
                    if (b == kz - 1) sides |= kPosZ;
                    city.buildings.push_back(makeBuilding(rng, xs[a], xs[a + 1], zs[b], zs[b + 1], sides, centrality));
                    city.maxHeight = std::max(city.maxHeight, city.buildings.back().height);
                }
            }
        }
    }
    return city;
}

// A facade: the rectangle of a wall that faces `side` (one BoxFace bit) at coordinate `plane`, spanning
// [u0, u1] along the wall (z for x-facing walls, x for z-facing ones) and [y0, y1] in height.
struct Facade {
    uint32_t side;
    float plane, u0, u1, y0, y1;
    uint32_t style;
    float area() const { return (u1 - u0) * (y1 - y0); }
};

void collectFacades(const Building& b, std::vector<Facade>& out) {
    auto addSides = [&](uint32_t sides, float x0, float x1, float z0, float z1, float y0, float y1) {
        if (sides & kNegX) out.push_back({kNegX, x0, z0, z1, y0, y1, b.style});
        if (sides & kPosX) out.push_back({kPosX, x1, z0, z1, y0, y1, b.style});
        if (sides & kNegZ) out.push_back({kNegZ, z0, x0, x1, y0, y1, b.style});
        if (sides & kPosZ) out.push_back({kPosZ, z1, x0, x1, y0, y1, b.style});
    };
    // Only street-facing walls get detail: the others touch a neighbour and are never seen.
    const float top = b.podium > 0.0f ? b.podium : b.height;
    addSides(b.streetSides, b.x0, b.x1, b.z0, b.z1, kSidewalkHeight, top);
    if (b.podium > 0.0f)
        addSides(kSides, b.x0 + kTowerInset, b.x1 - kTowerInset, b.z0 + kTowerInset, b.z1 - kTowerInset, b.podium,
                 b.height);
}

struct Materials {
    uint32_t ground, street, sidewalk, roof, window, ledge;
    uint32_t facade[kFacadeColours];
};

Materials addMaterials(MeshBuilder& builder) {
    Materials m;
    m.ground = builder.addMaterial("ground", {0.25f, 0.38f, 0.16f});
    m.street = builder.addMaterial("street", {0.11f, 0.11f, 0.12f});
    m.sidewalk = builder.addMaterial("sidewalk", {0.52f, 0.5f, 0.47f});
    m.roof = builder.addMaterial("roof", {0.3f, 0.29f, 0.31f});
    m.window = builder.addMaterial("window", {0.13f, 0.19f, 0.27f});
    m.ledge = builder.addMaterial("ledge", {0.72f, 0.7f, 0.66f});
    const glm::vec3 colours[kFacadeColours] = {
        {0.55f, 0.27f, 0.2f}, {0.76f, 0.66f, 0.5f}, {0.6f, 0.6f, 0.57f}, {0.86f, 0.84f, 0.78f}, {0.4f, 0.46f, 0.53f}};
    const char* names[kFacadeColours] = {"facade-brick", "facade-sandstone", "facade-concrete", "facade-plaster",
                                         "facade-slate"};
    for (int i = 0; i < kFacadeColours; ++i) m.facade[i] = builder.addMaterial(names[i], colours[i]);
    return m;
}

// Up-facing quad over [x0, x1] x [z0, z1] at height y.
void addGroundQuad(MeshBuilder& builder, float x0, float z0, float x1, float z1, float y, uint32_t material) {
    builder.addQuad({x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x1, y, z0}, material);
}

void addGroundAndBlocks(MeshBuilder& builder, const CityLayout& city, const Materials& m) {
    const StreetGrid& g = city.grid;
    // Streets: one quad over the whole city (blocks stand on it); grass around it out to a margin.
    const float x0 = g.minX(), x1 = g.maxX(), z0 = g.minZ(), z1 = g.maxZ();
    const float margin = 50.0f + 0.25f * (x1 - x0);
    addGroundQuad(builder, x0, z0, x1, z1, 0.0f, m.street);
    addGroundQuad(builder, x0 - margin, z0 - margin, x1 + margin, z0, 0.0f, m.ground);
    addGroundQuad(builder, x0 - margin, z1, x1 + margin, z1 + margin, 0.0f, m.ground);
    addGroundQuad(builder, x0 - margin, z0, x0, z1, 0.0f, m.ground);
    addGroundQuad(builder, x1, z0, x1 + margin, z1, 0.0f, m.ground);
    for (int j = 0; j < g.cellsZ(); ++j)
        for (int i = 0; i < g.cellsX(); ++i)
            builder.addBox({g.cellX0(i) - kSidewalk, 0.0f, g.cellZ0(j) - kSidewalk},
                           {g.cellX1(i) + kSidewalk, kSidewalkHeight, g.cellZ1(j) + kSidewalk}, m.sidewalk, kNoBottom);
    for (const Park& p : city.parks) builder.addBox({p.x0, 0.0f, p.z0}, {p.x1, 0.4f, p.z1}, m.ground, kNoBottom);
}

void addBuilding(MeshBuilder& builder, const Building& b, const Materials& m) {
    const uint32_t facade = m.facade[b.colour];
    const float top = b.podium > 0.0f ? b.podium : b.height;
    builder.addBox({b.x0, 0.0f, b.z0}, {b.x1, top, b.z1}, facade, kSides);
    builder.addBox({b.x0, 0.0f, b.z0}, {b.x1, top, b.z1}, m.roof, kPosY);
    if (b.podium > 0.0f) {
        const glm::vec3 lower(b.x0 + kTowerInset, b.podium, b.z0 + kTowerInset);
        const glm::vec3 upper(b.x1 - kTowerInset, b.height, b.z1 - kTowerInset);
        builder.addBox(lower, upper, facade, kSides);
        builder.addBox(lower, upper, m.roof, kPosY);
    }
}

// Places exactly `count` detail elements on a facade, one per cell of a grid whose cells are about 1.3x
// as tall as wide, filled row by row from the top (a partial bottom row reads as a shop front).
void addFacadeDetail(MeshBuilder& builder, const Facade& f, uint64_t count, const Materials& m) {
    if (count == 0) return;
    const float width = f.u1 - f.u0, height = f.y1 - f.y0;
    const float cellArea = width * height / float(count);
    const float nominalCellWidth = cellArea / std::sqrt(cellArea * 1.3f);
    const uint64_t cols = std::clamp<uint64_t>(uint64_t(std::lround(width / nominalCellWidth)), 1, count);
    const uint64_t rows = (count + cols - 1) / cols;
    const float cw = width / float(cols), ch = height / float(rows);
    const bool xFacing = (f.side & (kPosX | kNegX)) != 0;
    const float outward = (f.side & (kPosX | kPosZ)) ? 1.0f : -1.0f;
    const uint32_t back = f.side == kPosX ? kNegX : f.side == kNegX ? kPosX : f.side == kPosZ ? kNegZ : kPosZ;
    const uint32_t faces = kAllFaces & ~back;

    for (uint64_t k = 0; k < count; ++k) {
        const uint64_t row = k / cols, col = k % cols;
        // Element extent within its cell (fractions of cw, ch), depth off the wall, material.
        float a0 = 0.2f, a1 = 0.8f, b0 = 0.3f, b1 = 0.85f, depth = 0.12f;
        uint32_t material = m.window;
        switch (f.style) {
        case 1: a0 = 0.03f, a1 = 0.97f, b0 = 0.35f, b1 = 0.8f, depth = 0.08f; break; // ribbon windows
        case 2: // balconies on every other column above the ground row
            if (col % 2 == 0 && row + 1 < rows) {
                a0 = 0.1f, a1 = 0.9f, b0 = 0.0f, b1 = 0.3f, depth = std::clamp(0.4f * cw, 0.3f, 1.2f);
                material = m.ledge;
            }
            break;
        case 3: // cornices on every other row
            if (row % 2 == 0) a0 = 0.0f, a1 = 0.995f, b0 = 0.0f, b1 = 0.12f, depth = 0.35f, material = m.ledge;
            break;
        default: break;
        }
        const float u0 = f.u0 + (float(col) + a0) * cw, u1 = f.u0 + (float(col) + a1) * cw;
        const float cellBottom = f.y1 - float(row + 1) * ch;
        const float y0 = cellBottom + b0 * ch, y1 = cellBottom + b1 * ch;
        const float d0 = std::min(f.plane, f.plane + outward * depth), d1 = std::max(f.plane, f.plane + outward * depth);
        if (xFacing) builder.addBox({d0, y0, u0}, {d1, y1, u1}, material, faces);
        else builder.addBox({u0, y0, d0}, {u1, y1, d1}, material, faces);
    }
}

// Per-facade detail element counts: the budget left after `used` triangles, spread over the facades in
// proportion to their area; cumulative rounding makes the counts sum exactly to the total.
std::vector<uint64_t> facadeDetailCounts(const std::vector<Facade>& facades, uint64_t target, uint64_t used) {
    const uint64_t elementCost = MeshBuilder::boxCost(kAllFaces & ~uint32_t(kNegX));
    const uint64_t elements = target > used ? (target - used) / elementCost : 0;
    double totalArea = 0.0;
    for (const Facade& f : facades) totalArea += f.area();
    double areaSoFar = 0.0;
    uint64_t placed = 0;
    std::vector<uint64_t> counts(facades.size());
    for (size_t i = 0; i < facades.size(); ++i) {
        const Facade& f = facades[i];
        areaSoFar += f.area();
        const uint64_t upTo = i + 1 == facades.size() ? elements : uint64_t(double(elements) * (areaSoFar / totalArea));
        counts[i] = upTo - placed;
        placed = upTo;
    }
    return counts;
}

uint64_t buildingCost(const Building& b) {
    const uint64_t box = MeshBuilder::boxCost(kSides) + MeshBuilder::boxCost(kPosY);
    return b.podium > 0.0f ? 2 * box : box;
}

} // namespace

void generateCity(const ProceduralSpec& spec, MeshBuilder& builder) {
    const CityLayout city = makeCityLayout(spec);
    const uint64_t target = spec.targetTriangles;
    builder.reserve(target + 64, 2 * target + 256);
    const Materials materials = addMaterials(builder);
    addGroundAndBlocks(builder, city, materials);
    std::vector<Facade> facades;
    for (const Building& b : city.buildings) {
        addBuilding(builder, b, materials);
        collectFacades(b, facades);
    }
    const std::vector<uint64_t> counts = facadeDetailCounts(facades, target, builder.triangleCount());
    for (size_t i = 0; i < facades.size(); ++i) addFacadeDetail(builder, facades[i], counts[i], materials);
}

// The same city in parts (out-of-core preparation): the plan is the layout plus every facade's detail count,
// computed exactly as generateCity does (the triangle count before the detail follows from the primitives'
// fixed costs), so the union of all parts is the same geometry; only the triangle order differs.
struct CityParts::Plan {
    CityLayout city;
    std::vector<Facade> facades;
    std::vector<uint32_t> facadeBegin; // per building, + 1 at the end
    std::vector<uint64_t> counts;
    uint64_t groundTriangles = 0;
};

CityParts::CityParts(const ProceduralSpec& spec) : plan_(std::make_unique<Plan>()) {
    Plan& p = *plan_;
    p.city = makeCityLayout(spec);
    const StreetGrid& g = p.city.grid;
    p.groundTriangles = 5 * 2 + uint64_t(g.cellsX()) * uint64_t(g.cellsZ()) * MeshBuilder::boxCost(kNoBottom) +
                        p.city.parks.size() * MeshBuilder::boxCost(kNoBottom);
    uint64_t used = p.groundTriangles;
    for (const Building& b : p.city.buildings) {
        p.facadeBegin.push_back(uint32_t(p.facades.size()));
        collectFacades(b, p.facades);
        used += buildingCost(b);
    }
    p.facadeBegin.push_back(uint32_t(p.facades.size()));
    p.counts = facadeDetailCounts(p.facades, spec.targetTriangles, used);
}

CityParts::~CityParts() = default;

uint32_t CityParts::buildingCount() const { return uint32_t(plan_->city.buildings.size()); }

uint64_t CityParts::groundTriangles() const { return plan_->groundTriangles; }

uint64_t CityParts::buildingTriangles(uint32_t building) const {
    const Plan& p = *plan_;
    uint64_t n = buildingCost(p.city.buildings[building]);
    const uint64_t detail = MeshBuilder::boxCost(kAllFaces & ~uint32_t(kNegX));
    for (uint32_t f = p.facadeBegin[building]; f < p.facadeBegin[building + 1]; ++f) n += p.counts[f] * detail;
    return n;
}

void CityParts::generate(bool ground, uint32_t firstBuilding, uint32_t endBuilding, MeshBuilder& builder) const {
    const Plan& p = *plan_;
    const Materials materials = addMaterials(builder);
    if (ground) addGroundAndBlocks(builder, p.city, materials);
    for (uint32_t b = firstBuilding; b < endBuilding; ++b) {
        addBuilding(builder, p.city.buildings[b], materials);
        for (uint32_t f = p.facadeBegin[b]; f < p.facadeBegin[b + 1]; ++f)
            addFacadeDetail(builder, p.facades[f], p.counts[f], materials);
    }
}

CitySummary summarizeCity(const ProceduralSpec& spec) {
    CityLayout city = makeCityLayout(spec);
    return {std::move(city.grid), city.maxHeight};
}

} // namespace chcrt::procedural
