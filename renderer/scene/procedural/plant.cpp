// The Plant: an industrial site in the spirit of the Powerplant model of CHC+RT §6 — irregular, cluttered
// and deep rather than regular like the City. A grid of process units separated by 10 m access lanes; each
// unit holds tanks, vessels, stacks and scaffold towers (columns, beams, braces, platforms at several
// heights, stair flights) in four slots, criss-crossed by pipe runs with axis-aligned, ramped (45 degrees
// in a vertical plane) and diagonal (45 degrees in plan, above the structures) legs. Pipe bridges cross
// the lanes at 7-9.5 m.
//
// Layout guarantee for the near path: below 6 m nothing enters a lane — units keep everything inside
// their rectangle shrunk by 1 m; only bridges span lanes, and they are higher.
//
// Triangle budget: the unit count grows with the target (~25k triangles per unit); each unit gets an
// exact share of what the ground and bridges leave, spends up to 55 % on structures (their tessellation
// scales with the share), fills the rest with pipe runs, and the last few triangles with 12-triangle
// junction boxes, so the total lands within 12 triangles per unit below the target.
#include "renderer/scene/procedural/procedural_internal.h"

#include <algorithm>
#include <cmath>

namespace chcrt::procedural {

namespace {

constexpr float kLaneWidth = 10.0f;
constexpr float kUnitMargin = 1.0f;       // nothing of a unit closer than this to a lane
constexpr float kMaxStructureHeight = 55.0f;
constexpr float kLevelHeight = 4.0f, kBay = 3.0f;
constexpr uint64_t kTrianglesPerUnit = 25000;

int unitsPerSide(uint64_t target) {
    return std::clamp(int(std::lround(std::sqrt(double(target) / double(kTrianglesPerUnit)))), 2, 60);
}

StreetGrid makePlantGrid(const ProceduralSpec& spec) {
    Rng rng(spec.seed, kLayoutStream);
    const int n = unitsPerSide(spec.targetTriangles);
    return makeStreetGrid(rng, n, n, 30.0f, 46.0f, kLaneWidth);
}

struct Materials {
    uint32_t ground, lane, pad, tank, tankAlt, stack, steel, grating, valve;
    uint32_t pipe[3];
};

Materials addMaterials(MeshBuilder& builder) {
    Materials m;
    m.ground = builder.addMaterial("ground", {0.33f, 0.31f, 0.27f});
    m.lane = builder.addMaterial("lane", {0.12f, 0.12f, 0.13f});
    m.pad = builder.addMaterial("concrete-pad", {0.55f, 0.54f, 0.5f});
    m.tank = builder.addMaterial("tank", {0.82f, 0.82f, 0.8f});
    m.tankAlt = builder.addMaterial("tank-green", {0.36f, 0.5f, 0.4f});
    m.stack = builder.addMaterial("stack", {0.6f, 0.22f, 0.18f});
    m.steel = builder.addMaterial("scaffold", {0.75f, 0.45f, 0.12f});
    m.grating = builder.addMaterial("platform", {0.4f, 0.4f, 0.42f});
    m.valve = builder.addMaterial("valve", {0.15f, 0.3f, 0.65f});
    m.pipe[0] = builder.addMaterial("pipe-grey", {0.5f, 0.52f, 0.55f});
    m.pipe[1] = builder.addMaterial("pipe-yellow", {0.8f, 0.68f, 0.15f});
    m.pipe[2] = builder.addMaterial("pipe-red", {0.6f, 0.12f, 0.1f});
    return m;
}

struct Rect {
    float x0, z0, x1, z1;
    float width() const { return x1 - x0; }
    float depth() const { return z1 - z0; }
    glm::vec2 center() const { return {0.5f * (x0 + x1), 0.5f * (z0 + z1)}; }
};

// One unit's generator: spends exactly up to `budget` triangles.
class UnitBuilder {
public:
    UnitBuilder(MeshBuilder& builder, const Materials& m, Rng& rng, const Rect& inner, uint64_t budget)
        : b_(builder), m_(m), rng_(rng), inner_(inner), remaining_(budget) {
        tankSegments_ = uint32_t(std::clamp<uint64_t>(budget / 400 / 4 * 4, 12, 64));
        pipeSegments_ = uint32_t(std::clamp<uint64_t>(budget / 1500 / 2 * 2, 6, 20));
        splitX_ = inner.x0 + inner.width() * rng.uniform(0.4f, 0.6f);
        splitZ_ = inner.z0 + inner.depth() * rng.uniform(0.4f, 0.6f);
    }

