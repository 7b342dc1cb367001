#version 450 core
// CHC+RT subtree intersection over cell lists (culling/cell_traversal.h) as a compute pass: one work group per cell
// with work, one invocation per pixel of it, each ray traced by cell_pixel.glsl. For GPUs whose fragment work runs
// on few graphics-capable units (docs/architecture.md); there is no early depth test here, so inactive rays
// (tmax <= tmin, NaN counting as inactive as in every tracer) and, for any-hit rays, finished ones return at once.
// Host defines: cell_pixel.glsl's and CHCRT_CELL_SIZE (the cell edge in pixels = the work group's edge).
#include "culling/cell_pixel.glsl"
#include "render/group_pixels.glsl"

layout(local_size_x = CHCRT_CELL_SIZE, local_size_y = CHCRT_CELL_SIZE) in;

layout(binding = CHCRT_UNIT_CULLING_DRAW_CELLS) uniform usamplerBuffer drawCells;

uniform ivec2 raySize; // pixels of the ray set

void main() {
    int cellIndex = int(texelFetch(drawCells, int(gl_WorkGroupID.x)).x);
    ivec2 pixel = ivec2(cellIndex % cellsX, cellIndex / cellsX) * cellSize +
                  groupPixel(gl_LocalInvocationIndex, uint(CHCRT_CELL_SIZE));
    if (any(greaterThanEqual(pixel, raySize))) {
        return;
    }
    if (!(texelFetch(rayDirections, pixel, 0).w > texelFetch(rayOrigins, pixel, 0).w)) {
        return; // inactive: the mask a fragment pass tests early
    }
    traceCellPixel(pixel, cellIndex);
}
