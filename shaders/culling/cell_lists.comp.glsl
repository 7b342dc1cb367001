#version 450 core
// CHC+RT cell lists decided on the GPU (culling/gpu_cell_lists.h, `--chcrt-queries bounds-gpu`): one invocation per
// screen cell reads the cell's boxes from the ray bounds buffer (ray_bounds.comp.glsl), traverses the upper
// hierarchy down to the termination roots with them — a node whose tight boxes (§5.1: its children's) meet none of
// the cell's piece boxes holds nothing the cell's rays can hit before their current hits — and writes the reached
// roots, sorted by a lower bound of the distance at which the cell's rays can enter them, as the cell's list
// (layouts in shared/culling_layout.h); a cell with work is appended to the cells drawn. The same decisions as the
// CPU's bounds-only mode (culling/ray_bounds_grid.cpp: padding, pieces, entry bounds), per cell instead of per tile
// and cell, with no read-back. A cell with an unbounded ray, or with more roots than the list limit, traverses the
// whole tree (entry 0).
// Host defines: CHCRT_BOUNDS_PIECES (1 .. CHCRT_CULLING_BOUNDS_MAX_PIECES).
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/culling_layout.h"

#define POINTS (CHCRT_BOUNDS_PIECES + 2) // in the bounds buffer: the origins, then p_0 .. p_P
#define STRIDE CHCRT_CULLING_BOUNDS_STRIDE(CHCRT_BOUNDS_PIECES)

layout(local_size_x = 64) in;

layout(std430, binding = CHCRT_CULLING_BOUNDS_BUFFER) readonly buffer CellBounds {
    vec4 cellBounds[];
};
layout(std430, binding = CHCRT_CULLING_GPU_HEADERS_BUFFER) writeonly buffer Headers {
    uvec2 headers[];
};
layout(std430, binding = CHCRT_CULLING_GPU_ROOTS_BUFFER) writeonly buffer Roots {
    uvec2 roots[];
};
layout(std430, binding = CHCRT_CULLING_GPU_IDS_BUFFER) writeonly buffer Ids {
    uint ids[];
};
layout(std430, binding = CHCRT_CULLING_GPU_DRAW_BUFFER) buffer Draw {
    uint draw[];
};
layout(binding = CHCRT_UNIT_CULLING_HIERARCHY) uniform samplerBuffer hierarchy;

uniform uint cellCount;
uniform uint listLimit;      // at most CHCRT_CULLING_GPU_LIST_MAX
uniform float relativePad;   // RayBoundsOptions::relativePad
uniform bool frustum;        // RayBoundsOptions::frustum

vec3 pieceLower[CHCRT_BOUNDS_PIECES];
vec3 pieceUpper[CHCRT_BOUNDS_PIECES];
vec3 originLower, originUpper, directionLower, directionUpper;
float segmentStart, segmentEnd;
vec3 pad;

bool boxesOverlap(vec3 aLo, vec3 aHi, vec3 bLo, vec3 bHi) {
    return all(lessThanEqual(aLo, bHi)) && all(lessThanEqual(bLo, aHi));
}

// What decided this cell's box tests, as RayBoundsGrid::ShapeDecisions counts them on the CPU: culled by the
// pieces, culled by the ray interval where a piece met the box, reached.
uint culledByPieces = 0u, culledByFrustum = 0u, boxesReached = 0u;

// As RayBoundsGrid::overlaps: a piece meets the box, and so does the cell's ray interval.
bool reachesBox(vec3 lo, vec3 hi) {
    bool piece = false;
    for (int k = 0; k < CHCRT_BOUNDS_PIECES; ++k) {
        piece = piece || boxesOverlap(pieceLower[k], pieceUpper[k], lo, hi);
    }
    if (!piece) {
        ++culledByPieces;
        return false;
    }
    if (frustum && !rayIntervalMayHit(originLower, originUpper, directionLower, directionUpper, segmentStart,
                                      segmentEnd, lo - pad, hi + pad)) {
        ++culledByFrustum;
        return false;
    }
    ++boxesReached;
    return true;
}

void writeWholeTree(uint cell) {
    headers[cell] = uvec2(0u, 1u);
    uint slot = atomicAdd(draw[0], 1u);
    atomicAdd(draw[4], 1u);
    atomicAdd(draw[9], 1u);
    draw[CHCRT_CULLING_GPU_DRAW_HEADER + slot] = cell;
}

