#pragma once
// CHC+RT §4.3-4.4: the query-pair hierarchy is the product of a screen-space quadtree (tiles = packets of rays,
// one ray per pixel) and the BVH above the termination cut (subtree_partition.h). This file holds its pure
// geometry and decisions: tiles, the split heuristic and the termination test. The stored hierarchy with
// visibility is visibility_state.h; the GL passes and Algorithm 1 are chcrt_tracer.h.
#include "culling/culling_hierarchy.h"
#include "culling/subtree_partition.h"

#include <array>
#include <cstdint>

namespace chcrt {

// A screen-space tile in pixels (GL window coordinates, y up).
struct Tile {
    int x = 0, y = 0, width = 0, height = 0;
    int64_t area() const { return int64_t(width) * height; }
    bool operator==(const Tile&) const = default;
};

struct QueryPairOptions {
    // §4.4: split in object space when A_bvh / A_root > tq * A_tile / A_screen (favours object splits early).
    float tq = 0.5f;
    // §5.2 minimum tile size (edge, pixels). The paper used 200² at 1920×1080 (< 2% of the screen); 64² is 1.6%
    // of the 512×512 frames used here, and halving 512 three times lands on it exactly.
    int minTileSize = 64;
};

enum class PairSplit : uint8_t { None, Object, Screen };

// How to subdivide the pair (tile, node): None when it is terminal (tile at the minimum size and node a
// termination root), otherwise the heuristic's domain, or the other one when that domain cannot split.
PairSplit decideSplit(const Tile& tile, uint32_t node, const SubtreePartition& partition, int screenWidth,
                      int screenHeight, const QueryPairOptions& options);

// The same on the culling hierarchy (culling_hierarchy.h; `node` indexes its nodes), as the tracer uses it.
PairSplit decideSplit(const Tile& tile, uint32_t node, const CullingHierarchy& hierarchy, int screenWidth,
                      int screenHeight, const QueryPairOptions& options);

// The heuristic alone (§4.4), for tests: true = object space.
bool preferObjectSplit(float nodeArea, float rootArea, int64_t tileArea, int64_t screenArea, float tq);

// Screen split into 4 quadrants (2 when one side is already at the minimum). Returns the number of children.
int splitTile(const Tile& tile, int minTileSize, std::array<Tile, 4>& children);

} // namespace chcrt
