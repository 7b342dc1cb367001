// Camera paths and area lights of the procedural scenes: near walkthroughs at eye height along streets,
// lanes and corridors; far paths circling above (CHC+RT §6 uses one near-view and one far-view walkthrough
// per scene: near views are heavily occluded, far views are not).
#include "renderer/scene/procedural/procedural_internal.h"

#include <algorithm>
#include <cmath>

namespace chcrt {
namespace procedural {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinDuration = 10.0, kMaxDuration = 20.0;

CameraPath emptyPath(const std::string& name) {
    CameraPath path;
    path.name = name;
    path.fps = 30.0;
    path.fovYDegrees = 60.0f;
    return path;
}

// Distance of p from segment [a, b] and its position s along it.
float distanceToSegment(const glm::vec2& p, const glm::vec2& a, const glm::vec2& b, float& s) {
    const glm::vec2 ab = b - a;
    const float length = glm::length(ab);
    s = std::clamp(glm::dot(p - a, ab) / length, 0.0f, length);
    return glm::length(a + ab * (s / length) - p);
}

} // namespace

StreetGrid makeStreetGrid(Rng& rng, int cellsX, int cellsZ, float minCell, float maxCell, float streetWidth) {
    StreetGrid grid;
    grid.streetWidth = streetWidth;
    auto lines = [&](int cells) {
        std::vector<float> result(size_t(cells) + 1, 0.0f);
        for (int i = 0; i < cells; ++i) result[i + 1] = result[i] + streetWidth + rng.uniform(minCell, maxCell);
        const float middle = 0.5f * result.back();
        for (float& line : result) line -= middle;
        return result;
    };
    grid.lineX = lines(cellsX);
    grid.lineZ = lines(cellsZ);
    return grid;
}

CameraPath walkPath(const std::vector<glm::vec2>& corners, const std::vector<glm::vec2>& gates,
                    const WalkStyle& style, const std::string& name) {
    struct Key { glm::vec2 position, direction; };
    std::vector<Key> keys;
    const size_t legs = corners.size() - 1;
    for (size_t k = 0; k < legs; ++k) {
        const glm::vec2 a = corners[k], b = corners[k + 1];
        const float length = glm::length(b - a);
        const glm::vec2 direction = (b - a) / length;
        // Positions along this leg, as distances from its start.
        std::vector<float> along;
        if (k == 0) along.push_back(0.0f);
        for (float offset : style.turnOffsets) {
            if (offset >= 0.45f * length) continue; // keep leg-start and leg-end keyframes in order
            if (k > 0) along.push_back(offset);
            if (k + 1 < legs) along.push_back(length - offset);
        }
        for (const glm::vec2& gate : gates) {
            float s = 0.0f;
            if (distanceToSegment(gate, a, b, s) > 1e-3f) continue;
            along.push_back(s - style.gateOffset);
            along.push_back(s + style.gateOffset);
        }
        if (k + 1 == legs) along.push_back(length);
        std::sort(along.begin(), along.end());
        // Fill long gaps with evenly spaced keyframes (on the leg, so the spline stays straight there).
        std::vector<float> filled;
        for (size_t i = 0; i < along.size(); ++i) {
            if (i > 0) {
                const int pieces = int(std::ceil((along[i] - along[i - 1]) / style.maxSpacing));
                for (int p = 1; p < pieces; ++p)
                    filled.push_back(along[i - 1] + (along[i] - along[i - 1]) * float(p) / float(pieces));
            }
            filled.push_back(along[i]);
        }
        float previous = -1.0f;
        for (float s : filled) {
            if (s < 0.0f || s > length || s - previous < 0.1f) continue;
            keys.push_back({a + direction * s, direction});
            previous = s;
        }
    }

    // Constant speed along the keyframe polyline, scaled so the walk lasts between 10 and 20 seconds.
    double total = 0.0;
    for (size_t i = 1; i < keys.size(); ++i) total += glm::length(keys[i].position - keys[i - 1].position);
    const double duration = std::clamp(total / style.nominalSpeed, kMinDuration, kMaxDuration);
    const double speed = total / duration;

    CameraPath path = emptyPath(name);
    double travelled = 0.0;
    for (size_t i = 0; i < keys.size(); ++i) {
        if (i > 0) travelled += glm::length(keys[i].position - keys[i - 1].position);
        CameraKeyframe key;
        key.t = i + 1 == keys.size() ? duration : travelled / speed; // exact end time
        key.eye = glm::vec3(keys[i].position.x, style.eyeHeight, keys[i].position.y);
        key.target = key.eye + style.lookAhead * glm::vec3(keys[i].direction.x, 0.0f, keys[i].direction.y) +
                     glm::vec3(0.0f, style.lookUp, 0.0f);
        path.keyframes.push_back(key);
    }
    return path;
}

std::vector<glm::vec2> streetRoute(const StreetGrid& grid, uint32_t seed) {
    Rng rng(seed, kPathStream);
    const int nx = grid.cellsX(), nz = grid.cellsZ();
    // Only internal streets (not the border ones) are lined with blocks on both sides.
    auto allowed = [&](glm::ivec2 from, glm::ivec2 step) {
        const glm::ivec2 to = from + step;
        if (to.x < 0 || to.x > nx || to.y < 0 || to.y > nz) return false;
        return step.x != 0 ? (from.y >= 1 && from.y <= nz - 1) : (from.x >= 1 && from.x <= nx - 1);
    };
    glm::ivec2 at(rng.range(0, std::max(0, nx - 2)), rng.range(1, std::max(1, nz - 1)));
    glm::ivec2 heading(1, 0);
    std::vector<glm::ivec2> visited{at};
    const int maxEdges = 4;
    for (int edge = 0; edge < maxEdges; ++edge) {
        std::vector<glm::ivec2> options;
        if (edge == 0) options.push_back(heading);
        else {
            const glm::ivec2 left(heading.y, -heading.x), right(-heading.y, heading.x);
            for (glm::ivec2 step : {left, right, heading}) {
                if (!allowed(at, step)) continue;
                if (std::find(visited.begin(), visited.end(), at + step) != visited.end()) continue;
                options.push_back(step);
            }
        }
        if (options.empty()) break;
        // Avoid border crossings (dead ends: border streets are not walked) while there is another way.
        auto onBorder = [&](glm::ivec2 step) {
            const glm::ivec2 to = at + step;
            return to.x == 0 || to.x == nx || to.y == 0 || to.y == nz;
        };
        std::vector<glm::ivec2> inside;
        for (glm::ivec2 step : options)
            if (!onBorder(step)) inside.push_back(step);
        if (!inside.empty()) options = inside;
        // Prefer turning at crossings (60 %) so that each walk has corners to look around.
        const bool canGoStraight = options.back() == heading;
        glm::ivec2 step = options.back();
        const size_t turns = options.size() - (canGoStraight ? 1 : 0);
        if (turns > 0 && (!canGoStraight || rng.chance(0.6f))) step = options[rng.below(uint32_t(turns))];
        at += step;
        heading = step;
        visited.push_back(at);
    }
    // Start and end halfway along the first and last edges: between facades, not on a border street.
    std::vector<glm::vec2> points;
    for (const glm::ivec2& v : visited) points.emplace_back(grid.lineX[v.x], grid.lineZ[v.y]);
    const size_t last = points.size() - 1;
    if (last == 1) {
        const glm::vec2 a = points[0], b = points[1];
        points = {0.75f * a + 0.25f * b, 0.25f * a + 0.75f * b};
    } else {
        points[0] = 0.5f * (points[0] + points[1]);
        points[last] = 0.5f * (points[last - 1] + points[last]);
    }
    // Merge collinear crossings into corners.
    std::vector<glm::vec2> corners;
    for (size_t i = 0; i < points.size(); ++i) {
        if (i > 0 && i + 1 < points.size() && visited[i] - visited[i - 1] == visited[i + 1] - visited[i]) continue;
        corners.push_back(points[i]);
    }
    return corners;
}

CameraPath circlingPath(const glm::vec3& center, float radius, float height, uint32_t seed, const std::string& name) {
    Rng rng(seed, kPathStream);
    const double start = 2.0 * kPi * rng.uniform();
    const double sweep = 0.5 * kPi, duration = 16.0;
    const int segments = 8;
    CameraPath path = emptyPath(name);
    for (int k = 0; k <= segments; ++k) {
        const double angle = start + sweep * k / segments;
        CameraKeyframe key;
        key.t = duration * k / segments;
        key.eye = center + glm::vec3(float(radius * std::cos(angle)), height, float(radius * std::sin(angle)));
        key.target = center;
        path.keyframes.push_back(key);
    }
    return path;
}

AreaLight downwardLight(const glm::vec3& center, float size, float distanceToLit) {
    AreaLight light;
    light.corner = center - glm::vec3(0.5f * size, 0.0f, 0.5f * size);
    light.edgeU = glm::vec3(size, 0.0f, 0.0f);
    light.edgeV = glm::vec3(0.0f, 0.0f, size); // cross(edgeU, edgeV) = -Y: facing down
    // E ~ L * A * cos / d^2 for a small light straight above: L = E * d^2 / A with E = 3.
    light.radiance = glm::vec3(3.0f * distanceToLit * distanceToLit / (size * size));
    return light;
}

namespace {

float halfExtent(const StreetGrid& grid) {
    return 0.5f * std::max(grid.maxX() - grid.minX(), grid.maxZ() - grid.minZ());
}

CameraPath farOverGrid(const StreetGrid& grid, float top, uint32_t seed, const std::string& name) {
    const float half = halfExtent(grid);
    return circlingPath(glm::vec3(0.0f), 0.9f * half, std::max(1.4f * half, top + 0.5f * half), seed, name);
}

// A "sun" of side 1/10 of the scene, above the tallest geometry and offset diagonally so that shadows fall
// slanted into both street directions.
AreaLight lightOverGrid(const StreetGrid& grid, float top) {
    const float half = halfExtent(grid);
    const float height = std::max(2.0f * top, 1.2f * half);
    return downwardLight(glm::vec3(0.35f * half, height, 0.25f * half), 0.2f * half, height);
}

} // namespace
} // namespace procedural

