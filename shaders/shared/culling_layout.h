#ifndef CHCRT_SHARED_CULLING_LAYOUT_H
#define CHCRT_SHARED_CULLING_LAYOUT_H
// Constants shared by the CHC+RT passes (culling/chcrt_tracer.cpp) and their shaders (shaders/culling/*).
#include "shared_begin.h"

// Image unit of the hit buffer (RGBA32UI, layout of CHCRT_TRACE_OUT_HIT). Subtree passes over the same pixels
// read and update it with image load/store, separated by glMemoryBarrier (see culling/README.md).
#define CHCRT_CULLING_IMAGE_HIT 0

// Image unit of the optional debug image (R32UI: query overdraw, subtree ids, subtrees or traversal steps per
// pixel; see ChcrtDebugImage in culling/chcrt_tracer.h). Only the instrumented shader variants use it.
#define CHCRT_CULLING_IMAGE_DEBUG 1

// Image unit of an any-hit ray set's hit hints (R32UI, one texel per ray: the BVH node index of the leaf in which the
// ray found its hit in the previous trace of its ray set, CHCRT_NO_HIT_ID for none). The cell passes visit a ray's
// hinted leaf before its cell's list and record the leaf of every hit they find (culling/README.md, "Hit hints").
#define CHCRT_CULLING_IMAGE_HINT 2

// Out of core (culling/README.md "Hit hints out of core"): texture unit of the GPU cache's slot epochs (R32UI texture
// buffer, one texel per slot of the subtree pool: the low 32 bits of the cache's contentEpoch right after the slot's
// last replacement, 0 for none). A hint whose slot was replaced since its image was last validated is dropped.
#define CHCRT_UNIT_CULLING_HINT_SLOTS 33

// Image unit of the hit triangle image (R32UI), written beside the subtree-id debug image when the subtree passes
// are compiled with CHCRT_HIT_TRIANGLE_INDEX: the index, in the BVH-ordered triangle buffer, of the triangle that
// produced the pixel's latest hit change. The out-of-core primary resolve reads that one triangle of a subtree
// instead of the whole subtree (culling/outofcore/primary_resolve.h).
#define CHCRT_CULLING_IMAGE_HIT_TRIANGLE 3

// Cost debug image (CHCRT_CULLING_DEBUG_COST): the traversal-steps word of render_layout.h (CHCRT_TRACE_STEPS_*),
// summed over the subtree passes; the capped bit marks a pixel whose ray reached the loop cap in some pass. The
// viewer's cost view (shaders/viewer/visualize.frag.glsl) decodes it.

