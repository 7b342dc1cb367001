#include "culling/hint_pass.h"

#include "shaders/shared/culling_layout.h"

#include <array>

namespace chcrt {

HintPass::HintPass(bool compute, int cellSize, std::vector<ShaderDefine> defines,
                   std::shared_ptr<ProgramCache> programs)
    : compute_(compute), defines_(std::move(defines)), programs_(std::move(programs)), cellSize_(cellSize) {
    program(true, false, true);
    program(true, false, false);
    program(false, false, false); // closest-hit rays keep their cells (hint_pass.glsl): no marks
}

const ShaderProgram& HintPass::program(bool anyHit, bool debugCost, bool markCells) {
    const ShaderProgram*& program = variants_[anyHit ? 1 : 0][debugCost ? 1 : 0][markCells ? 1 : 0];
    if (!program) {
        std::vector<ShaderDefine> defines = defines_;
        defines.push_back({"TRACE_ANY_HIT", anyHit ? "1" : "0"});
        defines.push_back({"CHCRT_CULLING_HINT_MARKS", markCells ? "1" : "0"});
        if (debugCost) defines.push_back({"CHCRT_CULLING_DEBUG_COST", "1"});
        program = compute_ ? &programs_->get({{GL_COMPUTE_SHADER, "culling/chcrt_hints.comp.glsl"}}, defines)
                           : &programs_->get({{GL_VERTEX_SHADER, "render/fullscreen.vert.glsl"},
                                              {GL_FRAGMENT_SHADER, "culling/chcrt_hints.frag.glsl"}},
                                             defines);
    }
    return *program;
}

void HintPass::run(bool anyHit, int width, int height, GLuint maskFramebuffer, bool debugCost, bool markCells,
                   const HintSlots& slots) {
    const size_t rays = size_t(width) * size_t(height);
    if (rays > capacity_) {
        buffer_ = createBuffer((CHCRT_CULLING_COMPACT_HEADER + rays) * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
        capacity_ = rays;
    }
    const int cellsX = (width + cellSize_ - 1) / cellSize_, cellsY = (height + cellSize_ - 1) / cellSize_;
    const size_t cells = size_t(cellsX) * size_t(cellsY);
    if (cells > markCapacity_) {
        marks_ = createBuffer(size_t(CHCRT_CULLING_MARKED_UINTS(cells)) * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
        markCapacity_ = cells;
    }
    // No rays listed yet: a dispatch of no work groups; no cell marked, none listed.
    const std::array<uint32_t, CHCRT_CULLING_COMPACT_HEADER> reset = {0u, 1u, 1u, 0u};
    glNamedBufferSubData(buffer_.id(), 0, sizeof(reset), reset.data());
    if (markCells) {
        const uint32_t zero = 0u;
        glClearNamedBufferSubData(marks_.id(), GL_R32UI, 0, GLsizeiptr(cells * 4), GL_RED_INTEGER, GL_UNSIGNED_INT,
                                  &zero);
        glNamedBufferSubData(marks_.id(), GLintptr(CHCRT_CULLING_MARKED_HEADER(cells) * 4), sizeof(reset),
                             reset.data());
    }
    const ShaderProgram& pass = program(anyHit, debugCost, markCells);
    pass.use();
    pass.set("cellsX", cellsX);
    pass.set("cellCount", int(cells));
    pass.set("cellSize", cellSize_);
    if (slots.slotNodes != 0) {
        pass.set("hintSlotNodes", slots.slotNodes);
        pass.set("hintEpoch", slots.epoch);
        pass.set("hintEpochSpan", slots.span);
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_COMPACT_BUFFER, buffer_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_COMPACT_CELLS, marks_.id());
    if (compute_) {
        pass.set("raySize", glm::ivec2(width, height));
        glDispatchCompute(GLuint((width + 7) / 8), GLuint((height + 7) / 8), 1);
    } else {
        // The full-screen triangle lies at depth 0 or 0.5 (either clip-control convention): it passes where the
        // mask holds 1 (an active ray), which it never writes.
        glBindFramebuffer(GL_FRAMEBUFFER, maskFramebuffer);
        glViewport(0, 0, width, height);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_FALSE);
        drawFullscreenTriangle();
    }
    // The reduction and the cell passes read the hits and hints as images, the compact pass the list and its
    // dispatch command.
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, buffer_.id());
}

uint32_t HintPass::raysLeft() const {
    uint32_t listed = 0;
    if (buffer_.id() != 0) glGetNamedBufferSubData(buffer_.id(), 3 * 4, 4, &listed);
    return listed;
}

} // namespace chcrt
