#version 450 core
// CHC+RT cell lists (culling/cell_traversal.h): one point per cell with work, of the cell's size, so a draw shades
// exactly the pixels of those cells. Points, not two triangles per cell: llvmpipe shades the 4×4 blocks a quad's
// diagonal cuts once per triangle (measured 1.5x slower per traversal step). A point is clipped when its centre
// leaves the viewport, so a cell cut by the ray set's edge is drawn as a point shifted inwards; the fragment shader
// drops the pixels of the neighbouring cell it then covers. Depth 0 in NDC: the early depth test against a mask
// (1 = a ray to trace) passes under either clip-control convention.
#include "shared/culling_layout.h"

layout(binding = CHCRT_UNIT_CULLING_DRAW_CELLS) uniform usamplerBuffer drawCells;

uniform ivec2 raySize; // pixels of the ray set = the viewport
uniform int cellsX;
uniform int cellSize;

flat out int cellIndex;

void main() {
    cellIndex = int(texelFetch(drawCells, gl_VertexID).x);
    ivec2 lower = ivec2(cellIndex % cellsX, cellIndex / cellsX) * cellSize;
    vec2 centre = vec2(min(lower + cellSize, raySize) - cellSize) + 0.5f * float(cellSize);
    gl_Position = vec4(centre / vec2(raySize) * 2.0f - 1.0f, 0.0f, 1.0f);
    gl_PointSize = float(cellSize);
}