// Ray bounds grid (culling/ray_bounds_grid.h): screen cells of `cellSize`² pixels, each reduced to the boxes
// around CHCRT_CULLING_BOUNDS pieces of its active rays' segments — the part of each ray that can still change
// its hit, clipped to the scene's box. Buffer layout per cell (std430 vec4s): a header (state, extent, largest
// direction length, 0), then (lower.xyz, 0) and (upper.xyz, 0) of the ray origins and of each of the pieces + 1
// points that split every segment into equal pieces. `extent` bounds the magnitude of every coordinate the points
// were computed from (the CPU pads the boxes by a fraction of it for float rounding). Then the cell's ray interval
// (the "frustum" shape, rayIntervalMayHit below): (smallest direction components, smallest segment start t0) and
// (largest direction components, largest segment end t1). CHCRT_CULLING_BOUNDS_STRIDE vec4s per cell.
#define CHCRT_CULLING_BOUNDS_MAX_PIECES 8
#define CHCRT_CULLING_BOUNDS_STRIDE(pieces) (1 + 2 * ((pieces) + 2) + 2)
// A cell whose direction components spread wider than this gets no frustum test: its rays fan out (AO, diffuse), the
// test then culls almost nothing and only costs (city near, 256², AO: 322 of 36,000 tests per frame decided by it).
#define CHCRT_CULLING_FRUSTUM_MAX_SPREAD 0.5
#define CHCRT_CULLING_CELL_EMPTY 0.0     // no active ray (or every one finished / outside the scene's box)
#define CHCRT_CULLING_CELL_BOUNDED 1.0   // every active ray's segment is inside the union of the piece boxes
#define CHCRT_CULLING_CELL_UNBOUNDED 2.0 // some active ray has a NaN or infinite value: nothing is assumed
#define CHCRT_CULLING_BOUNDS_BUFFER 0    // shader storage binding of the grid's buffer
// The surface frames of hemisphere rays (AO; culling/hemisphere_ray_bounds.h, surface_frames.comp.glsl in shaders/):
// per cell of the grid, over the pixels with a surface point (active rays and inactive ones that kept their origin),
// a header (state as above, smallest and largest length of the shading normal, 0), then per class of normals (the
// axis of the normal's largest component and its sign: +x, -x, +y, -y, +z, -z) (lower.xyz, w) and (upper.xyz, 0) of
// the ray origins (w: 1 if the class has a point, else 0), the shading normals n, and the tangents and bitangents
// the ray generator builds from them (render/sampling.glsl). Classes keep a cell where a wall meets the ground from
// bounding one frame box around both. CHCRT_CULLING_FRAMES_STRIDE vec4s per cell; bound at
// CHCRT_CULLING_BOUNDS_BUFFER.
#define CHCRT_CULLING_FRAME_CLASSES 6
#define CHCRT_CULLING_FRAME_BOXES 4 // origins, normals, tangents, bitangents
#define CHCRT_CULLING_FRAMES_STRIDE (1 + 2 * CHCRT_CULLING_FRAME_BOXES * CHCRT_CULLING_FRAME_CLASSES)

// Cell lists (culling/cell_traversal.h): the termination subtrees each screen cell's rays traverse in one draw of
// the cells that have work (CHC+RT §5.2 batches, one per cell). Texture units of the RG32UI / R32UI texture
// buffers: per cell (first entry, entry count); per entry (the subtree's GPU root, bits of a lower bound of the
// distance at which the cell's rays can enter it; a cell's entries ascend by it); per entry the subtree's
// culling-hierarchy index (for the subtree debug image); the cells with work, drawn as points.
#define CHCRT_UNIT_CULLING_CELL_HEADERS 27
#define CHCRT_UNIT_CULLING_CELL_ROOTS 28
#define CHCRT_UNIT_CULLING_CELL_IDS 29
#define CHCRT_UNIT_CULLING_DRAW_CELLS 30

// Cell lists decided on the GPU (`--chcrt-queries bounds-gpu`, culling/gpu_cell_lists.h): one compute invocation per
// cell traverses the upper hierarchy with the cell's boxes from the ray bounds buffer and writes the cell's list
// in the layouts above (headers, roots, ids as the cell pass reads them through texture buffers), appending the
// cell to the cells drawn. The upper hierarchy is a texture buffer of CHCRT_CULLING_HIERARCHY_TEXELS RGBA32F texels
// per node: (box min, bits of the first child or CHCRT_NO_HIT_ID for a termination root), (box max, bits of the
// termination root's GPU root), (tight box 0 min, bits of the tight box count), (tight box 0 max, bits of the
// subtree index), (tight box 1 min, 0), (tight box 1 max, 0). Shader storage bindings of the outputs: headers
// (uvec2 per cell), roots (uvec2 per entry), ids (uint per entry), and the draw buffer: an indirect draw command
// (count, instances, first, base instance), an indirect dispatch command (count, 1, 1) and a 0, the counters
// (entries, cells over the list limit, nodes tested, box tests culled by the pieces, by the ray interval, and
// reached), then from CHCRT_CULLING_GPU_DRAW_HEADER on the cells drawn. Entry 0 of the roots is the whole tree; cell c's list starts at 1 + c ·
// CHCRT_CULLING_GPU_LIST_MAX, and a cell with more entries than its limit traverses the whole tree instead.
#define CHCRT_UNIT_CULLING_HIERARCHY 31
#define CHCRT_CULLING_HIERARCHY_TEXELS 6
#define CHCRT_CULLING_GPU_HEADERS_BUFFER 1
#define CHCRT_CULLING_GPU_ROOTS_BUFFER 2
#define CHCRT_CULLING_GPU_IDS_BUFFER 3
#define CHCRT_CULLING_GPU_DRAW_BUFFER 4
#define CHCRT_CULLING_GPU_DISPATCH_OFFSET 16 // bytes: the dispatch command in the draw buffer
#define CHCRT_CULLING_GPU_DRAW_HEADER 64 // uints before the cells drawn (256 bytes: any texture-buffer offset alignment)
#define CHCRT_CULLING_GPU_LIST_MAX 64

