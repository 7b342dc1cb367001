#include "culling/ray_bounds_grid.h"

#include "culling/camera_ray_bounds.h"
#include "renderer/core/error.h"
#include "shaders/shared/culling_layout.h"
#include "shaders/shared/render_layout.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace chcrt {
namespace {

static_assert(RayBoundsGrid::kMaxPieces == CHCRT_CULLING_BOUNDS_MAX_PIECES);

bool boxesOverlap(const glm::vec3& aLo, const glm::vec3& aHi, const glm::vec3& bLo, const glm::vec3& bHi) {
    return aLo.x <= bHi.x && bLo.x <= aHi.x && aLo.y <= bHi.y && bLo.y <= aHi.y && aLo.z <= bHi.z && bLo.z <= aHi.z;
}

} // namespace

RayBoundsGrid::RayBoundsGrid(const RayBoundsOptions& options, std::shared_ptr<ProgramCache> programs)
    : options_(options), programs_(std::move(programs)) {
    if (options.cellSize < 1 || options.cellSize > 32 || (options.cellSize & (options.cellSize - 1)) != 0) {
        throw InputError("chcrt: bounds cell size must be a power of two in [1, 32]");
    }
    if (options.pieces < 1 || options.pieces > kMaxPieces) {
        throw InputError("chcrt: bounds pieces must be in [1, " + std::to_string(kMaxPieces) + "]");
    }
    if (options.coarseCells < 1 || options.coarseCells > 64) throw InputError("chcrt: coarse cells must be in [1, 64]");
}

void RayBoundsGrid::update(GLuint origins, GLuint directions, GLuint hitImage, bool anyHit, int width, int height,
                           glm::vec3 sceneMin, glm::vec3 sceneMax, GLuint cellMarks) {
    reduce(origins, directions, hitImage, anyHit, width, height, sceneMin, sceneMax, cellMarks);
    readBack(width, height);
}

size_t RayBoundsGrid::valueCount(int width, int height) const {
    const int cell = options_.cellSize;
    return size_t((width + cell - 1) / cell) * size_t((height + cell - 1) / cell) *
           size_t(CHCRT_CULLING_BOUNDS_STRIDE(options_.pieces));
}

void RayBoundsGrid::readBack(int width, int height) {
    const size_t values = valueCount(width, height);
    readBack_.resize(values);
    glGetNamedBufferSubData(buffer_.id(), 0, GLsizeiptr(values * sizeof(glm::vec4)), readBack_.data());
    setCells(width, height, readBack_);
}

const ShaderProgram& RayBoundsGrid::reduction(int variant, bool cellMarks) {
    const ShaderProgram*& slot = variants_[variant][cellMarks ? 1 : 0];
    if (!slot) {
        slot = &programs_->get({{GL_COMPUTE_SHADER, "culling/ray_bounds.comp.glsl"}},
                               {{"CHCRT_BOUNDS_WITH_HITS", variant == 1 || variant == 2 ? "1" : "0"},
                                {"TRACE_ANY_HIT", variant == 2 ? "1" : "0"},
                                {"CHCRT_BOUNDS_LIGHT_SWEEP", variant == 3 ? "1" : "0"},
                                {"CHCRT_BOUNDS_CELL_MARKS", cellMarks ? "1" : "0"},
                                {"CHCRT_BOUNDS_PIECES", std::to_string(options_.pieces)},
                                {"CHCRT_BOUNDS_CELL", std::to_string(options_.cellSize)}});
    }
    return *slot;
}

size_t RayBoundsGrid::prepare(const ShaderProgram& program, GLuint origins, GLuint directions, int width, int height,
                              glm::vec3 sceneMin, glm::vec3 sceneMax) {
    const size_t bytes = valueCount(width, height) * sizeof(glm::vec4);
    if (bytes > bufferBytes_) {
        buffer_ = createBuffer(bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
        bufferBytes_ = bytes;
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_BOUNDS_BUFFER, buffer_.id());
    program.use();
    program.set("raySize", glm::ivec2(width, height));
    program.set("sceneMin", sceneMin);
    program.set("sceneMax", sceneMax);
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, origins);
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, directions);
    return bytes;
}

