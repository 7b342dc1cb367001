#pragma once
// Procedural scenes, deterministic by seed, with a triangle budget that scales from ~10k to 10M+ in memory:
// a city (2.5D blocks of buildings with facade detail and streets; street-level views are heavily occluded,
// like the CHC+RT paper's City models), an interior (rooms, corridors, doors, pillars: very high occlusion),
// an industrial plant (pipes, tanks, scaffolds: irregular and deep, like the Powerplant), and small analytic
// scenes for tests. Each large scene comes with a near-view (street level / inside) and a far-view (bird's
// eye) camera path, like the paper's two walkthroughs.
#include "renderer/scene/camera_path.h"
#include "renderer/scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace chcrt {

enum class ProceduralKind { City, Interior, Plant, PlaneAndBox, ClosedBox, OneTriangle };

struct ProceduralSpec {
    ProceduralKind kind = ProceduralKind::City;
    uint64_t targetTriangles = 1'000'000; // generators land within ±10% (analytic scenes ignore it)
    uint32_t seed = 1;
};

// Parses generator specs as used by --scene: "city", "city:2m", "interior:500k", "plant:10m:seed=7",
// "plane-and-box", "closed-box", "one-triangle". Counts accept k/m suffixes. Returns false when `text`
// is not a generator spec (so callers try it as a file path); throws InputError for a malformed one
// (e.g. "city:abc").
bool parseProceduralSpec(const std::string& text, ProceduralSpec& spec);
std::string toString(const ProceduralSpec& spec); // canonical form, e.g. "city:1000000:seed=1"

// Generates the scene. Materials have distinct base colours (facades, roofs, streets, ...). Normals are flat
// per face (vertices are not shared across faces with different normals). Units: metres, +Y up.
Scene generateProceduralScene(const ProceduralSpec& spec);

// Default walkthroughs of a generated scene ("near" at street level / inside, "far" from above), valid for
// any seed and size of that kind: the near path never passes through geometry. For analytic scenes, both
// are a single camera looking at the scene.
CameraPath proceduralNearPath(const ProceduralSpec& spec);
CameraPath proceduralFarPath(const ProceduralSpec& spec);

// The rectangular area light used for soft shadows in a generated scene (a "sun" rectangle above it, placed
// so that shadows fall visibly into the near-view path's streets/rooms; an interior's light is a ceiling
// panel inside a room or slanted through openings, so that it still lights the near path).
AreaLight proceduralAreaLight(const ProceduralSpec& spec);

} // namespace chcrt
