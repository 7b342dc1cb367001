#version 450 core
// CHC+RT subtree intersection over cell lists (culling/cell_traversal.h) for the rays the hint pass left
// (culling/hint_pass.h): one invocation per listed ray, dispatched indirectly from the compaction buffer, each ray
// traced through its cell's list by cell_pixel.glsl. Consecutive invocations hold rays that still need the
// traversal, instead of lanes that wait for them; the rays' hints were visited and dropped by the hint pass, so
// cell_pixel.glsl only records the leaf of a new hit (CellTraversal compiles it with CHCRT_CULLING_HINTS_VISITED).
// Host defines: cell_pixel.glsl's.
#include "culling/cell_pixel.glsl"

layout(local_size_x = CHCRT_CULLING_COMPACT_GROUP) in;

layout(std430, binding = CHCRT_CULLING_COMPACT_BUFFER) readonly buffer Compaction {
    uint dispatchGroups;
    uint dispatchY;
    uint dispatchZ;
    uint listed;
    uint pixels[];
};

void main() {
    uint slot = gl_GlobalInvocationID.x;
    if (slot >= listed) {
        return;
    }
    ivec2 pixel = ivec2(pixels[slot] & 0xffffu, pixels[slot] >> 16);
    ivec2 cell = pixel / cellSize;
    traceCellPixel(pixel, cell.y * cellsX + cell.x);
}
