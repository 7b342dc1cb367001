#pragma once
// Where the rays of a ray set can still change their hits, per screen cell: the boxes around `pieces` consecutive
// pieces of every active ray's segment in each cellSize² block of pixels, reduced on the GPU
// (shaders/culling/ray_bounds.comp.glsl) and read back once per update. A ray's segment runs from tmin to tmax —
// or, after hits were found, to its hit t for closest-hit rays, and not at all for any-hit rays that hit — clipped
// to the scene's box. A depth pyramid for rays: the boxes play the role a depth texel plays in hierarchical-Z
// culling (nvpro gl_occlusion_culling, zeux/niagara), and a coarse level (coarseCells² cells) lets a large tile
// be tested against few boxes.
//
// Our addition to CHC+RT (not in the paper): a query pair whose node boxes miss the boxes of every cell of its
// tile cannot be hit by any ray of the tile before its current hit, so it is invisible without an occlusion query
// (and a visible leaf in that case needs no intersection); a subtree need not be traversed by the rays of a cell
// whose boxes it misses. Pieces matter for long diagonal segments (shadow rays towards a high light, rays from the
// eye to a far hit), whose single box would cover a wide slab of the scene. The test is conservative: boxes are
// padded by 2^-12 of the magnitude of the coordinates the end points were computed from, far above their float
// rounding and that of the hits a traversal accepts, so hits stay exactly those of pure BVH tracing (tests:
// ChcrtExactness*, RayBoundsGrid*). Cells with a NaN or infinite ray value cull nothing.
#include "culling/hemisphere_ray_bounds.h"
#include "culling/query_pair_hierarchy.h"
#include "renderer/render/camera_math.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/program_cache.h"
#include "renderer/gl/shader.h"

#include <glm/glm.hpp>

#include <array>
#include <memory>
#include <vector>

namespace chcrt {

struct RayBoundsOptions {
    int cellSize = 8;    // pixels per cell edge (a power of two, 1..32)
    int pieces = 4;      // boxes per cell, each around an equal fraction of every ray's segment (1..8)
    int coarseCells = 8; // cells per coarse-cell edge (1..64)
    // Boxes grow by this fraction of the magnitude of the coordinates their end points were computed from, which
    // covers the float rounding of the end points and of accepted hits with a wide margin (0.7 m at 3 km). Tests
    // shrink boxes with a negative value to show that the exactness comparisons catch a bound that is too small.
    float relativePad = 1.0f / 4096.0f;
    // Also test the cell's ray interval ("frustum": origin box, direction box, segment range; rayIntervalMayHit in
    // shaders/shared/culling_layout.h): a box must meet a piece and the interval.
    bool frustum = true;
    // Primary rays the renderer generated from a camera (TraceRequest::cameraRays) get their cells before any hit
    // from the camera alone (setCameraCells), without the reduction and its read-back.
    bool cameraRays = true;
};

class RayBoundsGrid {
public:
    static constexpr int kMaxPieces = 8;

    // Throws InputError for out-of-range options. `programs`: where the reduction's programs are compiled, on first
    // use (shared with other grids that compile the same ones).
    explicit RayBoundsGrid(const RayBoundsOptions& options = {},
                           std::shared_ptr<ProgramCache> programs = std::make_shared<ProgramCache>());

