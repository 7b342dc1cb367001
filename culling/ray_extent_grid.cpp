#include "culling/ray_extent_grid.h"

#include "shaders/shared/culling_layout.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <cmath>

namespace chcrt {
namespace {

constexpr int kCell = CHCRT_CULLING_RAY_CELL;

// Float rounding of the segment end points (o + t·d in the shader) and of the hit points a traversal accepts is a
// few ulps of the coordinates' magnitude; 2^-12 relative (plus 2^-12 absolute near the origin) covers it with a
// wide margin and costs nothing measurable in culling (0.7 m at 3 km).
constexpr float kRelativePad = 1.0f / 4096.0f;

} // namespace

void RayExtentGrid::update(GLuint origins, GLuint directions, int width, int height) {
    if (!program_.valid()) program_ = ShaderProgram({{GL_COMPUTE_SHADER, "culling/ray_cell_bounds.comp.glsl"}});
    const int cellsX = (width + kCell - 1) / kCell, cellsY = (height + kCell - 1) / kCell;
    if (cellsX != cellsX_ || cellsY != cellsY_ || lower_.id() == 0) {
        lower_ = createTexture2D(cellsX, cellsY, GL_RGBA32F);
        upper_ = createTexture2D(cellsX, cellsY, GL_RGBA32F);
    }
    program_.use();
    program_.set("raySize", glm::ivec2(width, height));
    program_.set("cellCount", glm::ivec2(cellsX, cellsY));
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, origins);
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, directions);
    glBindImageTexture(CHCRT_CULLING_IMAGE_CELL_LOWER, lower_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(CHCRT_CULLING_IMAGE_CELL_UPPER, upper_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute(GLuint((cellsX + 7) / 8), GLuint((cellsY + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    const size_t cells = size_t(cellsX) * size_t(cellsY);
    readLower_.resize(cells);
    readUpper_.resize(cells);
    const GLsizei bytes = GLsizei(cells * sizeof(glm::vec4));
    glGetTextureImage(lower_.id(), 0, GL_RGBA, GL_FLOAT, bytes, readLower_.data());
    glGetTextureImage(upper_.id(), 0, GL_RGBA, GL_FLOAT, bytes, readUpper_.data());
    setCells(width, height, readLower_, readUpper_);
}

void RayExtentGrid::setCells(int width, int height, const std::vector<glm::vec4>& lower,
                             const std::vector<glm::vec4>& upper) {
    cellsX_ = (width + kCell - 1) / kCell;
    cellsY_ = (height + kCell - 1) / kCell;
    cells_.assign(size_t(cellsX_) * size_t(cellsY_), Cell{});
    for (size_t i = 0; i < cells_.size(); ++i) {
        Cell& cell = cells_[i];
        const float state = lower[i].w;
        if (state == float(CHCRT_CULLING_CELL_EMPTY)) continue;
        cell.state = Cell::Unbounded;
        if (state != float(CHCRT_CULLING_CELL_BOUNDED)) continue;
        const glm::vec3 lo(lower[i]), hi(upper[i]);
        if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) continue; // NaN or inverted: assume nothing
        const float magnitude = std::max({1.0f, std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z), std::fabs(hi.x),
                                          std::fabs(hi.y), std::fabs(hi.z)});
        const float pad = magnitude * kRelativePad;
        cell.lower = lo - glm::vec3(pad);
        cell.upper = hi + glm::vec3(pad);
        cell.state = Cell::Bounded;
    }
}

bool RayExtentGrid::mayReach(const Tile& tile, const glm::vec3* lower, const glm::vec3* upper, int count) const {
    if (cells_.empty()) return true; // no grid: nothing is known
    const int x0 = std::clamp(tile.x / kCell, 0, cellsX_), y0 = std::clamp(tile.y / kCell, 0, cellsY_);
    const int x1 = std::clamp((tile.x + tile.width + kCell - 1) / kCell, 0, cellsX_);
    const int y1 = std::clamp((tile.y + tile.height + kCell - 1) / kCell, 0, cellsY_);
    for (int cy = y0; cy < y1; ++cy) {
        for (int cx = x0; cx < x1; ++cx) {
            const Cell& cell = cells_[size_t(cy) * size_t(cellsX_) + size_t(cx)];
            if (cell.state == Cell::Empty) continue;
            if (cell.state == Cell::Unbounded) return true;
            for (int i = 0; i < count; ++i) {
                const bool overlap = lower[i].x <= cell.upper.x && cell.lower.x <= upper[i].x &&
                                     lower[i].y <= cell.upper.y && cell.lower.y <= upper[i].y &&
                                     lower[i].z <= cell.upper.z && cell.lower.z <= upper[i].z;
                if (overlap) return true;
            }
        }
    }
    return false;
}

} // namespace chcrt
