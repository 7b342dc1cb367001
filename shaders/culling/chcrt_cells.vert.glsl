#version 450 core
// CHC+RT cell lists (culling/cell_traversal.h): six vertices per cell with work make its rectangle, so one draw
// shades exactly the pixels of the cells that have subtrees to traverse (llvmpipe shades every fragment group it
// rasterises through the whole traversal code, so cells without work must not be drawn at all). Depth 0 in NDC:
// the early depth test against the ray set's mask (1 = a ray to trace) passes under either clip-control convention.
#include "shared/culling_layout.h"

layout(binding = CHCRT_UNIT_CULLING_DRAW_CELLS) uniform usamplerBuffer drawCells;

uniform ivec2 raySize;  // pixels of the ray set = the viewport
uniform int cellsX;
uniform int cellSize;

flat out uint cellIndex;

void main() {
    cellIndex = texelFetch(drawCells, gl_VertexID / 6).x;
    // Two triangles (0,0) (1,0) (1,1) and (0,0) (1,1) (0,1): a shared diagonal rasterises each pixel once.
    int corner = gl_VertexID % 6;
    ivec2 offset = ivec2(corner == 1 || corner == 2 || corner == 4 ? 1 : 0, corner == 2 || corner >= 4 ? 1 : 0);
    ivec2 cell = ivec2(int(cellIndex) % cellsX, int(cellIndex) / cellsX);
    vec2 pixel = vec2(min((cell + offset) * cellSize, raySize));
    gl_Position = vec4(pixel / vec2(raySize) * 2.0f - 1.0f, 0.0f, 1.0f);
}