// Hint pass (culling/hint_pass.h): shader storage binding of its compaction buffer. Layout (uints): an indirect
// dispatch command (work groups of CHCRT_CULLING_COMPACT_GROUP rays, 1, 1), the number of rays listed, then from
// CHCRT_CULLING_COMPACT_HEADER on the pixel of each ray left for the cell lists (x | y << 16). The pass that appends
// a ray adds a work group whenever its slot starts one, so the command always covers exactly the rays listed.
#define CHCRT_CULLING_COMPACT_BUFFER 5
#define CHCRT_CULLING_COMPACT_GROUP 64
#define CHCRT_CULLING_COMPACT_HEADER 4
// And the binding of its cell marks, which let the reduction after it skip the cells whose rays all ended at their
// hints. Layout (uints) for a grid of C cells: a mark per cell (nonzero where the pass listed a ray), then at
// CHCRT_CULLING_MARKED_HEADER(C) an indirect dispatch command (work groups of CHCRT_CULLING_MARKED_GROUP cells, 1, 1)
// and the number of cells marked, then from CHCRT_CULLING_MARKED_LIST(C) on the index of each marked cell (the pass
// appends a cell when it marks it first), so that the reduction runs over the marked cells alone.
#define CHCRT_CULLING_COMPACT_CELLS 6
#define CHCRT_CULLING_MARKED_GROUP 32
#define CHCRT_CULLING_MARKED_HEADER(cells) (cells)
#define CHCRT_CULLING_MARKED_LIST(cells) ((cells) + 4)
#define CHCRT_CULLING_MARKED_UINTS(cells) (2 * (cells) + 4)

// Batched queries (`--chcrt-queries batched`, culling/batched_queries.h): the pairs of one round are tested by one
// compute dispatch instead of a GL occlusion query each. Shader storage bindings: the round's input (uvec4s: per
// pair CHCRT_CULLING_BATCH_PAIR_TEXELS of them — (tile x, y, width, height), (box count, 0, 0, 0), then box 0 min,
// box 0 max, box 1 min, box 1 max as float bits — followed from `itemBase` on by the work items (pair, first pixel of
// the tile's row-major order, 0, 0)) and a uint count per pair: the tile's rays that reach one of its boxes before
// their nearest hit so far, counted until it exceeds the visible threshold. A work group takes CHCRT_CULLING_BATCH_ITEM
// pixels of one pair's tile.
#define CHCRT_CULLING_BATCH_INPUT_BUFFER 7
#define CHCRT_CULLING_BATCH_COUNTS_BUFFER 8
#define CHCRT_CULLING_BATCH_PAIR_TEXELS 6
#define CHCRT_CULLING_BATCH_GROUP 64
#define CHCRT_CULLING_BATCH_ITEM 1024

// Boxes per occlusion query: §5.1 multi-queries of up to 8 pairs with tighter bounds (2 child boxes each).
#define CHCRT_CULLING_MAX_QUERY_BOXES 16

