#include "culling/gpu_cell_lists.h"

#include "culling/cell_traversal.h"
#include "shaders/shared/bvh_layout.h"
#include "shaders/shared/culling_layout.h"

#include <algorithm>
#include <array>
#include <bit>
#include <vector>

namespace chcrt {
namespace {

// The upper hierarchy's texels (layout: shaders/shared/culling_layout.h).
std::vector<glm::vec4> hierarchyTexels(const CullingHierarchy& h) {
    std::vector<glm::vec4> texels;
    texels.reserve(h.nodes.size() * CHCRT_CULLING_HIERARCHY_TEXELS);
    const auto bits = [](uint32_t value) { return std::bit_cast<float>(value); };
    for (const CullingHierarchy::Node& n : h.nodes) {
        const bool terminal = n.isTerminal();
        const uint32_t gpuRoot = terminal ? h.subtrees[n.subtree].bvhNode : 0u;
        texels.emplace_back(n.boxMin, bits(terminal ? CHCRT_NO_HIT_ID : n.firstChild));
        texels.emplace_back(n.boxMax, bits(gpuRoot));
        texels.emplace_back(n.tightMin[0], bits(n.tightCount));
        texels.emplace_back(n.tightMax[0], bits(terminal ? n.subtree : 0u));
        texels.emplace_back(n.tightMin[1], 0.0f);
        texels.emplace_back(n.tightMax[1], 0.0f);
    }
    return texels;
}

// A texture view of `bytes` of `buffer` from `offset`, with the buffer's lifetime owned elsewhere.
GlTexture textureView(GLuint buffer, GLenum format, size_t offset, size_t bytes) {
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &id);
    glTextureBufferRange(id, format, buffer, GLintptr(offset), GLsizeiptr(bytes));
    return GlTexture(id);
}

} // namespace

GpuCellLists::GpuCellLists(const CullingHierarchy& hierarchy, int pieces, std::shared_ptr<ProgramCache> programs)
    : programs_(std::move(programs)),
      program_(&programs_->get({{GL_COMPUTE_SHADER, "culling/cell_lists.comp.glsl"}},
                               {{"CHCRT_BOUNDS_PIECES", std::to_string(pieces)}})) {
    const std::vector<glm::vec4> texels = hierarchyTexels(hierarchy);
    hierarchy_ = createTextureBuffer(texels.data(), texels.size() * sizeof(glm::vec4), GL_RGBA32F);
}

void GpuCellLists::ensureCapacity(size_t cells) {
    if (cells <= capacity_) return;
    const size_t entries = 1 + cells * CHCRT_CULLING_GPU_LIST_MAX;
    headers_ = createTextureBuffer(nullptr, cells * 8, GL_RG32UI);
    // Entry 0 is the whole tree (the BVH root from its start, id CellTraversal::kWholeTreeId), written once.
    std::vector<uint32_t> roots(entries * 2, 0u), ids(entries, 0u);
    ids[0] = CellTraversal::kWholeTreeId;
    roots_ = createTextureBuffer(roots.data(), roots.size() * 4, GL_RG32UI);
    ids_ = createTextureBuffer(ids.data(), ids.size() * 4, GL_R32UI);
    const size_t drawBytes = (CHCRT_CULLING_GPU_DRAW_HEADER + cells) * 4;
    draw_ = createBuffer(drawBytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
    drawCells_.buffer = GlBuffer(); // the view below reads draw_
    drawCells_.texture = textureView(draw_.id(), GL_R32UI, CHCRT_CULLING_GPU_DRAW_HEADER * 4, cells * 4);
    drawCells_.bytes = cells * 4;
    capacity_ = cells;
}

void GpuCellLists::build(GLuint boundsBuffer, int cellsX, int cellsY, uint32_t listLimit, float relativePad,
                         bool frustum) {
    const size_t cells = size_t(cellsX) * size_t(cellsY);
    ensureCapacity(cells);
    // Fresh indirect commands (no cells yet: a draw of one instance, a dispatch of one row) and zero counters.
    const std::array<uint32_t, 14> reset = {0u, 1u, 0u, 0u, 0u, 1u, 1u, 0u, 0u, 0u, 0u, 0u, 0u, 0u};
    glNamedBufferSubData(draw_.id(), 0, sizeof(reset), reset.data());
    const uint32_t limit = listLimit == 0 ? CHCRT_CULLING_GPU_LIST_MAX : std::min<uint32_t>(listLimit, CHCRT_CULLING_GPU_LIST_MAX);
    program_->use();
    program_->set("cellCount", uint32_t(cells));
    program_->set("listLimit", limit);
    program_->set("relativePad", relativePad);
    program_->set("frustum", int(frustum));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_BOUNDS_BUFFER, boundsBuffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_GPU_HEADERS_BUFFER, headers_.buffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_GPU_ROOTS_BUFFER, roots_.buffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_GPU_IDS_BUFFER, ids_.buffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_GPU_DRAW_BUFFER, draw_.id());
    glBindTextureUnit(CHCRT_UNIT_CULLING_HIERARCHY, hierarchy_.texture.id());
    glDispatchCompute(GLuint((cells + 63) / 64), 1, 1);
    // The cell pass reads the lists through texture buffers and its cell count from the indirect command.
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    bind();
}

void GpuCellLists::bind() const {
    glBindTextureUnit(CHCRT_UNIT_CULLING_CELL_HEADERS, headers_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_CULLING_CELL_ROOTS, roots_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_CULLING_CELL_IDS, ids_.texture.id());
    glBindTextureUnit(CHCRT_UNIT_CULLING_DRAW_CELLS, drawCells_.texture.id());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, draw_.id());
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, draw_.id());
}

GpuCellLists::Counters GpuCellLists::counters() const {
    std::array<uint32_t, 14> head{};
    if (draw_.id() != 0) glGetNamedBufferSubData(draw_.id(), 0, sizeof(head), head.data());
    return Counters{head[0], head[8], head[9], head[10], head[11], head[12], head[13]};
}

} // namespace chcrt