    void build() {
        // Four slots around the split point, leaving 3 m pipe corridors between them and 1.5 m at the edges.
        const Rect slots[4] = {{inner_.x0 + 1.5f, inner_.z0 + 1.5f, splitX_ - 1.5f, splitZ_ - 1.5f},
                               {splitX_ + 1.5f, inner_.z0 + 1.5f, inner_.x1 - 1.5f, splitZ_ - 1.5f},
                               {inner_.x0 + 1.5f, splitZ_ + 1.5f, splitX_ - 1.5f, inner_.z1 - 1.5f},
                               {splitX_ + 1.5f, splitZ_ + 1.5f, inner_.x1 - 1.5f, inner_.z1 - 1.5f}};
        const uint64_t slotBudget = remaining_ * 55 / 100 / 4;
        for (const Rect& slot : slots) {
            switch (rng_.below(5)) {
            case 0: addTank(slot.center(), 0.45f * std::min(slot.width(), slot.depth()) * rng_.uniform(0.65f, 1.0f),
                            rng_.uniform(6.0f, 16.0f), slotBudget); break;
            case 1: addTankCluster(slot, slotBudget); break;
            case 2: addScaffold(slot, slotBudget); break;
            case 3: addVessels(slot, slotBudget); break;
            default: addStack(slot, slotBudget); break;
            }
        }
        while (addPipeRun()) {}
        while (remaining_ >= MeshBuilder::boxCost()) addJunctionBox();
    }

private:
    bool spend(uint64_t cost) {
        if (cost > remaining_) return false;
        remaining_ -= cost;
        return true;
    }

    void addTank(glm::vec2 at, float radius, float height, uint64_t cap) {
        const uint64_t cost = MeshBuilder::cylinderCost(tankSegments_, true);
        if (cost > cap || !spend(cost)) return;
        b_.addCylinder({at.x, 0.0f, at.y}, {at.x, height, at.y}, radius, tankSegments_,
                       rng_.chance(0.7f) ? m_.tank : m_.tankAlt, true);
        structureTop_ = std::max(structureTop_, height);
    }

    void addTankCluster(const Rect& slot, uint64_t cap) {
        const float radius = 0.22f * std::min(slot.width(), slot.depth());
        for (int k = 0; k < 4; ++k) {
            const glm::vec2 at(slot.x0 + (k % 2 == 0 ? 0.25f : 0.75f) * slot.width(),
                               slot.z0 + (k / 2 == 0 ? 0.25f : 0.75f) * slot.depth());
            addTank(at, radius, rng_.uniform(4.0f, 10.0f), cap / 4);
        }
    }

    void addVessels(const Rect& slot, uint64_t cap) {
        // Horizontal pressure vessels on two saddles each, along the slot's longer side.
        const bool alongX = slot.width() >= slot.depth();
        const float length = 0.85f * (alongX ? slot.width() : slot.depth());
        const float across = alongX ? slot.depth() : slot.width();
        const int count = across > 9.0f ? 2 : 1;
        const float radius = std::min(1.8f, 0.35f * across / float(count));
        const uint64_t cost = MeshBuilder::cylinderCost(tankSegments_, true) + 2 * MeshBuilder::boxCost(kNoBottom);
        for (int k = 0; k < count; ++k) {
            if (cost * count > cap || !spend(cost)) return;
            const float offset = (float(k) + 0.5f) / float(count) - 0.5f;
            const glm::vec2 c = slot.center();
            const glm::vec3 axis = alongX ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
            const glm::vec3 side = alongX ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
            const glm::vec3 center = glm::vec3(c.x, radius + 0.6f, c.y) + side * (offset * across);
            b_.addCylinder(center - axis * (0.5f * length), center + axis * (0.5f * length), radius, tankSegments_,
                           m_.tankAlt, true);
            for (float s : {-0.3f, 0.3f}) {
                const glm::vec3 foot = center + axis * (s * length);
                const glm::vec3 half = axis * 0.3f + side * (0.8f * radius);
                b_.addBox(glm::min(foot - half, foot + half) * glm::vec3(1, 0, 1),
                          glm::max(foot - half, foot + half) * glm::vec3(1, 0, 1) + glm::vec3(0, 0.6f + 0.5f * radius, 0),
                          m_.steel, kNoBottom);
            }
            structureTop_ = std::max(structureTop_, 2.0f * radius + 0.6f);
        }
    }

