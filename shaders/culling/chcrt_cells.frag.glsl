#version 450 core
// CHC+RT subtree intersection over cell lists (culling/cell_traversal.h) as a fragment pass: one draw per round, a
// point per cell with work (chcrt_cells.vert.glsl); each pixel's ray is traced by cell_pixel.glsl. Inactive and
// finished rays are rejected by the early depth test against a mask (the ray set's active-ray mask, or
// chcrt_cells_mask.frag.glsl's), as in the pure passes: nothing here writes depth. Host defines: cell_pixel.glsl's.
#include "culling/cell_pixel.glsl"

layout(early_fragment_tests) in;

flat in int cellIndex;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 cell = pixel / cellSize;
    if (cell.y * cellsX + cell.x != cellIndex) {
        return; // a neighbour's pixel under an edge cell's shifted point
    }
    traceCellPixel(pixel, cellIndex);
}