void RayBoundsGrid::reduce(GLuint origins, GLuint directions, GLuint hitImage, bool anyHit, int width, int height,
                           glm::vec3 sceneMin, glm::vec3 sceneMax, GLuint cellMarks) {
    const ShaderProgram& program = reduction(hitImage == 0 ? 0 : (anyHit ? 2 : 1), cellMarks != 0);
    const int cell = options_.cellSize;
    const int cellsX = (width + cell - 1) / cell, cellsY = (height + cell - 1) / cell;
    const size_t bytes = prepare(program, origins, directions, width, height, sceneMin, sceneMax);
    if (hitImage != 0) glBindImageTexture(CHCRT_CULLING_IMAGE_HIT, hitImage, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32UI);
    if (cellMarks != 0) {
        // An invocation per marked cell, from the command the hint pass counted; every other cell is empty (0).
        const float empty = float(CHCRT_CULLING_CELL_EMPTY);
        glClearNamedBufferSubData(buffer_.id(), GL_R32F, 0, GLsizeiptr(bytes), GL_RED, GL_FLOAT, &empty);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_COMPACT_CELLS, cellMarks);
        glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, cellMarks); // left bound (ray_bounds_grid.h)
        glDispatchComputeIndirect(GLintptr(CHCRT_CULLING_MARKED_HEADER(size_t(cellsX) * size_t(cellsY)) * 4));
    } else {
        glDispatchCompute(GLuint((cellsX + 7) / 8), GLuint((cellsY + 7) / 8), 1); // an invocation per cell
    }
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

void RayBoundsGrid::updateLightSweep(GLuint origins, GLuint directions, int width, int height, glm::vec3 sceneMin,
                                     glm::vec3 sceneMax, glm::vec3 lightMin, glm::vec3 lightMax) {
    reduceLightSweep(origins, directions, width, height, sceneMin, sceneMax, lightMin, lightMax);
    readBack(width, height);
}

