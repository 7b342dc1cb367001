#include "culling/cell_traversal.h"

#include "renderer/core/timing.h"
#include "shaders/shared/culling_layout.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <bit>

namespace chcrt {

void CellTraversal::begin(int cellsX, int cellsY, int cellSize) {
    cellsX_ = cellsX;
    cellsY_ = cellsY;
    cellSize_ = cellSize;
    entries_.clear();
    listUploadMs_ = 0.0; // a draw of no lists uploads none
    kept_ = -1; // the kept lists were for another grid, or are to be replaced
}

const ShaderProgram& CellTraversal::program(bool anyHit, const std::string& debugDefine, bool compacted,
                                            bool writesAll) {
    const bool visited = compacted || hintsVisited_;
    const ProgramKey key{debugDefine, anyHit, compacted, visited, writesAll};
    auto it = variants_.find(key);
    if (it != variants_.end()) return *it->second;
    std::vector<ShaderDefine> defines = defines_(anyHit);
    defines.push_back({"TRACE_ANY_HIT", anyHit ? "1" : "0"});
    if (visited) defines.push_back({"CHCRT_CULLING_HINTS_VISITED", "1"});
    if (!debugDefine.empty()) defines.push_back({debugDefine, "1"});
    if (writesAll) defines.push_back({"CHCRT_CELL_PASS_WRITES_ALL", "1"});
    // The subtree-id image comes with the hit triangle's buffer index, as from the subtree passes (the out-of-core
    // primary resolve reads both: culling/outofcore/primary_resolve.h).
    if (debugDefine == "CHCRT_CULLING_DEBUG_SUBTREES") defines.push_back({"CHCRT_HIT_TRIANGLE_INDEX", "1"});
    if (compute() && !compacted) defines.push_back({"CHCRT_CELL_SIZE", std::to_string(computeCellSize_)});
    const ShaderProgram& program =
        compacted   ? programs_->get({{GL_COMPUTE_SHADER, "culling/chcrt_cells_compact.comp.glsl"}}, defines)
        : compute() ? programs_->get({{GL_COMPUTE_SHADER, "culling/chcrt_cells.comp.glsl"}}, defines)
                    : programs_->get({{GL_VERTEX_SHADER, "culling/chcrt_cells.vert.glsl"},
                                      {GL_FRAGMENT_SHADER, "culling/chcrt_cells.frag.glsl"}},
                                     defines);
    variants_.emplace(key, &program);
    return program;
}

void CellTraversal::compile(bool compacted) {
    program(false, "", false);
    program(true, "", false);
    if (compacted) program(true, "", true);
    if (!compute()) maskProgram();
}

const ShaderProgram& CellTraversal::maskProgram() {
    if (!maskProgram_) {
        maskProgram_ = &programs_->get({{GL_VERTEX_SHADER, "culling/chcrt_cells.vert.glsl"},
                                        {GL_FRAGMENT_SHADER, "culling/chcrt_cells_mask.frag.glsl"}});
    }
    return *maskProgram_;
}

void CellTraversal::upload(TextureBuffer& target, const void* data, size_t bytes, GLenum format) {
    if (bytes > target.bytes || target.texture.id() == 0) {
        // Grow by half again, so that a slowly growing list does not reallocate every frame.
        target = createTextureBuffer(nullptr, std::max<size_t>(bytes + bytes / 2, 256), format);
    }
    if (bytes > 0) glNamedBufferSubData(target.buffer.id(), 0, GLsizeiptr(bytes), data);
}

void CellTraversal::drawPoints(const ShaderProgram& program, int width, int height) const {
    program.use();
    program.set("raySize", glm::ivec2(width, height));
    program.set("cellsX", cellsX_);
    program.set("cellSize", cellSize_);
    if (compute()) glDispatchCompute(GLuint(drawCells_.size()), 1, 1);
    else drawAttributeless(GL_POINTS, GLsizei(drawCells_.size()));
}

uint32_t CellTraversal::draw(bool anyHit, const std::string& debugDefine, int width, int height,
                             GLuint maskFramebuffer, bool writeMask, bool writesAll) {
    if (entries_.empty() && !writesAll) return 0;
    const uint32_t withWork = uploadLists(debugDefine, writesAll);
    drawMaskAndCells(anyHit, debugDefine, width, height, maskFramebuffer, writeMask,
                     [&](const ShaderProgram& p) { drawPoints(p, width, height); }, writesAll);
    return withWork;
}

uint32_t CellTraversal::keep() {
    const bool any = !entries_.empty();
    keptWithWork_ = any ? uploadLists("") : 0;
    kept_ = any ? next_ ^ 1 : -1; // uploadLists filled buffers_[next_] and moved on
    return keptWithWork_;
}

uint32_t CellTraversal::drawKept(bool anyHit, int width, int height, GLuint maskFramebuffer) {
    if (kept_ < 0) return 0;
    bindLists(buffers_[kept_], false);
    drawMaskAndCells(anyHit, "", width, height, maskFramebuffer, false,
                     [&](const ShaderProgram& p) { drawPoints(p, width, height); });
    return keptWithWork_;
}

uint32_t CellTraversal::drawKeptCompacted(bool anyHit) {
    if (kept_ < 0) return 0; // no cell has work: every listed ray keeps its miss
    bindLists(buffers_[kept_], false);
    dispatchCompacted(anyHit, "", cellsX_, cellSize_);
    return keptWithWork_;
}

uint32_t CellTraversal::drawCompacted(bool anyHit, const std::string& debugDefine) {
    if (entries_.empty()) return 0; // no cell has work: every listed ray keeps its miss
    const uint32_t withWork = uploadLists(debugDefine);
    dispatchCompacted(anyHit, debugDefine, cellsX_, cellSize_);
    return withWork;
}

void CellTraversal::dispatchCompacted(bool anyHit, const std::string& debugDefine, int cellsX, int cellSize) {
    const ShaderProgram& p = program(anyHit, debugDefine, true);
    p.use();
    p.set("cellsX", cellsX);
    p.set("cellSize", cellSize);
    glDispatchComputeIndirect(0);
}

uint32_t CellTraversal::uploadLists(const std::string& debugDefine, bool everyCell) {
    const auto start = std::chrono::steady_clock::now();
    // Counting sort by cell (stable: a cell's entries keep the order of add() among equal bounds).
    const size_t cells = size_t(cellsX_) * size_t(cellsY_);
    counts_.assign(cells + 1, 0u);
    for (const Entry& e : entries_) ++counts_[e.cell + 1];
    for (size_t c = 1; c <= cells; ++c) counts_[c] += counts_[c - 1];
    // Entry 0 of the uploaded lists is the whole tree (for cells over the limit); a cell's list starts at
    // 1 + its first sorted entry.
    headers_.assign(cells * 2, 0u);
    drawCells_.clear();
    wholeTreeCells_ = 0;
    uint32_t withWork = 0;
    for (size_t c = 0; c < cells; ++c) {
        const uint32_t count = counts_[c + 1] - counts_[c];
        const bool whole = listLimit_ > 0 && count > listLimit_;
        headers_[2 * c] = whole ? 0u : 1u + counts_[c];
        headers_[2 * c + 1] = whole ? 1u : count;
        wholeTreeCells_ += whole;
        withWork += count != 0;
        if (count != 0 || everyCell) drawCells_.push_back(uint32_t(c));
    }
    sorted_.resize(entries_.size());
    for (const Entry& e : entries_) sorted_[counts_[e.cell]++] = e;
    // Each cell's list by its entry bound (the traversal ends a list once the bound passes the ray's hit); the
    // lists are short, so sorting them one by one is cheaper than sorting all entries.
    for (uint32_t c : drawCells_) {
        if (headers_[2 * size_t(c)] == 0) continue; // the whole tree
        const auto begin = sorted_.begin() + (headers_[2 * size_t(c)] - 1);
        std::stable_sort(begin, begin + headers_[2 * size_t(c) + 1],
                         [](const Entry& a, const Entry& b) { return a.entryBound < b.entryBound; });
    }
    roots_.resize((entries_.size() + 1) * 2);
    ids_.resize(entries_.size() + 1);
    roots_[0] = wholeTreeRoot_;
    roots_[1] = std::bit_cast<uint32_t>(0.0f);
    ids_[0] = kWholeTreeId;
    for (size_t i = 0; i < sorted_.size(); ++i) {
        roots_[2 * (i + 1)] = sorted_[i].root;
        roots_[2 * (i + 1) + 1] = std::bit_cast<uint32_t>(sorted_[i].entryBound);
        ids_[i + 1] = sorted_[i].subtree;
    }
    Buffers& b = buffers_[next_];
    if (kept_ == next_) kept_ = -1; // replaced
    next_ ^= 1;
    upload(b.headers, headers_.data(), headers_.size() * 4, GL_RG32UI);
    upload(b.roots, roots_.data(), roots_.size() * 4, GL_RG32UI);
    const bool withIds = debugDefine == "CHCRT_CULLING_DEBUG_SUBTREES";
    if (withIds) upload(b.ids, ids_.data(), ids_.size() * 4, GL_R32UI);
    upload(b.drawCells, drawCells_.data(), drawCells_.size() * 4, GL_R32UI);
    bindLists(b, withIds);
    entries_.clear();
    listUploadMs_ = millisecondsSince(start);
    return withWork;
}

void CellTraversal::bindLists(const Buffers& b, bool withIds) const {
    glBindTextureUnit(CHCRT_UNIT_CULLING_CELL_HEADERS, b.headers.texture.id());
    glBindTextureUnit(CHCRT_UNIT_CULLING_CELL_ROOTS, b.roots.texture.id());
    glBindTextureUnit(CHCRT_UNIT_CULLING_DRAW_CELLS, b.drawCells.texture.id());
    if (withIds) glBindTextureUnit(CHCRT_UNIT_CULLING_CELL_IDS, b.ids.texture.id());
}

void CellTraversal::drawIndirect(bool anyHit, const std::string& debugDefine, int width, int height, int cellsX,
                                 int cellSize, GLuint maskFramebuffer, bool writeMask) {
    drawMaskAndCells(anyHit, debugDefine, width, height, maskFramebuffer, writeMask, [&](const ShaderProgram& p) {
        p.use();
        p.set("raySize", glm::ivec2(width, height));
        p.set("cellsX", cellsX);
        p.set("cellSize", cellSize);
            if (compute()) glDispatchComputeIndirect(CHCRT_CULLING_GPU_DISPATCH_OFFSET);
        else drawAttributelessIndirect(GL_POINTS);
    });
}

void CellTraversal::drawMaskAndCells(bool anyHit, const std::string& debugDefine, int width, int height,
                                     GLuint maskFramebuffer, bool writeMask,
                                     const std::function<void(const ShaderProgram&)>& issue, bool writesAll) {
    if (compute()) {
        issue(program(anyHit, debugDefine, false, writesAll));
        return;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, maskFramebuffer);
    glViewport(0, 0, width, height);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glEnable(GL_DEPTH_TEST);
    if (writeMask) {
        const ShaderProgram& mask = maskProgram();
        const GLfloat skip = 0.0f;
        glClearNamedFramebufferfv(maskFramebuffer, GL_DEPTH, 0, &skip);
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
        issue(mask);
    }
    glDepthFunc(GL_LESS); // passes where the mask holds 1
    glDepthMask(GL_FALSE);
    issue(program(anyHit, debugDefine, false, writesAll));
    glDisable(GL_PROGRAM_POINT_SIZE);
}

} // namespace chcrt
