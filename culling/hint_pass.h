#pragma once
// CHC+RT hint pass (ours; culling/README.md "Hit hints", "The hint pass"): for an any-hit ray set with hit hints,
// one compute pass visits every active ray's hinted leaf before the ray bounds reduction, and lists the rays that
// it did not finish in a compaction buffer. Rays finished there drop out of the reduction (their cells' bounds
// shrink or empty), and the cell lists are then traversed by one dispatch over the listed rays only
// (CellTraversal::drawCompacted): when most rays of a cell hit their hints, a pass over all of them made each SIMD
// group wait in every loop of the list traversal for its slowest ray. Same hits: the hint visit is the one the cell
// pass made (shaders/culling/hint_leaf.glsl), and the rays left are traversed as before.
#include "renderer/gl/gl_objects.h"
#include "renderer/gl/program_cache.h"
#include "renderer/gl/shader.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace chcrt {

// Out of core: what a hint pass checks each hint's GPU cache slot against (shaders/culling/hint_leaf.glsl).
struct HintSlots {
    uint32_t slotNodes = 0; // node records per GPU cache slot (SubtreeSource::hintSlotNodes); 0 in core
    uint32_t epoch = 0;     // low 32 bits of the cache's contentEpoch when the hints were last validated
    uint32_t span = 0;      // the epoch now minus that
};

class HintPass {
public:
    // `compute`: the pass is a compute dispatch (GPUs); else a full-screen fragment pass behind the active-ray mask.
    // `cellSize`: the ray bounds grid's cell edge (its marks are per cell). `defines`: the subtree buffers' layout
    // (CHCRT_COMPACT_SUBTREES out of core). Compiles the pass's programs now, so that no trace pays for them, in
    // `programs` (shared with other passes that compile the same ones).
    HintPass(bool compute, int cellSize, std::vector<ShaderDefine> defines = {},
             std::shared_ptr<ProgramCache> programs = std::make_shared<ProgramCache>());

    // Visits the hinted leaves of a width × height ray set: the ray textures, the hit image (cleared) and the hint
    // image must be bound as the cell passes bind them (culling_layout.h). `maskFramebuffer`: a depth-only target
    // whose depth is 1 where a ray is active (the fragment pass tests it early). `debugCost`: add the visits' steps
    // to the cost debug image (bound at CHCRT_CULLING_IMAGE_DEBUG). Leaves the compaction buffer bound as the shader
    // storage buffer CHCRT_CULLING_COMPACT_BUFFER and as GL_DISPATCH_INDIRECT_BUFFER, ordered before later reads.
    // `anyHit`: the ray set's kind (shaders/culling/hint_pass.glsl: any-hit rays that hit are finished, closest-hit
    // rays bounded). `markCells`: mark and list the cells of the rays left (cellMarks()), for a reduction over those
    // cells; without, the pass leaves out those atomics. `slots`: out of core, what the hints are checked against.
    void run(bool anyHit, int width, int height, GLuint maskFramebuffer, bool debugCost, bool markCells,
             const HintSlots& slots = {});
    // The marks of the last run that marked cells (a uint per ray bounds cell of `cellSize` pixels: nonzero where a ray was listed),
    // for the reduction that follows it (RayBoundsGrid::update's `cellMarks`).
    GLuint cellMarks() const { return marks_.id(); }
    // Binds the compaction buffer as GL_DISPATCH_INDIRECT_BUFFER again (after a pass that bound another).
    void bindDispatch() const { glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buffer_.id()); }
    // Rays the last run left for the cell lists (reads back: call once the trace has finished).
    uint32_t raysLeft() const;

private:
    const ShaderProgram& program(bool anyHit, bool debugCost, bool markCells);

    bool compute_ = false;
    std::vector<ShaderDefine> defines_;
    std::shared_ptr<ProgramCache> programs_;
    // [anyHit][debugCost][markCells] of programs_; the debug ones made on first use
    const ShaderProgram* variants_[2][2][2] = {};
    int cellSize_ = 8;
    GlBuffer buffer_, marks_;
    size_t capacity_ = 0, markCapacity_ = 0; // rays the buffer can list, cells the marks hold
};

} // namespace chcrt