using namespace procedural;

CameraPath proceduralNearPath(const ProceduralSpec& spec) {
    const std::string name = toString(spec) + "-near";
    switch (spec.kind) {
    case ProceduralKind::City: {
        const CitySummary city = summarizeCity(spec);
        return walkPath(streetRoute(city.grid, spec.seed), {}, WalkStyle{}, name);
    }
    case ProceduralKind::Plant: {
        const PlantSummary plant = summarizePlant(spec);
        WalkStyle style;
        style.nominalSpeed = 8.0f;
        style.lookUp = 1.0f;
        return walkPath(streetRoute(plant.grid, spec.seed), {}, style, name);
    }
    case ProceduralKind::Interior: {
        const InteriorSummary interior = summarizeInterior(spec);
        WalkStyle style;
        style.eyeHeight = 1.6f;
        style.lookAhead = 3.0f;
        style.lookUp = 0.0f;
        style.nominalSpeed = 1.5f;
        style.turnOffsets = {0.6f};
        style.maxSpacing = 3.0f;
        return walkPath(interior.pathCorners, interior.pathGates, style, name);
    }
    default: return analyticPath(spec);
    }
}

CameraPath proceduralFarPath(const ProceduralSpec& spec) {
    const std::string name = toString(spec) + "-far";
    switch (spec.kind) {
    case ProceduralKind::City: {
        const CitySummary city = summarizeCity(spec);
        return farOverGrid(city.grid, city.maxBuildingHeight, spec.seed, name);
    }
    case ProceduralKind::Plant: {
        const PlantSummary plant = summarizePlant(spec);
        return farOverGrid(plant.grid, plant.maxHeight, spec.seed, name);
    }
    case ProceduralKind::Interior: {
        const InteriorSummary interior = summarizeInterior(spec);
        const glm::vec3 extent = interior.bounds.extent();
        const float half = 0.5f * std::max(extent.x, extent.z);
        const glm::vec3 center(interior.bounds.center().x, 0.0f, interior.bounds.center().z);
        return circlingPath(center, 0.9f * half, std::max(1.4f * half, interior.bounds.upper.y + 0.5f * half),
                            spec.seed, name);
    }
    default: return analyticPath(spec);
    }
}

AreaLight proceduralAreaLight(const ProceduralSpec& spec) {
    switch (spec.kind) {
    case ProceduralKind::City: {
        const CitySummary city = summarizeCity(spec);
        return lightOverGrid(city.grid, city.maxBuildingHeight);
    }
    case ProceduralKind::Plant: {
        const PlantSummary plant = summarizePlant(spec);
        return lightOverGrid(plant.grid, plant.maxHeight);
    }
    case ProceduralKind::Interior: {
        // A ceiling panel in the first room the near path enters, 5 cm below the ceiling: the building is
        // closed, so a sun outside would leave the ground-floor walk unlit.
        const InteriorSummary interior = summarizeInterior(spec);
        const float height = interior.ceilingHeight - 0.05f;
        return downwardLight(glm::vec3(interior.lightRoomCenter.x, height, interior.lightRoomCenter.y), 1.2f,
                             height);
    }
    default: return analyticLight(spec);
    }
}

} // namespace chcrt
