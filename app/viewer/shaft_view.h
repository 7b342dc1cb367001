#pragma once
// The viewer's "shafts" view: the binary Line Space of one picked Line Space node (Keul et al., representative
// candidate paper §3.2 "Adaptation to BVH"; linespace/README.md), drawn over the shaded frame. Everything runs on
// the CPU: the pick traces the pixel's primary ray with the CPU twin of the GLSL tracer, the node is the Line
// Space node of the cut (depth D, threshold T) whose subtree holds the hit triangle, and its bitset is computed
// with the same builder and dilation as linespace/linespace_build.cpp, so the bits are those the bvh+ls* methods
// use for that node with the same N/D/T. Each pixel's primary ray (as shaders/render/raygen.frag.glsl makes it) is
// classified into its shaft of the node's box (shaftIndexForRay): green = empty shaft (a Line Space traversal
// skips the node for that ray), red = filled; the box's edges are drawn in white.
#include "renderer/bvh/bvh.h"
#include "renderer/core/aabb.h"
#include "renderer/scene/scene.h"

#include <cstdint>
#include <optional>
#include <vector>

namespace chcrt::app {

struct ShaftPick {
    int pixelX = 0, pixelY = 0;      // internal image, rows top to bottom
    uint32_t triangleId = 0;         // original id of the primary hit
    uint32_t space = 0;              // index of the node in the Line Space cut (LineSpaces::bvhNodes order)
    uint32_t spaceCount = 0;         // Line Space nodes of the cut
    uint32_t bvhNode = 0;
    uint32_t subtreeTriangles = 0;
    Aabb box;
    uint32_t n = 0, depth = 0, triangleThreshold = 0;
    uint64_t shafts = 0, filled = 0; // symmetric binary shafts (15 N^4) and the non-empty ones
    uint32_t pickedShaft = 0;        // the shaft of the picked pixel's primary ray (symmetric index)
    std::vector<uint32_t> words;     // the bitset, symmetric layout
    double buildMs = 0;
    double fillRate() const { return shafts ? double(filled) / double(shafts) : 0.0; }
};

// The primary ray's direction through the centre of pixel (x, y) (rows top to bottom), as raygen.frag.glsl.
glm::vec3 primaryRayDirection(const Camera& camera, int width, int height, float x, float y);

// Picks the Line Space node under pixel (x, y): nullopt when the primary ray misses the scene.
std::optional<ShaftPick> pickLineSpaceNode(const Bvh& bvh, const Camera& camera, int width, int height, int x, int y,
                                           uint32_t n, uint32_t depth, uint32_t triangleThreshold);

// Draws the pick over `rgb` (width × height × 3, rows top to bottom, display values in [0, 1]): pixels whose
// primary ray's line meets the node's box are tinted green (empty shaft) or red (filled), the others darkened,
// the box's edges white; pixels whose ray lies in the picked pixel's shaft get full blue (magenta when filled,
// cyan when empty). Returns the number of pixels whose ray meets the box.
uint64_t drawShafts(const ShaftPick& pick, const Camera& camera, int width, int height, std::vector<float>& rgb);

} // namespace chcrt::app
