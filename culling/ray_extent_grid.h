#pragma once
// Where the rays of a ray set can reach, per screen cell: the box around every active ray's segment
// [origin + tmin·d, origin + tmax·d] in each CHCRT_CULLING_RAY_CELL² block of pixels, reduced on the GPU
// (shaders/culling/ray_cell_bounds.comp.glsl) and read back once per trace (16 bytes × 2 per cell).
//
// Our addition to CHC+RT (not in the paper): a query pair whose node boxes miss the boxes of every cell of its
// tile cannot be hit by any ray of the tile, so it is invisible without an occlusion query, and a previously
// visible leaf in that case needs no intersection pass. Bounded rays — shadow rays end at their light sample, AO
// rays after the AO length — reach a small part of a large scene, while on a CPU rasteriser an occlusion query
// costs about as much as the traversal it saves (culling/README.md). The test is conservative: cell boxes are
// padded for the float rounding of the segment end points and of the hit points, so hits stay exactly those of
// pure BVH tracing (tests: ChcrtExactness*, RayExtentGrid*). Cells with an unbounded ray (primary and diffuse
// rays, tmax beyond CHCRT_CULLING_RAY_UNBOUNDED_T) or a NaN never cull anything.
#include "culling/query_pair_hierarchy.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"

#include <glm/glm.hpp>

#include <vector>

namespace chcrt {

class RayExtentGrid {
public:
    RayExtentGrid() = default;

    // Reduces the rays of a width × height ray set (RayTextures' origin+tmin and direction+tmax textures) to cell
    // boxes and reads them back (waits for the GPU). Needs a current GL context (the first call compiles the
    // reduction shader).
    void update(GLuint origins, GLuint directions, int width, int height);

    // True when some active ray of `tile`'s pixels may meet one of the `count` boxes (lower[i], upper[i]); false
    // means no ray of the tile can hit anything inside them. Tiles are in pixels of the ray set, GL orientation.
    bool mayReach(const Tile& tile, const glm::vec3* lower, const glm::vec3* upper, int count) const;

    // Drops the cells: nothing is known, mayReach is true everywhere (for ray sets known to be unbounded).
    void forget() { cells_.clear(); }

    int cellsX() const { return cellsX_; }
    int cellsY() const { return cellsY_; }

    // The CPU side alone, for tests: cells from read-back images (RGBA per cell, lower.xyz + state, upper.xyz).
    void setCells(int width, int height, const std::vector<glm::vec4>& lower, const std::vector<glm::vec4>& upper);

private:
    struct Cell {
        glm::vec3 lower{0.0f}, upper{0.0f};
        enum State : uint8_t { Empty, Bounded, Unbounded } state = Empty;
    };
    ShaderProgram program_;
    GlTexture lower_, upper_;
    int cellsX_ = 0, cellsY_ = 0;
    std::vector<Cell> cells_; // row-major, cell row 0 = pixel rows 0..CELL-1 (GL orientation)
    std::vector<glm::vec4> readLower_, readUpper_;
};

} // namespace chcrt
