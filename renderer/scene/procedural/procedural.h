#pragma once
// Procedural scenes, deterministic by seed, with a triangle budget that scales from ~10k to 10M+ in memory:
// a city (2.5D blocks of buildings with facade detail and streets; street-level views are heavily occluded,
// like the CHC+RT paper's City models), an interior (rooms, corridors, doors, pillars: very high occlusion),
// an industrial plant (pipes, tanks, scaffolds: irregular and deep, like the Powerplant), and small analytic
// scenes for tests. Each large scene comes with a near-view (street level / inside) and a far-view (bird's
// eye) camera path, like the paper's two walkthroughs.
#include "renderer/core/progress.h"
#include "renderer/scene/camera_path.h"
#include "renderer/scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace chcrt {

// Large generated scenes (ground at y = 0, metres, +Y up; triangle counts within 10 % of the target for
// 10k..20M, in practice a few triangles below it):
//   City      blocks of 45-75 m separated by 16 m streets (10 m road, 3 m sidewalks, 0.15 m high), each block
//             split into 2x2..3x3 lots whose buildings fill the lot up to the sidewalk (3x3: a park in the
//             middle); towers near the centre (up to 200 m). Facade detail (windows, ribbon windows,
//             balconies up to 1.2 m deep, cornices) on street-facing walls takes the budget. ~25k triangles
//             per block; the city is centred at the origin.
//   Interior  2-4 storeys (3.0 m rooms, 3.3 m storey pitch) of wings: a row of 5-7 m rooms, a 2.6 m
//             corridor, a row of rooms; 1.1 x 2.2 m door openings in the middle of walls, 0.5 m pillars at
//             every wall junction, furniture stacked in room corners. The top storey has no ceiling
//             (cut-away for the far view). Origin at the building's corner, building in +x/+z.
//   Plant     process units of 30-46 m separated by 10 m lanes: tanks, vessels, stacks (<= 55 m), scaffold
//             towers with platforms and stairs, pipe runs (axis-aligned, 45-degree ramps, diagonal legs in
//             plan); pipe bridges cross lanes at 7-9.5 m. Centred at the origin.
// Analytic scenes (exact, for tests; the count and seed are ignored):
//   PlaneAndBox  14 triangles: the ground quad [-10,10] x {0} x [-10,10] (2 triangles, normal +Y, material 0)
//                and the box [-1,1] x [0,2] x [-1,1] (12 triangles, outward normals, material 1).
//   ClosedBox    12 triangles: the box [-5,5] x [0,10] x [-5,5] with inward normals; materials floor 0,
//                ceiling 1, walls z = +-5 2, wall x = -5 3 (red), wall x = +5 4 (green).
//   OneTriangle  positions (-1,0,-1), (1,0,-1), (0,0,1), all normals +Y, triangle indices {0, 2, 1} (so the
//                winding is counter-clockwise seen from +Y, agreeing with the normal), material 0.
enum class ProceduralKind { City, Interior, Plant, PlaneAndBox, ClosedBox, OneTriangle };

struct ProceduralSpec {
    ProceduralKind kind = ProceduralKind::City;
    uint64_t targetTriangles = 1'000'000; // generators land within ±10% (analytic scenes ignore it)
    uint32_t seed = 1;
};

// Parses generator specs as used by --scene: "city", "city:2m", "interior:500k", "plant:10m:seed=7",
// "plane-and-box", "closed-box", "one-triangle". Counts accept k/m suffixes and decimals ("1.5m"), from 1
// to 1000m (below ~10k the smallest layout can exceed the target). Returns false when `text`
// is not a generator spec (so callers try it as a file path); throws InputError for a malformed one
// (e.g. "city:abc").
bool parseProceduralSpec(const std::string& text, ProceduralSpec& spec);
std::string toString(const ProceduralSpec& spec); // canonical form, e.g. "city:1000000:seed=1"
// "city, interior, plant, plane-and-box, closed-box, one-triangle": the generators, for messages.
std::string proceduralGeneratorNames();

// Generates the scene. Materials have distinct base colours (facades, roofs, streets, ...). Normals are flat
// per face (vertices are not shared across faces with different normals). Units: metres, +Y up.
// Reports one step "Generating <spec>" to `progress`, its total the target triangle count (0 for the analytic
// scenes); generators land within ±10 % of it, so the count may stop short of the total before the step ends.
Scene generateProceduralScene(const ProceduralSpec& spec, Progress& progress = nullProgress());

// Default walkthroughs of a generated scene ("near" at street level / inside, "far" from above), valid for
// any seed and size of that kind: the near path never passes through geometry. For analytic scenes, both
// are a single camera looking at the scene.
//   near: 30 fps, fovY 60, 10-20 s. City: eye 1.7 m on the road's centre line, 2-4 block edges along
//         internal streets with turns at crossings (starting and ending mid-block). Plant: the same along
//         lanes. Interior: eye 1.6 m on the ground floor, along the first corridor, through two rooms (door,
//         partition door, door) and into a third.
//   far:  30 fps, fovY 60, 16 s: a quarter circle at 0.9 x the scene's half extent from its centre, at least
//         1.4 x the half extent high (and above all geometry), looking at the centre on the ground.
//   analytic: PlaneAndBox eye (6,5,8) -> (0,1,0); ClosedBox eye (0,5,4.5) -> (0,4,-5) (inside);
//         OneTriangle eye (0,3,3) -> (0,0,0).
CameraPath proceduralNearPath(const ProceduralSpec& spec);
CameraPath proceduralFarPath(const ProceduralSpec& spec);

// The rectangular area light used for soft shadows in a generated scene (a "sun" rectangle above it, placed
// so that shadows fall visibly into the near-view path's streets/rooms; an interior's light is a ceiling
// panel inside a room or slanted through openings, so that it still lights the near path).
// All lights are squares facing down (edgeU along +X, edgeV along +Z) with white radiance L = 3 d^2 / A,
// d = the light's height above the ground (or floor) below it, so that E ~ L A / d^2 = 3 there.
//   City/Plant: side 1/10 of the grid's extent, at max(2 x the tallest geometry, 1.2 x the half extent),
//               offset by (+0.35, +0.25) x the half extent so shadows fall diagonally across streets.
//   Interior:   1.2 m panel 5 cm below the ceiling of the first room the near path enters (ground floor).
//   PlaneAndBox, OneTriangle: 2 x 2 m centred at (0, 10, 0). ClosedBox: the same at y = 9.9 (inside the box,
//               not coplanar with its ceiling).
AreaLight proceduralAreaLight(const ProceduralSpec& spec);

} // namespace chcrt
