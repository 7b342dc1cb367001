#pragma once
// Internals shared by the procedural generators and their camera paths. A generator's layout (street
// grid, floor plan) is a cheap function of the spec, so the paths recompute it instead of generating the
// geometry; what keeps a near path clear is the layout, by construction.
#include "renderer/scene/procedural/mesh_builder.h"
#include "renderer/scene/procedural/procedural.h"
#include "renderer/scene/procedural/rng.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace chcrt::procedural {

// Independent random streams per purpose (see Rng).
enum Stream : uint64_t { kLayoutStream = 1, kDetailStream = 2, kPathStream = 3 };

// ---- Street grid (city blocks, plant units) -------------------------------------------------------------

// A rectangular grid of cells ("blocks") separated by straight streets, with streets around the border too.
// Street k along z runs at x = lineX[k]; cell i spans x in [lineX[i] + streetWidth/2, lineX[i+1] - streetWidth/2].
struct StreetGrid {
    float streetWidth = 16.0f;
    std::vector<float> lineX; // cellsX + 1 street centre lines (streets running along z)
    std::vector<float> lineZ; // cellsZ + 1 street centre lines (streets running along x)

    int cellsX() const { return int(lineX.size()) - 1; }
    int cellsZ() const { return int(lineZ.size()) - 1; }
    float cellX0(int i) const { return lineX[i] + 0.5f * streetWidth; }
    float cellX1(int i) const { return lineX[i + 1] - 0.5f * streetWidth; }
    float cellZ0(int j) const { return lineZ[j] + 0.5f * streetWidth; }
    float cellZ1(int j) const { return lineZ[j + 1] - 0.5f * streetWidth; }
    // Outer edges of the border streets.
    float minX() const { return lineX.front() - 0.5f * streetWidth; }
    float maxX() const { return lineX.back() + 0.5f * streetWidth; }
    float minZ() const { return lineZ.front() - 0.5f * streetWidth; }
    float maxZ() const { return lineZ.back() + 0.5f * streetWidth; }
};

// Cell sizes uniform in [minCell, maxCell], the whole grid centred at the origin.
StreetGrid makeStreetGrid(Rng& rng, int cellsX, int cellsZ, float minCell, float maxCell, float streetWidth);

// ---- Camera path helpers (paths.cpp) ----------------------------------------------------------------------

struct WalkStyle {
    float eyeHeight = 1.7f;
    float lookAhead = 20.0f;   // target distance ahead along the direction of travel
    float lookUp = 2.0f;       // target height above the eye
    float nominalSpeed = 12.0f; // m/s; adjusted so the path lasts between 10 and 20 s
    std::vector<float> turnOffsets{12.0f, 4.0f}; // keyframes at these distances before and after each turn
    float gateOffset = 0.45f;  // keyframes at +-this around each gate (door) on a leg
    float maxSpacing = 15.0f;  // longer straight stretches get intermediate keyframes
};

// A walkthrough along a polyline of corners in the ground plane (x, z) with axis-aligned or straight legs.
// Turns are rounded by keyframes at WalkStyle::turnOffsets before/after each corner; gates (door centres,
// lying on legs) get keyframes just before and after them so the spline is exactly straight through them
// (a centripetal Catmull-Rom segment is straight when its four control points are collinear).
CameraPath walkPath(const std::vector<glm::vec2>& corners, const std::vector<glm::vec2>& gates,
                    const WalkStyle& style, const std::string& name);

// A route of 2..4 edges along internal streets of the grid (never the border streets), chosen by seed.
std::vector<glm::vec2> streetRoute(const StreetGrid& grid, uint32_t seed);

// A bird's-eye path: circles `center` at `radius`, `height` above it, looking at the centre.
CameraPath circlingPath(const glm::vec3& center, float radius, float height, uint32_t seed, const std::string& name);

// A downward-facing square light of side `size` centred at `center`, with radiance such that a white
// Lambertian plane `distanceToLit` below receives irradiance E ~ 3 (E ~ L * A / d^2 for a small light).
AreaLight downwardLight(const glm::vec3& center, float size, float distanceToLit);

// ---- Generators and their layouts ------------------------------------------------------------------------

void generateCity(const ProceduralSpec& spec, MeshBuilder& builder);
void generateInterior(const ProceduralSpec& spec, MeshBuilder& builder);
void generatePlant(const ProceduralSpec& spec, MeshBuilder& builder);
void generateAnalytic(const ProceduralSpec& spec, MeshBuilder& builder);

struct CitySummary {
    StreetGrid grid;
    float maxBuildingHeight = 0.0f;
};
CitySummary summarizeCity(const ProceduralSpec& spec);

// The city in parts, for streaming preparation of cities larger than RAM (renderer/outofcore/): the ground
// (streets, sidewalks, parks) and any range of buildings with their facade detail. The union of
// generate(true, 0, 0) and generate(false, b0, b1) over a partition of the buildings is exactly
// generateCity's geometry (in another triangle order). Each part starts with the same materials.
class CityParts {
public:
    explicit CityParts(const ProceduralSpec& spec);
    ~CityParts();
    uint32_t buildingCount() const;
    uint64_t groundTriangles() const;
    uint64_t buildingTriangles(uint32_t building) const; // with its facade detail
    void generate(bool ground, uint32_t firstBuilding, uint32_t endBuilding, MeshBuilder& builder) const;

private:
    struct Plan;
    std::unique_ptr<Plan> plan_;
};

struct PlantSummary {
    StreetGrid grid;
    float maxHeight = 0.0f; // upper bound of any geometry (by construction)
};
PlantSummary summarizePlant(const ProceduralSpec& spec);

// The interior's ground-floor near path corners, door gates, bounds and the room the light is in.
struct InteriorSummary {
    std::vector<glm::vec2> pathCorners;
    std::vector<glm::vec2> pathGates;
    glm::vec2 lightRoomCenter{0.0f};
    float ceilingHeight = 3.0f;
    Aabb bounds;
};
InteriorSummary summarizeInterior(const ProceduralSpec& spec);

CameraPath analyticPath(const ProceduralSpec& spec);
AreaLight analyticLight(const ProceduralSpec& spec);

} // namespace chcrt::procedural