    // Reduces a width × height ray set (RayTextures' origin+tmin and direction+tmax textures) to cell boxes and
    // reads them back (waits for the GPU). `hitImage` (0: none) holds the hits found so far (RGBA32UI, the
    // hit-target layout); `anyHit` says whether rays with a hit are finished. Needs a current GL context (the first
    // call compiles the reduction shader). `cellMarks` (0: none): the hint pass's marks of the cells where a ray
    // may be left to trace and their list (CHCRT_CULLING_COMPACT_CELLS layout, hint_pass.h): only the listed cells
    // are reduced, the others are empty without looking at their rays; the marks buffer is then left bound as
    // GL_DISPATCH_INDIRECT_BUFFER (no state query on this path: a threaded GPU driver waits for its queue on one).
    void update(GLuint origins, GLuint directions, GLuint hitImage, bool anyHit, int width, int height,
                glm::vec3 sceneMin, glm::vec3 sceneMax, GLuint cellMarks = 0);
    // The reduction alone, into buffer() (CHCRT_CULLING_BOUNDS_* layout), for passes that read the grid on the GPU
    // (gpu_cell_lists.h): nothing is read back, the CPU side keeps its previous cells.
    void reduce(GLuint origins, GLuint directions, GLuint hitImage, bool anyHit, int width, int height,
                glm::vec3 sceneMin, glm::vec3 sceneMax, GLuint cellMarks = 0);
    GLuint buffer() const { return buffer_.id(); }
    // The cells of every shadow ray set that starts at the ray set's surface points and ends in the box (lightMin,
    // lightMax) (TraceRequest::lightSweep): boxes around the segments from each cell's origin box to the light's box,
    // over the cell's active rays and the inactive ones that kept their origin (shared/render_layout.h). Reads them
    // back like update(); reduceLightSweep reduces them into buffer() alone, like reduce().
    void updateLightSweep(GLuint origins, GLuint directions, int width, int height, glm::vec3 sceneMin,
                          glm::vec3 sceneMax, glm::vec3 lightMin, glm::vec3 lightMax);
    void reduceLightSweep(GLuint origins, GLuint directions, int width, int height, glm::vec3 sceneMin,
                          glm::vec3 sceneMax, glm::vec3 lightMin, glm::vec3 lightMax);
    // The cells of a camera's primary rays before any hit, bounded from the camera (camera_ray_bounds.h): boxes that
    // hold those update() would reduce from the rays, with nothing read from the GPU.
    void setCameraCells(const PrimaryRayBasis& basis, glm::vec3 sceneMin, glm::vec3 sceneMax);
    // Hemisphere rays (AO, TraceRequest::HemisphereRays; hemisphere_ray_bounds.h): reduceSurfaceFrames reduces the
    // surface frames every set of a G-buffer shares — the origins of a width × height ray set of it (its active rays
    // and the inactive ones that kept their origin) and the shading normals' texture — and reads them back (waits for
    // the GPU); setHemisphereCells then bounds the cells of one set from them on the CPU, before any hit, in this
    // grid or any other of the same cell size.
    SurfaceFrames reduceSurfaceFrames(GLuint origins, GLuint directions, GLuint shadingNormals, int width,
                                      int height);
    void setHemisphereCells(const SurfaceFrames& frames, const HemisphereSample& set, glm::vec3 sceneMin,
                            glm::vec3 sceneMax);

    // True when some ray of `tile`'s pixels may meet one of the `count` boxes (lower[i], upper[i]) before its hit;
    // false means no ray of the tile can hit anything inside them. Tiles are in pixels of the ray set, GL
    // orientation. Without cells (nothing known) always true.
    bool mayReach(const Tile& tile, const glm::vec3* lower, const glm::vec3* upper, int count) const;
    // The same for one cell (cx, cy).
    bool cellMayReach(int cx, int cy, const glm::vec3* lower, const glm::vec3* upper, int count) const;
    // The cells a tile covers: [x0, x1) × [y0, y1), clamped to the grid.
    std::array<int, 4> cellRange(const Tile& tile) const;
    // A lower bound of the distance t at which any ray of cell (cx, cy) can enter the box (lower, upper): the gap
    // between the box and the cell's ray origins over the longest direction, rounded down. 0 when nothing is known.
    float entryLowerBound(int cx, int cy, const glm::vec3& lower, const glm::vec3& upper) const;

    // Drops the cells: nothing is known, mayReach is true everywhere.
    void forget() { cells_.clear(); }
    bool known() const { return !cells_.empty(); }