// CHC+RT §5.2 by-tile batching: at most this many subtree roots per shader call.
#define CHCRT_CULLING_MAX_BATCH 24

// Ray distance -> depth for the generalized occlusion queries (§4.1): depth = clamp(t * 2^-64, 0, 1).
// Multiplying by a power of two is exact for every normal float, so the mapping is strictly monotone on
// [2^-62, 2^64) and non-decreasing everywhere (underflow and clamping only merge values). Hence
// entry <= best t implies depth(entry) <= depth(best t). The depth buffer holds depth(pruneLimit(best t))
// (shared/intersect.h), the same limit traversal prunes with; with GL_LEQUAL a box that could hold a hit at the
// current nearest t is never culled, including an entry equal to the hit distance and rays starting inside
// the box (entry < 0 maps to 0). DEPTH32F stores gl_FragDepth in [0, 1] exactly.
#define CHCRT_CULLING_DEPTH_SCALE 5.42101086242752217e-20

#ifdef __cplusplus
#define CHCRT_INLINE inline
#define CHCRT_INOUT_FLOAT float&
using glm::max;
using glm::min;
#else
#define CHCRT_INLINE
#define CHCRT_INOUT_FLOAT inout float
#endif

CHCRT_INLINE float depthFromDistance(float t) {
    return min(max(t * float(CHCRT_CULLING_DEPTH_SCALE), 0.0f), 1.0f);
}

// The "frustum" shape of a cell's rays (interval arithmetic, as packet tracers test a packet against a box): every ray
// o + t·d of the cell has o in [oLo, oHi], d in [dLo, dHi] and t in [tLo, tHi], tLo >= 0. Per axis, some ray may be
// inside the box's slab at t only if oLo + t·dLo <= bHi and oHi + t·dHi >= bLo (the smallest and largest coordinate
// any ray of the intervals reaches at t >= 0); false when the axes' t intervals and [tLo, tHi] have nothing in
// common: no ray of the cell meets the box. Each axis may pick another ray, so this is conservative; a cell of one
// origin and a narrow bundle of directions (primary rays, shadow rays seen from the light) gets a tight test. The
// callers pad the box and the origins against float rounding (as the pieces' boxes).
CHCRT_INLINE bool rayIntervalAxis(float oLo, float oHi, float dLo, float dHi, float bLo, float bHi,
                                  CHCRT_INOUT_FLOAT lo, CHCRT_INOUT_FLOAT hi) {
    if (dLo > 0.0f) hi = min(hi, (bHi - oLo) / dLo);
    else if (dLo < 0.0f) lo = max(lo, (bHi - oLo) / dLo);
    else if (oLo > bHi) return false;
    if (dHi < 0.0f) hi = min(hi, (bLo - oHi) / dHi);
    else if (dHi > 0.0f) lo = max(lo, (bLo - oHi) / dHi);
    else if (oHi < bLo) return false;
    return true;
}

CHCRT_INLINE bool rayIntervalMayHit(vec3 oLo, vec3 oHi, vec3 dLo, vec3 dHi, float tLo, float tHi, vec3 bLo, vec3 bHi) {
    if (!(tLo >= 0.0f)) return true; // the test assumes t >= 0
    float lo = tLo;
    float hi = tHi;
    if (!rayIntervalAxis(oLo.x, oHi.x, dLo.x, dHi.x, bLo.x, bHi.x, lo, hi)) return false;
    if (!rayIntervalAxis(oLo.y, oHi.y, dLo.y, dHi.y, bLo.y, bHi.y, lo, hi)) return false;
    if (!rayIntervalAxis(oLo.z, oHi.z, dLo.z, dHi.z, bLo.z, bHi.z, lo, hi)) return false;
    return lo <= hi;
}

#undef CHCRT_INLINE
#undef CHCRT_INOUT_FLOAT
#include "shared_end.h"
#endif