void RayBoundsGrid::reduceLightSweep(GLuint origins, GLuint directions, int width, int height, glm::vec3 sceneMin,
                                     glm::vec3 sceneMax, glm::vec3 lightMin, glm::vec3 lightMax) {
    const ShaderProgram& program = reduction(3, false);
    const int cell = options_.cellSize;
    const int cellsX = (width + cell - 1) / cell, cellsY = (height + cell - 1) / cell;
    prepare(program, origins, directions, width, height, sceneMin, sceneMax);
    // The ray generator's points on the light (corner + u·edge + v·edge, in float) may lie outside the exact box by
    // their rounding: pad it as the cells' boxes are padded.
    const glm::vec3 magnitude = glm::max(glm::abs(lightMin), glm::abs(lightMax));
    const glm::vec3 pad(std::max({1.0f, magnitude.x, magnitude.y, magnitude.z}) * options_.relativePad);
    program.set("lightMin", lightMin - pad);
    program.set("lightMax", lightMax + pad);
    glDispatchCompute(GLuint((cellsX + 7) / 8), GLuint((cellsY + 7) / 8), 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

SurfaceFrames RayBoundsGrid::reduceSurfaceFrames(GLuint origins, GLuint directions, GLuint shadingNormals, int width,
                                                int height) {
    if (!surfaceFrames_) {
        surfaceFrames_ = &programs_->get({{GL_COMPUTE_SHADER, "culling/surface_frames.comp.glsl"}},
                                         {{"CHCRT_BOUNDS_CELL", std::to_string(options_.cellSize)}});
    }
    const int cell = options_.cellSize;
    const int cellsX = (width + cell - 1) / cell, cellsY = (height + cell - 1) / cell;
    const size_t values = size_t(cellsX) * size_t(cellsY) * CHCRT_CULLING_FRAMES_STRIDE;
    if (values * sizeof(glm::vec4) > framesBufferBytes_) {
        framesBufferBytes_ = values * sizeof(glm::vec4);
        framesBuffer_ = createBuffer(framesBufferBytes_, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, CHCRT_CULLING_BOUNDS_BUFFER, framesBuffer_.id());
    surfaceFrames_->use();
    surfaceFrames_->set("raySize", glm::ivec2(width, height));
    glBindTextureUnit(CHCRT_UNIT_RAY_ORIGIN, origins);
    glBindTextureUnit(CHCRT_UNIT_RAY_DIRECTION, directions);
    glBindTextureUnit(CHCRT_UNIT_GBUFFER_NORMAL, shadingNormals);
    glDispatchCompute(GLuint((cellsX + 7) / 8), GLuint((cellsY + 7) / 8), 1); // an invocation per cell
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    SurfaceFrames frames{std::vector<glm::vec4>(values), width, height};
    glGetNamedBufferSubData(framesBuffer_.id(), 0, GLsizeiptr(values * sizeof(glm::vec4)), frames.values.data());
    return frames;
}

void RayBoundsGrid::setHemisphereCells(const SurfaceFrames& frames, const HemisphereSample& set, glm::vec3 sceneMin,
                                       glm::vec3 sceneMax) {
    const int cell = options_.cellSize;
    const int cellsX = (frames.width + cell - 1) / cell, cellsY = (frames.height + cell - 1) / cell;
    assert(frames.values.size() == size_t(cellsX) * size_t(cellsY) * CHCRT_CULLING_FRAMES_STRIDE);
    setCells(frames.width, frames.height,
             hemisphereRayBounds(frames.values, cellsX, cellsY, options_.pieces, set, sceneMin, sceneMax));
}

void RayBoundsGrid::setCameraCells(const PrimaryRayBasis& basis, glm::vec3 sceneMin, glm::vec3 sceneMax) {
    setCells(basis.width, basis.height, cameraRayBounds(basis, options_.cellSize, options_.pieces, sceneMin, sceneMax));
}

void RayBoundsGrid::setCells(int width, int height, const std::vector<glm::vec4>& buffer) {
    const int cell = options_.cellSize, pieces = options_.pieces;
    cellsX_ = (width + cell - 1) / cell;
    cellsY_ = (height + cell - 1) / cell;
    cells_.assign(size_t(cellsX_) * size_t(cellsY_), CellBoxes{});
    const int points = pieces + 2; // origins, then the pieces' end points
    const size_t stride = size_t(CHCRT_CULLING_BOUNDS_STRIDE(pieces));
    for (size_t i = 0; i < cells_.size() && (i + 1) * stride <= buffer.size(); ++i) {
        CellBoxes& out = cells_[i];
        const glm::vec4* in = &buffer[i * stride];
        const float state = in[0].x;
        if (state == float(CHCRT_CULLING_CELL_EMPTY)) continue;
        out.state = 2;
        if (state != float(CHCRT_CULLING_CELL_BOUNDED) || !std::isfinite(in[0].y) || !std::isfinite(in[0].z)) continue;
        bool valid = true;
        float magnitude = std::max(1.0f, in[0].y);
        for (int j = 0; j < points; ++j) {
            const glm::vec3 lo(in[1 + 2 * j]), hi(in[2 + 2 * j]);
            valid = valid && lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z; // NaN or inverted: assume nothing
            magnitude = std::max({magnitude, std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z), std::fabs(hi.x),
                                  std::fabs(hi.y), std::fabs(hi.z)});
        }
        if (!valid) continue;
        // Float rounding of the end points (o + t·d in the shader, t from slab tests against the scene's box) and
        // of the hit points a traversal accepts is a few ulps of the magnitude of the coordinates involved.
        const glm::vec3 pad(magnitude * options_.relativePad);
        const auto point = [&](int j, int side) { return glm::vec3(in[1 + 2 * (j + 1) + side]); };
        for (int k = 0; k < pieces; ++k) {
            // Piece k of every ray lies between its points k and k + 1.
            out.lower[size_t(k)] = glm::min(point(k, 0), point(k + 1, 0)) - pad;
            out.upper[size_t(k)] = glm::max(point(k, 1), point(k + 1, 1)) + pad;
        }
        out.originLower = glm::vec3(in[1]) - pad;
        out.originUpper = glm::vec3(in[2]) + pad;
        out.pad = pad.x;
        out.directionLength = in[0].z * (1.0f + 1.0f / 1024.0f);
        const glm::vec4 directionLower = in[1 + 2 * points], directionUpper = in[2 + 2 * points];
        out.directionLower = glm::vec3(directionLower);
        out.directionUpper = glm::vec3(directionUpper);
        // Rounded outwards with a wide margin: the traversal computes its own entry and exit distances.
        out.segmentStart = directionLower.w * (1.0f - 1.0f / 1024.0f);
        out.segmentEnd = directionUpper.w * (1.0f + 1.0f / 1024.0f);
        const glm::vec3 spread = out.directionUpper - out.directionLower;
        const bool intervalValid = glm::all(glm::lessThanEqual(out.directionLower, out.directionUpper)) &&
                                   out.segmentStart <= out.segmentEnd && std::isfinite(out.segmentEnd) &&
                                   std::max({spread.x, spread.y, spread.z}) <= float(CHCRT_CULLING_FRUSTUM_MAX_SPREAD);
        if (!intervalValid) { // no frustum test for this cell
            out.directionLower = glm::vec3(-2.0f);
            out.directionUpper = glm::vec3(2.0f);
            out.segmentStart = -1.0f;
        }
        out.state = 1;
    }
    buildCoarse();
}

float RayBoundsGrid::entryLowerBound(int cx, int cy, const glm::vec3& lower, const glm::vec3& upper) const {
    if (cells_.empty()) return 0.0f;
    const CellBoxes& c = cell(cx, cy);
    if (c.state != 1 || !(c.directionLength > 0.0f)) return 0.0f;
    // Per axis, the gap between the origin box and the box; the entry point is at least that far from every origin.
    const glm::vec3 gap = glm::max(glm::vec3(0.0f), glm::max(lower - c.originUpper, c.originLower - upper));
    const float distance = std::sqrt(gap.x * gap.x + gap.y * gap.y + gap.z * gap.z);
    // Rounded down with a wide margin: the traversal's slab test rounds the entry distance its own way.
    return distance / c.directionLength * (1.0f - 1.0f / 1024.0f);
}

void RayBoundsGrid::buildCoarse() {
    const int g = options_.coarseCells, pieces = options_.pieces;
    coarseX_ = (cellsX_ + g - 1) / g;
    coarseY_ = (cellsY_ + g - 1) / g;
    coarse_.assign(size_t(coarseX_) * size_t(coarseY_), CellBoxes{});
    for (CellBoxes& c : coarse_) {
        c.lower.fill(glm::vec3(3.0e38f));
        c.upper.fill(glm::vec3(-3.0e38f));
        c.originLower = glm::vec3(1.0f); // empty until the first bounded fine cell
        c.originUpper = glm::vec3(0.0f);
    }
    for (int cy = 0; cy < cellsY_; ++cy) {
        for (int cx = 0; cx < cellsX_; ++cx) {
            const CellBoxes& fine = cell(cx, cy);
            CellBoxes& c = coarse_[size_t(cy / g) * size_t(coarseX_) + size_t(cx / g)];
            c.state = std::max(c.state, fine.state);
            if (fine.state != 1) continue;
            // Piece k of every cell covers the same fraction of its rays' segments, so their union covers it for
            // the coarse cell's rays.
            for (int k = 0; k < pieces; ++k) {
                c.lower[size_t(k)] = glm::min(c.lower[size_t(k)], fine.lower[size_t(k)]);
                c.upper[size_t(k)] = glm::max(c.upper[size_t(k)], fine.upper[size_t(k)]);
            }
            // The union of the fine cells' intervals holds every ray of the coarse cell.
            const bool first = c.originLower.x > c.originUpper.x;
            c.originLower = first ? fine.originLower : glm::min(c.originLower, fine.originLower);
            c.originUpper = first ? fine.originUpper : glm::max(c.originUpper, fine.originUpper);
            c.directionLower = first ? fine.directionLower : glm::min(c.directionLower, fine.directionLower);
            c.directionUpper = first ? fine.directionUpper : glm::max(c.directionUpper, fine.directionUpper);
            c.segmentStart = first ? fine.segmentStart : std::min(c.segmentStart, fine.segmentStart);
            c.segmentEnd = first ? fine.segmentEnd : std::max(c.segmentEnd, fine.segmentEnd);
            c.pad = std::max(c.pad, fine.pad);
        }
    }
}

bool RayBoundsGrid::piecesOverlap(const CellBoxes& c, const glm::vec3& lower, const glm::vec3& upper) const {
    for (int k = 0; k < options_.pieces; ++k) {
        if (boxesOverlap(c.lower[size_t(k)], c.upper[size_t(k)], lower, upper)) return true;
    }
    return false;
}

bool RayBoundsGrid::frustumOverlaps(const CellBoxes& c, const glm::vec3& lower, const glm::vec3& upper) const {
    // The box padded as the pieces are (their pad is in them already: the difference of a piece's and the origins'
    // padded bounds is the pad, which covers the rounding of the divisions as well).
    const glm::vec3 pad(c.pad);
    return gpu::rayIntervalMayHit(c.originLower, c.originUpper, c.directionLower, c.directionUpper, c.segmentStart,
                                  c.segmentEnd, lower - pad, upper + pad);
}

bool RayBoundsGrid::overlaps(const CellBoxes& c, const glm::vec3* lower, const glm::vec3* upper, int count) const {
    if (c.state == 0) return false;
    if (c.state == 2) return true;
    // A box is reached when a piece meets it and the frustum does; the frustum is tested only where a piece met the
    // box (the pieces are the cheaper test). Counted by the shape that decided: the pieces, else the frustum.
    bool pieces = false;
    for (int i = 0; i < count; ++i) {
        if (!piecesOverlap(c, lower[i], upper[i])) continue;
        pieces = true;
        if (!options_.frustum || frustumOverlaps(c, lower[i], upper[i])) {
            ++decisions_.reached;
            return true;
        }
    }
    ++(pieces ? decisions_.frustum : decisions_.pieces);
    return false;
}

std::array<int, 4> RayBoundsGrid::cellRange(const Tile& tile) const {
    const int cell = options_.cellSize;
    return {std::clamp(tile.x / cell, 0, cellsX_), std::clamp(tile.y / cell, 0, cellsY_),
            std::clamp((tile.x + tile.width + cell - 1) / cell, 0, cellsX_),
            std::clamp((tile.y + tile.height + cell - 1) / cell, 0, cellsY_)};
}

bool RayBoundsGrid::cellMayReach(int cx, int cy, const glm::vec3* lower, const glm::vec3* upper, int count) const {
    if (cells_.empty()) return true;
    return overlaps(cell(cx, cy), lower, upper, count);
}

bool RayBoundsGrid::mayReach(const Tile& tile, const glm::vec3* lower, const glm::vec3* upper, int count) const {
    if (cells_.empty()) return true; // nothing known
    const auto [x0, y0, x1, y1] = cellRange(tile);
    const int g = options_.coarseCells;
    for (int gy = y0 / g; gy * g < y1; ++gy) {
        for (int gx = x0 / g; gx * g < x1; ++gx) {
            if (!overlaps(coarse_[size_t(gy) * size_t(coarseX_) + size_t(gx)], lower, upper, count)) continue;
            for (int cy = std::max(y0, gy * g); cy < std::min(y1, (gy + 1) * g); ++cy) {
                for (int cx = std::max(x0, gx * g); cx < std::min(x1, (gx + 1) * g); ++cx) {
                    if (overlaps(cell(cx, cy), lower, upper, count)) return true;
                }
            }
        }
    }
    return false;
}

std::array<uint32_t, 3> RayBoundsGrid::cellStates() const {
    std::array<uint32_t, 3> counts{};
    for (const CellBoxes& c : cells_) ++counts[c.state];
    return counts;
}

} // namespace chcrt