    const RayBoundsOptions& options() const { return options_; }
    int cellsX() const { return cellsX_; }
    int cellsY() const { return cellsY_; }
    // Cells per state after the last update (for statistics): empty, bounded, unbounded.
    std::array<uint32_t, 3> cellStates() const;
    // The padded boxes of cell (cx, cy) and whether it is bounded (for the viewer's bounds view and tests).
    struct CellBoxes {
        uint8_t state = 0; // 0 empty, 1 bounded, 2 unbounded
        std::array<glm::vec3, kMaxPieces> lower{}, upper{}; // per piece
        glm::vec3 originLower{0.0f}, originUpper{0.0f};
        float directionLength = 0.0f; // the longest direction of the cell's rays
        // The ray interval: direction components and segment range of the cell's rays (the frustum shape).
        glm::vec3 directionLower{0.0f}, directionUpper{0.0f};
        float segmentStart = 0.0f, segmentEnd = 0.0f;
        float pad = 0.0f; // the rounding margin every box of the cell carries
    };
    // Which shape decided the tests of cells against boxes (statistics, "how many pairs each shape decides"); tiles
    // test their coarse cells first, then their cells, and every such test counts. The pieces are tested first.
    struct ShapeDecisions {
        uint64_t pieces = 0;  // culled: no piece met a box
        uint64_t frustum = 0; // culled: pieces met a box, the frustum met none of those
        uint64_t reached = 0; // not culled
    };
    // The counts of mayReach/cellMayReach calls so far (reset with resetDecisions).
    const ShapeDecisions& decisions() const { return decisions_; }
    void resetDecisions() { decisions_ = {}; }
    const CellBoxes& cell(int cx, int cy) const { return cells_[size_t(cy) * size_t(cellsX_) + size_t(cx)]; }

    // The CPU side alone, for tests: cells from a read-back buffer (CHCRT_CULLING_BOUNDS_* layout).
    void setCells(int width, int height, const std::vector<glm::vec4>& buffer);

private:
    // The reduction's program: `variant` 0 without hits, 1 with closest hits, 2 with any hits, 3 swept to a light.
    const ShaderProgram& reduction(int variant, bool cellMarks);
    // vec4s of the buffer for a width × height ray set.
    size_t valueCount(int width, int height) const;
    // Sizes and binds the buffer, and makes `program` current with the ray textures and uniforms every variant
    // reads; returns the buffer's bytes.
    size_t prepare(const ShaderProgram& program, GLuint origins, GLuint directions, int width, int height,
                   glm::vec3 sceneMin, glm::vec3 sceneMax);
    void readBack(int width, int height);
    bool overlaps(const CellBoxes& cell, const glm::vec3* lower, const glm::vec3* upper, int count) const;
    bool piecesOverlap(const CellBoxes& cell, const glm::vec3& lower, const glm::vec3& upper) const;
    bool frustumOverlaps(const CellBoxes& cell, const glm::vec3& lower, const glm::vec3& upper) const;
    void buildCoarse();

    RayBoundsOptions options_;
    std::shared_ptr<ProgramCache> programs_;
    // Of programs_: [without hits, with hits (closest hit), with hits (any hit), swept to a light][cell marks]
    const ShaderProgram* variants_[4][2] = {};
    const ShaderProgram* surfaceFrames_ = nullptr; // of programs_
    GlBuffer framesBuffer_;
    size_t framesBufferBytes_ = 0;
    GlBuffer buffer_;
    size_t bufferBytes_ = 0;
    int cellsX_ = 0, cellsY_ = 0;
    int coarseX_ = 0, coarseY_ = 0;
    std::vector<CellBoxes> cells_;  // row-major, cell row 0 = pixel rows 0..cellSize-1 (GL orientation)
    std::vector<CellBoxes> coarse_; // unions of coarseCells² cells
    std::vector<glm::vec4> readBack_;
    mutable ShapeDecisions decisions_;
};

} // namespace chcrt
