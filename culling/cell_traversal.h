#pragma once
// CHC+RT §5.2 batches as cell lists: the termination subtrees scheduled for intersection are grouped per screen
// cell (the ray bounds grid's cells, ray_bounds_grid.h), and one draw per round — a point of the cell's size per
// cell with work — traverses them, each pixel its cell's list with one stack (shaders/culling/chcrt_cells.*.glsl).
// The draw tests a mask early (the ray set's active-ray mask, or one written over the same cells first: active
// any-hit rays without a hit). Replaces a draw per tile and batch: llvmpipe sends every fragment group of a draw
// through the traversal code at least once, so many small draws cost as much as the work they trace, and a pass
// that wrote gl_FragDepth could not skip finished or inactive rays with an early depth test. (Measured on the city,
// 256², AO: two triangles per cell cost 1.5x more per traversal step, their diagonals split llvmpipe's 4×4 blocks;
// a full-screen draw behind a mask of the cells with work spent ~1.1 ms per round on the mask pass alone.)
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/program_cache.h"
#include "renderer/gl/shader.h"

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace chcrt {

class CellTraversal {
public:
    // The subtree id the debug image of subtrees records for the whole tree.
    static constexpr uint32_t kWholeTreeId = 0xfffffffeu;
    // `defines(anyHit)`: the defines of the subtree shader variant (stack size, a debug image's define).
    using Defines = std::function<std::vector<ShaderDefine>(bool anyHit)>;
    // `computeCellSize` > 0: the passes are compute dispatches with work groups of that edge (the grid's cell size),
    // one per cell with work (chcrt_cells.comp.glsl); 0: fragment passes drawing a point per cell. `programs`: where
    // its programs are compiled (shared with other traversals that compile the same ones).
    explicit CellTraversal(Defines defines, int computeCellSize = 0,
                           std::shared_ptr<ProgramCache> programs = std::make_shared<ProgramCache>())
        : defines_(std::move(defines)), computeCellSize_(computeCellSize), programs_(std::move(programs)) {}
    bool compute() const { return computeCellSize_ > 0; }

    // Starts new lists for a grid of cellsX × cellsY cells of cellSize² pixels.
    void begin(int cellsX, int cellsY, int cellSize);
    // Appends a subtree (its GPU root and culling-hierarchy index) to cell `cell`'s list, with a lower bound of the
    // distance at which the cell's rays can enter it (0 when unknown); each list is sorted by it for the draw.
    void add(uint32_t cell, uint32_t gpuRoot, uint32_t subtree, float entryBound) {
        entries_.push_back(Entry{cell, gpuRoot, subtree, entryBound});
    }
    size_t entryCount() const { return entries_.size(); }
    // A cell whose list would hold more than `limit` subtrees traverses the whole tree from `root` instead (0 = no
    // limit): its rays would pay a box test per listed root that the pure traversal's near-first order and pruning
    // mostly avoid. Exact: the whole tree holds every subtree. Needs a traversal stack as deep as the whole tree.
    void setWholeTree(uint32_t root, uint32_t limit) {
        wholeTreeRoot_ = root;
        listLimit_ = limit;
    }
    uint32_t wholeTreeCells() const { return wholeTreeCells_; } // cells that did so in the last draw
    // Wall time of the sorting and upload of the lists since begin() (ms; 0 when a draw had none to upload). Not
    // the pass it issued: llvmpipe runs a compute dispatch (the compacted one, compute cell passes) before the call
    // returns.
    double listUploadMs() const { return listUploadMs_; }
    // Whether the hint pass visited every ray's hint in this trace: the passes then run a variant without the visit
    // (shaders/culling/cell_pixel.glsl, CHCRT_CULLING_HINTS_VISITED). The compacted dispatch always follows the pass.
    void setHintsVisited(bool visited) { hintsVisited_ = visited; }
    // Compiles the programs of both ray kinds and the mask program now (they are otherwise compiled on first use);
    // `compacted`: also drawCompacted's program for any-hit rays.
    void compile(bool compacted);

    // Uploads the lists and traverses them into `maskFramebuffer` (a depth-only target of the ray set's size whose
    // depth is 1 where a ray is to be traced), with the ray textures, hit image and BVH buffers bound. `writeMask`:
    // first write that depth over the cells with work (active rays without a hit; for rounds of any-hit rays after
    // the first). `debugDefine` names a debug image variant ("" = none). `writesAll`: the trace's first pass over a hit
    // image that was not cleared, with every ray of the set active (ChcrtTracer::beginTrace): every cell is drawn,
    // also one with an empty list, and each ray stores its result, a miss too (no debug image). Returns the number of
    // cells with work.
    uint32_t draw(bool anyHit, const std::string& debugDefine, int width, int height, GLuint maskFramebuffer,
                  bool writeMask, bool writesAll = false);
    // The same as a compute dispatch over the rays the hint pass left (hint_pass.h; its compaction buffer bound as
    // the shader storage and dispatch-indirect buffer): each traverses the list of its cell. Returns the cells with
    // work.
    uint32_t drawCompacted(bool anyHit, const std::string& debugDefine);
    // The same over lists decided on the GPU (gpu_cell_lists.h, bound already), the compaction buffer bound as the
    // dispatch-indirect buffer.
    void dispatchCompacted(bool anyHit, const std::string& debugDefine, int cellsX, int cellSize);
    // Lists for several ray sets (the shadow ray sets of a frame, TraceRequest::lightSweep): keep() sorts and uploads
    // the lists added since begin() and returns the cells with work; drawKept / drawKeptCompacted traverse them (as
    // draw / drawCompacted without a mask to write) as often as asked, until the next keep, draw or drawCompacted.
    // No debug image (the subtree ids are not kept).
    uint32_t keep();
    uint32_t drawKept(bool anyHit, int width, int height, GLuint maskFramebuffer);
    uint32_t drawKeptCompacted(bool anyHit);
    // The same for lists decided on the GPU (gpu_cell_lists.h): the list texture units and the indirect draw of the
    // cells with work are bound already; cellsX / cellSize describe the grid.
    void drawIndirect(bool anyHit, const std::string& debugDefine, int width, int height, int cellsX, int cellSize,
                      GLuint maskFramebuffer, bool writeMask);

private:
    struct Entry {
        uint32_t cell, root, subtree;
        float entryBound;
    };
    struct Buffers {
        TextureBuffer headers, roots, ids, drawCells;
    };
    // The cell pass variant: `compacted` = chcrt_cells_compact.comp.glsl, else the fragment or compute pass per cell.
    const ShaderProgram& program(bool anyHit, const std::string& debugDefine, bool compacted, bool writesAll = false);
    // Sorts the entries into per-cell lists, uploads and binds them (texture units CHCRT_UNIT_CULLING_CELL_*);
    // `everyCell`: every cell is drawn, not only those with work. Returns the cells with work.
    uint32_t uploadLists(const std::string& debugDefine, bool everyCell = false);
    void bindLists(const Buffers& buffers, bool withIds) const;
    void drawPoints(const ShaderProgram& program, int width, int height) const;
    // The mask (when asked for) and the traversal of the cells `issue` draws, into `maskFramebuffer`; compute passes
    // need no mask (finished and inactive rays return at once) and no framebuffer.
    void drawMaskAndCells(bool anyHit, const std::string& debugDefine, int width, int height, GLuint maskFramebuffer,
                          bool writeMask, const std::function<void(const ShaderProgram&)>& issue,
                          bool writesAll = false);
    static void upload(TextureBuffer& target, const void* data, size_t bytes, GLenum format);
    const ShaderProgram& maskProgram();

    Defines defines_;
    int computeCellSize_ = 0;
    // debug define, any-hit, compacted, hints visited, writes all
    using ProgramKey = std::tuple<std::string, bool, bool, bool, bool>;
    std::shared_ptr<ProgramCache> programs_;
    std::map<ProgramKey, const ShaderProgram*> variants_; // of programs_, found once
    const ShaderProgram* maskProgram_ = nullptr;
    int cellsX_ = 0, cellsY_ = 0, cellSize_ = 0;
    std::vector<Entry> entries_, sorted_;
    std::vector<uint32_t> counts_, headers_, roots_, ids_, drawCells_; // drawCells_: the cells drawn
    Buffers buffers_[2]; // alternate per draw, so an upload never waits for the previous draw
    int next_ = 0;
    int kept_ = -1;              // the buffers keep() filled, -1 = none (or replaced since)
    uint32_t keptWithWork_ = 0;  // their cells with work
    uint32_t wholeTreeRoot_ = 0, listLimit_ = 0, wholeTreeCells_ = 0;
    double listUploadMs_ = 0.0;
    bool hintsVisited_ = false;
};

} // namespace chcrt