    void addStack(const Rect& slot, uint64_t cap) {
        const glm::vec2 c = slot.center();
        const float radius = std::min(rng_.uniform(0.8f, 1.6f), 0.3f * std::min(slot.width(), slot.depth()));
        const float height = rng_.uniform(25.0f, kMaxStructureHeight);
        const uint64_t cost = MeshBuilder::cylinderCost(tankSegments_, true) + MeshBuilder::boxCost(kNoBottom);
        if (cost > cap || !spend(cost)) return;
        b_.addBox({c.x - 1.6f * radius, 0.0f, c.y - 1.6f * radius}, {c.x + 1.6f * radius, 2.0f, c.y + 1.6f * radius},
                  m_.pad, kNoBottom);
        b_.addCylinder({c.x, 2.0f, c.y}, {c.x, height, c.y}, radius, tankSegments_, m_.stack, true);
    }

    void addScaffold(const Rect& slot, uint64_t cap);
    void addStairFlight(float x0, float z0, float y0, bool positive);
    bool addPipeRun();
    void addJunctionBox();

    MeshBuilder& b_;
    const Materials& m_;
    Rng& rng_;
    Rect inner_;
    uint64_t remaining_;
    uint32_t tankSegments_ = 12, pipeSegments_ = 6;
    float splitX_ = 0.0f, splitZ_ = 0.0f;
    float structureTop_ = 2.0f; // highest tank/scaffold/vessel top so far (stacks excluded)
};

constexpr int kStairSteps = 16;

void UnitBuilder::addStairFlight(float x0, float z0, float y0, bool positive) {
    // 16 steps of 0.25 m rise and run: 4 m up over 4 m along x, 1 m wide.
    for (int k = 0; k < kStairSteps; ++k) {
        const float along = positive ? x0 + 0.25f * float(k) : x0 - 0.25f * float(k + 1);
        b_.addBox({along, y0 + 0.25f * float(k), z0}, {along + 0.25f, y0 + 0.25f * float(k + 1), z0 + 1.0f}, m_.grating);
    }
}

void UnitBuilder::addScaffold(const Rect& slot, uint64_t cap) {
    int nx = std::clamp(int(slot.width() / kBay), 1, 5), nz = std::clamp(int(slot.depth() / kBay), 1, 5);
    int levels = rng_.range(2, 6);
    auto cost = [&](int x, int z, int l, int flights) {
        const uint64_t box = MeshBuilder::boxCost();
        const uint64_t columns = uint64_t((x + 1) * (z + 1)) * MeshBuilder::boxCost(kNoBottom);
        const uint64_t beams = uint64_t(l * (x * (z + 1) + z * (x + 1))) * box;
        const uint64_t braces = uint64_t(l * 2 * (x + z)) * box;
        const uint64_t platforms = uint64_t((l + 1) / 2) * box;
        return columns + beams + braces + platforms + uint64_t(flights * kStairSteps) * box;
    };
    auto flightsFor = [&](int x, int l) { return x >= 2 ? l : 0; };
    while (cost(nx, nz, levels, flightsFor(nx, levels)) > cap && levels > 1) --levels;
    while (cost(nx, nz, levels, flightsFor(nx, levels)) > cap && (nx > 1 || nz > 1)) {
        if (nx >= nz) --nx;
        else --nz;
    }
    const int flights = flightsFor(nx, levels);
    const uint64_t total = cost(nx, nz, levels, flights);
    if (total > cap || !spend(total)) return;
    const glm::vec2 c = slot.center();
    const float x0 = c.x - 0.5f * kBay * float(nx), z0 = c.y - 0.5f * kBay * float(nz);
    const float top = kLevelHeight * float(levels);
    const float col = 0.125f, beam = 0.1f;
    for (int j = 0; j <= nz; ++j)
        for (int i = 0; i <= nx; ++i) {
            const float x = x0 + kBay * float(i), z = z0 + kBay * float(j);
            b_.addBox({x - col, 0.0f, z - col}, {x + col, top, z + col}, m_.steel, kNoBottom);
        }
    for (int l = 1; l <= levels; ++l) {
        const float y = kLevelHeight * float(l);
        for (int j = 0; j <= nz; ++j)
            for (int i = 0; i < nx; ++i) {
                const float x = x0 + kBay * float(i), z = z0 + kBay * float(j);
                b_.addBox({x + col, y - 2.5f * beam, z - beam}, {x + kBay - col, y, z + beam}, m_.steel);
            }
        for (int i = 0; i <= nx; ++i)
            for (int j = 0; j < nz; ++j) {
                const float x = x0 + kBay * float(i), z = z0 + kBay * float(j);
                b_.addBox({x - beam, y - 2.5f * beam, z + col}, {x + beam, y, z + kBay - col}, m_.steel);
            }
        // Diagonal braces on the four outer faces, one per bay (oriented boxes along the bay's diagonal).
        const float y0 = y - kLevelHeight + 0.15f; // braces start above the ground (and the beams below)
        auto brace = [&](glm::vec3 from, glm::vec3 to, glm::vec3 faceNormal) {
            const glm::vec3 axis = 0.5f * (to - from);
            const glm::vec3 across = glm::normalize(glm::cross(axis, faceNormal)) * 0.06f; // right-handed frame
            b_.addOrientedBox(0.5f * (from + to), axis, glm::normalize(faceNormal) * 0.06f, across, m_.steel);
        };
        for (int i = 0; i < nx; ++i)
            for (float z : {z0, z0 + kBay * float(nz)}) {
                const float x = x0 + kBay * float(i);
                const bool up = (i + l) % 2 == 0;
                brace({x, up ? y0 : y, z}, {x + kBay, up ? y : y0, z}, {0, 0, z == z0 ? -1.0f : 1.0f});
            }
        for (int j = 0; j < nz; ++j)
            for (float x : {x0, x0 + kBay * float(nx)}) {
                const float z = z0 + kBay * float(j);
                const bool up = (j + l) % 2 == 0;
                brace({x, up ? y0 : y, z}, {x, up ? y : y0, z + kBay}, {x == x0 ? -1.0f : 1.0f, 0, 0});
            }
        if (l % 2 == 0 || l == levels)
            b_.addBox({x0 - col, y, z0 - col}, {x0 + kBay * float(nx) + col, y + 0.08f, z0 + kBay * float(nz) + col},
                      m_.grating);
    }
    // Stair flights zig-zagging up from level to level inside the first bay row.
    for (int f = 0; f < flights; ++f) {
        const bool positive = f % 2 == 0;
        addStairFlight(positive ? x0 + 0.5f : x0 + 4.5f, z0 + 1.0f, kLevelHeight * float(f), positive);
    }
    structureTop_ = std::max(structureTop_, top + 0.1f);
}

// A pipe run: starts at a node of the unit's pipe corridors (edges and split lines), rises, runs along
// corridors with turns, ramps and possibly a diagonal leg above the structures, and comes back down.
bool UnitBuilder::addPipeRun() {
    const float xs[3] = {inner_.x0 + 0.75f, splitX_, inner_.x1 - 0.75f};
    const float zs[3] = {inner_.z0 + 0.75f, splitZ_, inner_.z1 - 0.75f};
    const float radius = rng_.uniform(0.08f, 0.35f);
    const glm::vec2 offset(rng_.uniform(-0.6f, 0.6f), rng_.uniform(-0.6f, 0.6f));
    auto node = [&](int i, int j, float y) { return glm::vec3(xs[i] + offset.x, y, zs[j] + offset.y); };

    std::vector<glm::vec3> points;
    int i = rng_.range(0, 2), j = rng_.range(0, 2);
    float y = rng_.uniform(2.0f, 12.0f);
    points.push_back(node(i, j, 0.5f)); // ends 0.5 m up: flanges stay above the ground
    points.push_back(node(i, j, y));
    const int legs = rng_.range(2, 4);
    for (int leg = 0; leg < legs; ++leg) {
        if (rng_.chance(0.12f)) {
            // Diagonal in plan, above every structure of the unit so far.
            const float high = structureTop_ + rng_.uniform(2.0f, 5.0f);
            points.push_back(node(i, j, high));
            int ni = i, nj = j;
            while (ni == i) ni = rng_.range(0, 2);
            while (nj == j) nj = rng_.range(0, 2);
            i = ni, j = nj, y = high;
            points.push_back(node(i, j, y));
            continue;
        }
        const bool alongX = rng_.chance(0.5f);
        int next = alongX ? i : j;
        while (next == (alongX ? i : j)) next = rng_.range(0, 2);
        const glm::vec3 end = alongX ? node(next, j, y) : node(i, next, y);
        const float length = glm::length(end - points.back());
        if (length > 6.0f && rng_.chance(0.4f)) {
            // Ramp at 45 degrees in the vertical plane over the last part of the leg.
            const float rise = std::min(length - 3.0f, 3.0f) * (y > 6.0f ? -1.0f : 1.0f);
            const glm::vec3 direction = glm::normalize(end - points.back());
            points.push_back(end - direction * std::fabs(rise));
            y += rise;
            points.push_back(end + glm::vec3(0.0f, rise, 0.0f));
        } else {
            points.push_back(end);
        }
        (alongX ? i : j) = next;
    }
    points.push_back(glm::vec3(points.back().x, 0.5f, points.back().z));
    // Drop legs too short to draw (a random height can meet the next one).
    std::vector<glm::vec3> kept{points.front()};
    for (size_t k = 1; k < points.size(); ++k)
        if (glm::length(points[k] - kept.back()) > 0.05f) kept.push_back(points[k]);
    points.swap(kept);
    if (points.size() < 2) return true;

    const uint64_t joints = points.size(), segments = points.size() - 1;
    const uint64_t cost = segments * MeshBuilder::cylinderCost(pipeSegments_, false) + joints * MeshBuilder::boxCost();
    if (!spend(cost)) return false;
    const uint32_t material = m_.pipe[rng_.below(3)];
    const float flange = 1.3f * radius;
    for (size_t k = 0; k < points.size(); ++k) {
        b_.addBox(points[k] - glm::vec3(flange), points[k] + glm::vec3(flange), m_.valve);
        if (k > 0) b_.addCylinder(points[k - 1], points[k], radius, pipeSegments_, material, false);
    }
    return true;
}

void UnitBuilder::addJunctionBox() {
    spend(MeshBuilder::boxCost());
    const float size = rng_.uniform(0.4f, 1.0f);
    const float x = rng_.uniform(inner_.x0, inner_.x1 - size), z = rng_.uniform(inner_.z0, inner_.z1 - size);
    b_.addBox({x, 0.0f, z}, {x + size, size, z + size}, m_.valve);
}

// Bundles of 2-3 pipes crossing the lane between two neighbouring units, on portal columns inside them.
void addPipeBridges(MeshBuilder& builder, const StreetGrid& g, const Materials& m, Rng& rng) {
    for (int axis = 0; axis < 2; ++axis) {
        const int along = axis == 0 ? g.cellsX() - 1 : g.cellsZ() - 1;
        const int across = axis == 0 ? g.cellsZ() : g.cellsX();
        for (int k = 0; k < along; ++k) {
            for (int c = 0; c < across; ++c) {
                if (!rng.chance(0.35f)) continue;
                // Span from 3 m inside cell k to 3 m inside cell k+1, at a lateral position within the row.
                const float s0 = axis == 0 ? g.cellX1(k) - 3.0f : g.cellZ1(k) - 3.0f;
                const float s1 = axis == 0 ? g.cellX0(k + 1) + 3.0f : g.cellZ0(k + 1) + 3.0f;
                const float lo = axis == 0 ? g.cellZ0(c) : g.cellX0(c), hi = axis == 0 ? g.cellZ1(c) : g.cellX1(c);
                const float lateral = rng.uniform(lo + 4.0f, hi - 6.0f);
                const float height = rng.uniform(7.0f, 9.0f);
                const int pipes = rng.range(2, 3);
                auto at = [&](float s, float t, float y) {
                    return axis == 0 ? glm::vec3(s, y, t) : glm::vec3(t, y, s);
                };
                for (int p = 0; p < pipes; ++p)
                    builder.addCylinder(at(s0, lateral + 0.7f * float(p), height + 0.3f),
                                        at(s1, lateral + 0.7f * float(p), height + 0.3f), 0.25f, 8, m.pipe[p % 3], true);
                for (float s : {s0 + 0.5f, s1 - 0.5f}) {
                    const glm::vec3 a = at(s - 0.2f, lateral - 0.4f, 0.0f), b = at(s + 0.2f, lateral + 0.7f * float(pipes - 1) + 0.4f, height);
                    builder.addBox(glm::min(a, b), glm::max(a, b), m.steel, kNoBottom);
                }
            }
        }
    }
}

} // namespace

void generatePlant(const ProceduralSpec& spec, MeshBuilder& builder) {
    const StreetGrid g = makePlantGrid(spec);
    const uint64_t target = spec.targetTriangles;
    builder.reserve(target + 64, 2 * target + 256);
    const Materials m = addMaterials(builder);
    Rng rng(spec.seed, kDetailStream);

    const float x0 = g.minX(), x1 = g.maxX(), z0 = g.minZ(), z1 = g.maxZ();
    const float margin = 40.0f + 0.25f * (x1 - x0);
    builder.addQuad({x0, 0, z0}, {x0, 0, z1}, {x1, 0, z1}, {x1, 0, z0}, m.lane);
    builder.addQuad({x0 - margin, 0, z0 - margin}, {x0 - margin, 0, z0}, {x1 + margin, 0, z0}, {x1 + margin, 0, z0 - margin}, m.ground);
    builder.addQuad({x0 - margin, 0, z1}, {x0 - margin, 0, z1 + margin}, {x1 + margin, 0, z1 + margin}, {x1 + margin, 0, z1}, m.ground);
    builder.addQuad({x0 - margin, 0, z0}, {x0 - margin, 0, z1}, {x0, 0, z1}, {x0, 0, z0}, m.ground);
    builder.addQuad({x1, 0, z0}, {x1, 0, z1}, {x1 + margin, 0, z1}, {x1 + margin, 0, z0}, m.ground);
    for (int j = 0; j < g.cellsZ(); ++j)
        for (int i = 0; i < g.cellsX(); ++i)
            builder.addBox({g.cellX0(i), 0.0f, g.cellZ0(j)}, {g.cellX1(i), 0.2f, g.cellZ1(j)}, m.pad, kNoBottom);
    addPipeBridges(builder, g, m, rng);

    const uint64_t used = builder.triangleCount();
    const uint64_t budget = target > used ? target - used : 0;
    const uint64_t units = uint64_t(g.cellsX()) * uint64_t(g.cellsZ());
    for (int j = 0; j < g.cellsZ(); ++j)
        for (int i = 0; i < g.cellsX(); ++i) {
            const uint64_t index = uint64_t(j) * uint64_t(g.cellsX()) + uint64_t(i);
            const Rect inner{g.cellX0(i) + kUnitMargin, g.cellZ0(j) + kUnitMargin, g.cellX1(i) - kUnitMargin,
                             g.cellZ1(j) - kUnitMargin};
            UnitBuilder(builder, m, rng, inner, budget / units + (index < budget % units ? 1 : 0)).build();
        }
}

PlantSummary summarizePlant(const ProceduralSpec& spec) {
    // Bound: stacks reach kMaxStructureHeight; scaffolds 24 m, diagonal pipes at most 5 m above them.
    return {makePlantGrid(spec), kMaxStructureHeight + 5.0f};
}

} // namespace chcrt::procedural
