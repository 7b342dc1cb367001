#pragma once
// CHC+RT cell lists decided on the GPU (`--chcrt-queries bounds-gpu`): the bounds-only mode's decisions without the
// read-back. After the ray bounds reduction (ray_bounds_grid.h), one compute invocation per screen cell traverses the
// upper hierarchy with the cell's boxes and writes the cell's list of termination subtrees in the layout the cell
// pass reads (shaders/culling/cell_lists.comp.glsl, layouts in shaders/shared/culling_layout.h), together with an
// indirect draw of the cells with work. Nothing waits for the GPU between the reduction and the cell pass: on a GPU a
// blocking read-back and CPU decisions per trace cost more than the trace itself, and on llvmpipe they are a serial
// share of every trace (culling/README.md, "Deciding pairs"). In core only: the lists name BVH nodes of the scene,
// and a cell over its list limit traverses the whole tree. Counters of the last build are read after the trace.
#include "culling/culling_hierarchy.h"
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/program_cache.h"

#include <cstdint>
#include <memory>

namespace chcrt {

class GpuCellLists {
public:
    // Uploads the upper hierarchy (`hierarchy.subtrees[s].bvhNode` as each root's GPU node). `pieces`: the ray bounds
    // grid's. The program depends on `pieces` only, not on the hierarchy, so it comes from `programs` (shared with the
    // other termination heights' lists, whose tracers are made with the configuring one: a GPU driver compiles at link
    // time, once instead of once per height). Needs a current GL context.
    GpuCellLists(const CullingHierarchy& hierarchy, int pieces,
                 std::shared_ptr<ProgramCache> programs = std::make_shared<ProgramCache>());

    // Decides the lists of a cellsX × cellsY grid from the reduction in `boundsBuffer`: a cell with more than
    // `listLimit` subtrees (at most CHCRT_CULLING_GPU_LIST_MAX; 0 = that maximum) traverses the whole tree.
    // `relativePad`, `frustum`: RayBoundsOptions'. Leaves the lists bound for the cell pass (texture units
    // CHCRT_UNIT_CULLING_CELL_*) and the draw buffer bound to GL_DRAW_INDIRECT_BUFFER and GL_DISPATCH_INDIRECT_BUFFER
    // (the dispatch command at CHCRT_CULLING_GPU_DISPATCH_OFFSET).
    void build(GLuint boundsBuffer, int cellsX, int cellsY, uint32_t listLimit, float relativePad, bool frustum);
    // Binds the lists of the last build again as build leaves them (for another ray set that shares them).
    void bind() const;

    struct Counters {
        uint32_t cellsDrawn = 0, entries = 0, wholeTreeCells = 0, nodesTested = 0;
        // Box tests by what decided them (RayBoundsGrid::ShapeDecisions): culled by the pieces, culled by the
        // cell's ray interval, reached.
        uint32_t culledPieces = 0, culledFrustum = 0, reached = 0;
    };
    // The counters of the last build (reads them back: call once its trace has finished).
    Counters counters() const;

private:
    void ensureCapacity(size_t cells);

    std::shared_ptr<ProgramCache> programs_;
    const ShaderProgram* program_; // of programs_
    TextureBuffer hierarchy_;
    TextureBuffer headers_, roots_, ids_, drawCells_; // texture views for the cell pass over the compute's buffers
    GlBuffer draw_;                                   // indirect command, counters, cells drawn
    size_t capacity_ = 0;                             // cells the buffers hold
};

} // namespace chcrt