void main() {
    uint cell = gl_GlobalInvocationID.x;
    if (cell >= cellCount) {
        return;
    }
    uint base = cell * uint(STRIDE);
    vec4 header = cellBounds[base];
    if (header.x == float(CHCRT_CULLING_CELL_EMPTY)) {
        headers[cell] = uvec2(0u, 0u);
        return;
    }
    // As RayBoundsGrid::setCells: NaN, infinite or inverted values assume nothing.
    bool bounded = header.x == float(CHCRT_CULLING_CELL_BOUNDED) && !isinf(header.y) && !isnan(header.y) &&
                   !isinf(header.z) && !isnan(header.z);
    float magnitude = max(1.0f, header.y);
    for (int j = 0; j < POINTS && bounded; ++j) {
        vec3 lo = cellBounds[base + 1u + 2u * uint(j)].xyz;
        vec3 hi = cellBounds[base + 2u + 2u * uint(j)].xyz;
        bounded = all(lessThanEqual(lo, hi));
        magnitude = max(magnitude, max(max(abs(lo.x), abs(lo.y)), max(max(abs(lo.z), abs(hi.x)), max(abs(hi.y), abs(hi.z)))));
    }
    if (!bounded) {
        writeWholeTree(cell);
        return;
    }
    pad = vec3(magnitude * relativePad);
    for (int k = 0; k < CHCRT_BOUNDS_PIECES; ++k) {
        // Piece k of every ray lies between its points k and k + 1.
        uint a = base + 3u + 2u * uint(k), b = a + 2u;
        pieceLower[k] = min(cellBounds[a].xyz, cellBounds[b].xyz) - pad;
        pieceUpper[k] = max(cellBounds[a + 1u].xyz, cellBounds[b + 1u].xyz) + pad;
    }
    originLower = cellBounds[base + 1u].xyz - pad;
    originUpper = cellBounds[base + 2u].xyz + pad;
    float directionLength = header.z * (1.0f + 1.0f / 1024.0f);
    // The ray interval, rounded outwards as on the CPU; a cell whose interval is not valid gets no frustum test.
    vec4 intervalLower = cellBounds[base + uint(1 + 2 * POINTS)];
    vec4 intervalUpper = cellBounds[base + uint(2 + 2 * POINTS)];
    directionLower = intervalLower.xyz;
    directionUpper = intervalUpper.xyz;
    segmentStart = intervalLower.w * (1.0f - 1.0f / 1024.0f);
    segmentEnd = intervalUpper.w * (1.0f + 1.0f / 1024.0f);
    vec3 spread = directionUpper - directionLower;
    if (!(all(lessThanEqual(directionLower, directionUpper)) && segmentStart <= segmentEnd && !isinf(segmentEnd) &&
          max(max(spread.x, spread.y), spread.z) <= float(CHCRT_CULLING_FRUSTUM_MAX_SPREAD))) {
        segmentStart = -1.0f; // rayIntervalMayHit: always true
    }

    uint listRoot[CHCRT_CULLING_GPU_LIST_MAX];
    float listBound[CHCRT_CULLING_GPU_LIST_MAX];
    uint listId[CHCRT_CULLING_GPU_LIST_MAX];
    uint count = 0u;
    uint tested = 0u;
    bool overflow = false;
    uint stack[CHCRT_MAX_BVH_DEPTH];
    int stackSize = 1;
    stack[0] = 0u;
    // The upper hierarchy is at most as deep as the BVH, so the stack never overflows; at most listLimit + 1 roots
    // are kept before the cell gives up on its list, so the loop ends well below llvmpipe's iteration cap.
    while (stackSize > 0 && !overflow) {
        uint node = stack[--stackSize];
        int texel = int(node) * CHCRT_CULLING_HIERARCHY_TEXELS;
        vec4 box0 = texelFetch(hierarchy, texel);
        vec4 box1 = texelFetch(hierarchy, texel + 1);
        vec4 tight0 = texelFetch(hierarchy, texel + 2);
        vec4 tight1 = texelFetch(hierarchy, texel + 3);
        ++tested;
        bool reached = reachesBox(tight0.xyz, tight1.xyz);
        if (!reached && floatBitsToUint(tight0.w) == 2u) {
            reached = reachesBox(texelFetch(hierarchy, texel + 4).xyz, texelFetch(hierarchy, texel + 5).xyz);
        }
        if (!reached) {
            continue;
        }
        uint firstChild = floatBitsToUint(box0.w);
        if (firstChild != CHCRT_NO_HIT_ID) {
            stack[stackSize++] = firstChild + 1u;
            stack[stackSize++] = firstChild;
            continue;
        }
        if (count == listLimit) {
            overflow = true;
            break;
        }
        // A lower bound of the distance at which a ray of the cell enters the node's box: the gap between the box
        // and the origins over the longest direction, rounded down with a wide margin (entryLowerBound on the CPU).
        vec3 gap = max(vec3(0.0f), max(box0.xyz - originUpper, originLower - box1.xyz));
        float bound = directionLength > 0.0f ? length(gap) / directionLength * (1.0f - 1.0f / 1024.0f) : 0.0f;
        // Insertion by bound (stable: equal bounds keep their traversal order).
        uint i = count;
        while (i > 0u && listBound[i - 1u] > bound) {
            listRoot[i] = listRoot[i - 1u];
            listBound[i] = listBound[i - 1u];
            listId[i] = listId[i - 1u];
            --i;
        }
        listRoot[i] = floatBitsToUint(box1.w);
        listBound[i] = bound;
        listId[i] = floatBitsToUint(tight1.w);
        ++count;
    }
    atomicAdd(draw[10], tested);
    atomicAdd(draw[11], culledByPieces);
    atomicAdd(draw[12], culledByFrustum);
    atomicAdd(draw[13], boxesReached);
    if (overflow) {
        writeWholeTree(cell);
        return;
    }
    uint first = 1u + cell * uint(CHCRT_CULLING_GPU_LIST_MAX);
    headers[cell] = uvec2(first, count);
    if (count == 0u) {
        return;
    }
    for (uint i = 0u; i < count; ++i) {
        roots[first + i] = uvec2(listRoot[i], floatBitsToUint(listBound[i]));
        ids[first + i] = listId[i];
    }
    uint slot = atomicAdd(draw[0], 1u);
    atomicAdd(draw[4], 1u);
    atomicAdd(draw[8], count);
    draw[CHCRT_CULLING_GPU_DRAW_HEADER + slot] = cell;
}
