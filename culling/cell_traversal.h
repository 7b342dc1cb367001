#pragma once
// CHC+RT §5.2 batches as cell lists: the termination subtrees scheduled for intersection are grouped per screen
// cell (the ray bounds grid's cells, ray_bounds_grid.h), nearest first, and one draw covers every cell that has
// work, each pixel traversing its cell's list with one stack (shaders/culling/chcrt_cells.frag.glsl). Replaces a
// draw per tile and batch: llvmpipe sends every fragment group of a draw through the traversal code at least once,
// so many small draws cost as much as the work they trace, and a pass that wrote gl_FragDepth could not skip
// finished or inactive rays with an early depth test. The pass writes no depth: rays are kept out by the mask
// bound as depth by the caller.
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/shader.h"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace chcrt {

class CellTraversal {
public:
    // `defines(anyHit)`: the defines of the subtree shader variant (stack size, a debug image's define).
    using Defines = std::function<std::vector<ShaderDefine>(bool anyHit)>;
    explicit CellTraversal(Defines defines) : defines_(std::move(defines)) {}

    // Starts new lists for a grid of cellsX × cellsY cells of cellSize² pixels.
    void begin(int cellsX, int cellsY, int cellSize);
    // Appends a subtree (its GPU root and culling-hierarchy index) to cell `cell`'s list, with a lower bound of the
    // distance at which the cell's rays can enter it (0 when unknown); each list is sorted by it for the draw.
    void add(uint32_t cell, uint32_t gpuRoot, uint32_t subtree, float entryBound) {
        entries_.push_back(Entry{cell, gpuRoot, subtree, entryBound});
    }
    size_t entryCount() const { return entries_.size(); }

    // Uploads the lists and draws the cells that have entries into the bound framebuffer (whose depth is the mask
    // the caller set up), with the ray textures, hit image and BVH buffers bound. `debugDefine` names a debug image
    // variant ("" = none). Returns the number of cells drawn.
    uint32_t draw(bool anyHit, const std::string& debugDefine, int width, int height);

private:
    struct Entry {
        uint32_t cell, root, subtree;
        float entryBound;
    };
    struct Buffers {
        TextureBuffer headers, roots, ids, drawCells;
    };
    const ShaderProgram& program(bool anyHit, const std::string& debugDefine);
    static void upload(TextureBuffer& target, const void* data, size_t bytes, GLenum format);

    Defines defines_;
    std::map<std::pair<std::string, bool>, ShaderProgram> programs_;
    int cellsX_ = 0, cellsY_ = 0, cellSize_ = 0;
    std::vector<Entry> entries_, sorted_;
    std::vector<uint32_t> counts_, headers_, roots_, ids_, drawCells_;
    Buffers buffers_[2]; // alternate per draw, so an upload never waits for the previous draw
    int next_ = 0;
};

} // namespace chcrt
