// Which pixel each invocation of a square compute work group traces (render/trace_bvh.comp.glsl: CHCRT_TRACE_GROUP_SIZE
// wide; culling/chcrt_cells.comp.glsl: one cell). Consecutive invocations run together — 32 in a warp on NVIDIA GPUs,
// 8 per SIMD group on llvmpipe — and a group lasts as long as its slowest ray, so they take compact blocks of pixels,
// whose rays' costs go together, rather than rows: 8×4 blocks (a warp) made of 4×2 blocks (llvmpipe's 8 lanes, the
// shape of its fragment groups). Row by row, a warp of a 16-pixel cell held two rows and llvmpipe's groups were 8×1.
// Measured in culling/README.md, "Cell passes in compute". Groups narrower than 8 pixels keep rows.
#ifndef CHCRT_GROUP_PIXELS_GLSL
#define CHCRT_GROUP_PIXELS_GLSL

// The pixel of invocation `i` (gl_LocalInvocationIndex) of a work group `size` × `size` pixels.
ivec2 groupPixel(uint i, uint size) {
    if (size % 8u != 0u) {
        return ivec2(i % size, i / size);
    }
    uint lane = i & 31u;
    uint block = i >> 5u;
    uvec2 inBlock = uvec2(lane & 3u, (lane >> 2u) & 1u) + uvec2((lane >> 3u) & 1u, (lane >> 4u) & 1u) * uvec2(4u, 2u);
    uint blocksX = size / 8u;
    return ivec2(uvec2(block % blocksX, block / blocksX) * uvec2(8u, 4u) + inBlock);
}
#endif
