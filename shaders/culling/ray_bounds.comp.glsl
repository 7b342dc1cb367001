#version 450 core
// Ray bounds grid (culling/ray_bounds_grid.h): one invocation per screen cell of CHCRT_BOUNDS_CELL² pixels reduces
// its active rays to boxes: the box of the ray origins, and the boxes of the points p_j = o + d·s_j, j = 0..P, that
// split each ray's segment [t0, t1] into P equal pieces (the CPU makes piece k's box from the boxes of p_k and
// p_{k+1}); or it marks the cell empty or unbounded. t0 = tmin and t1 = tmax, clipped to the scene's box (nothing
// outside it can be hit); with CHCRT_BOUNDS_WITH_HITS the segments end at the hits found so far: closest-hit rays
// at their hit t (only nearer hits can still change the result), any-hit rays that hit are finished and left out.
// With them, the cell's ray interval (smallest and largest direction components, segment range) for the frustum test
// (rayIntervalMayHit in shared/culling_layout.h). One invocation per cell, looping over its pixels: a reduction in
// shared memory with barriers (one invocation per pixel) measured 40x slower on llvmpipe, whose work groups switch
// coroutines at every barrier.
// With CHCRT_BOUNDS_LIGHT_SWEEP the cells hold every shadow ray set of a frame at once (TraceRequest::lightSweep): the
// rays of any set run from the same surface points (each set's inactive rays keep theirs, shared/render_layout.h) to
// points of the light's box L, so the cell's boxes are those of the segments from its origin box O to L — point j of
// the pieces is the box (1 - s_j)·O + s_j·L, s_j = j/P — and its ray interval the directions of L - O normalised,
// segments [0, the largest distance from O to L].
// Host defines: CHCRT_BOUNDS_WITH_HITS (0 | 1), TRACE_ANY_HIT (0 | 1), CHCRT_BOUNDS_CELL (1..32, a power of two),
// CHCRT_BOUNDS_PIECES (1 .. CHCRT_CULLING_BOUNDS_MAX_PIECES), CHCRT_BOUNDS_CELL_MARKS (0 | 1: only the cells the hint
// pass marked, an invocation per listed cell from an indirect dispatch; the host cleared the others to empty),
// CHCRT_BOUNDS_LIGHT_SWEEP (0 | 1; not with hits or marks).
// Over the marked cells alone, because an 8-wide SIMD group loops over all its cells' pixels when one of them has a
// ray left: after city shadow rays' hint passes ~12 % of the cells are marked, and the whole-grid reduction took
// 0.55 ms per ray set on llvmpipe.
#include "shared/render_layout.h"
#include "shared/bvh_layout.h"
#include "shared/intersect.h"
#include "shared/culling_layout.h"

#define POINTS (CHCRT_BOUNDS_PIECES + 2) // the origins, then p_0 .. p_P

#if CHCRT_BOUNDS_CELL_MARKS
layout(local_size_x = CHCRT_CULLING_MARKED_GROUP) in;
#else
layout(local_size_x = 8, local_size_y = 8) in;
#endif

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
#if CHCRT_BOUNDS_WITH_HITS
layout(binding = CHCRT_CULLING_IMAGE_HIT, rgba32ui) uniform readonly uimage2D hitImage;
#endif
layout(std430, binding = CHCRT_CULLING_BOUNDS_BUFFER) writeonly buffer CellBounds {
    vec4 cellBounds[];
};
#if CHCRT_BOUNDS_CELL_MARKS
// The hint pass's marks (culling/hint_pass.h): an unmarked cell has no ray left to trace, so it is empty.
layout(std430, binding = CHCRT_CULLING_COMPACT_CELLS) readonly buffer CellMarks {
    uint cellMarks[]; // CHCRT_CULLING_COMPACT_CELLS layout: marks, dispatch command and count, marked cells
};
#endif

uniform ivec2 raySize; // the ray set's size in pixels
uniform vec3 sceneMin;
uniform vec3 sceneMax;
#if CHCRT_BOUNDS_LIGHT_SWEEP
uniform vec3 lightMin; // the light's box, padded by the host for the rounding of the points sampled on it
uniform vec3 lightMax;
#endif

float maxComponent(vec3 v) {
    return max(max(v.x, v.y), v.z);
}

void main() {
    ivec2 cellCount = (raySize + CHCRT_BOUNDS_CELL - 1) / CHCRT_BOUNDS_CELL;
#if CHCRT_BOUNDS_CELL_MARKS
    int cells = cellCount.x * cellCount.y;
    uint listed = gl_GlobalInvocationID.x;
    if (listed >= cellMarks[CHCRT_CULLING_MARKED_HEADER(cells) + 3]) {
        return;
    }
    int index = int(cellMarks[CHCRT_CULLING_MARKED_LIST(cells) + int(listed)]);
    ivec2 cell = ivec2(index % cellCount.x, index / cellCount.x);
#else
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    if (cell.x >= cellCount.x || cell.y >= cellCount.y) {
        return;
    }
#endif
    const float big = 3.0e38f;
    vec3 lower[POINTS];
    vec3 upper[POINTS];
    for (int j = 0; j < POINTS; ++j) {
        lower[j] = vec3(big);
        upper[j] = vec3(-big);
    }
    float state = CHCRT_CULLING_CELL_EMPTY;
    float extent = 0.0f;
    float directionLength = 0.0f;
    // The cell's ray interval: directions and segment range.
    vec3 directionLower = vec3(big);
    vec3 directionUpper = vec3(-big);
    float segmentStart = big;
    float segmentEnd = -big;
    ivec2 first = cell * CHCRT_BOUNDS_CELL;
    ivec2 end = min(first + CHCRT_BOUNDS_CELL, raySize);
    // At most 32² iterations, far below llvmpipe's 65,535-iteration loop cap.
    for (int y = first.y; y < end.y; ++y) {
        for (int x = first.x; x < end.x; ++x) {
            ivec2 pixel = ivec2(x, y);
            vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
            vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
#if CHCRT_BOUNDS_LIGHT_SWEEP
            // Every surface point: active rays and inactive ones that kept their origin (an all-zero direction).
            if (!(directionTmax.w > originTmin.w) && directionTmax != vec4(0.0f)) {
                continue; // no surface point (or a NaN bound: inactive in every tracer)
            }
            if (any(isnan(originTmin)) || any(isinf(originTmin)) || any(isnan(directionTmax)) ||
                any(isinf(directionTmax))) {
                state = CHCRT_CULLING_CELL_UNBOUNDED;
                continue;
            }
            lower[0] = min(lower[0], originTmin.xyz);
            upper[0] = max(upper[0], originTmin.xyz);
            state = max(state, CHCRT_CULLING_CELL_BOUNDED);
            continue;
#endif
            if (!(directionTmax.w > originTmin.w)) {
                continue; // inactive
            }
            // isnan/isinf rather than comparisons: GLSL leaves comparisons with NaN to the implementation.
            if (any(isnan(originTmin)) || any(isinf(originTmin)) || any(isnan(directionTmax)) ||
                any(isinf(directionTmax))) {
                state = CHCRT_CULLING_CELL_UNBOUNDED;
                continue;
            }
            float t1 = directionTmax.w;
#if CHCRT_BOUNDS_WITH_HITS
            uvec4 stored = imageLoad(hitImage, pixel);
            if (stored.y != CHCRT_NO_HIT_ID) {
#if TRACE_ANY_HIT
                continue; // finished
#else
                t1 = min(t1, uintBitsToFloat(stored.x));
#endif
            }
#endif
            vec3 o = originTmin.xyz;
            vec3 d = directionTmax.xyz;
            vec2 sceneEntryExit = intersectRayAabb(o, safeInverseDirection(d), sceneMin, sceneMax);
            float t0 = max(originTmin.w, sceneEntryExit.x);
            t1 = min(t1, sceneEntryExit.y);
            if (!(t0 <= t1)) {
                continue; // the segment misses the scene: no hit possible
            }
            extent = max(extent, maxComponent(abs(o)) + maxComponent(abs(d)) * max(abs(t0), abs(t1)));
            directionLength = max(directionLength, length(d));
            directionLower = min(directionLower, d);
            directionUpper = max(directionUpper, d);
            segmentStart = min(segmentStart, t0);
            segmentEnd = max(segmentEnd, t1);
            lower[0] = min(lower[0], o);
            upper[0] = max(upper[0], o);
            for (int j = 0; j <= CHCRT_BOUNDS_PIECES; ++j) {
                float s = j == 0 ? t0 : (j == CHCRT_BOUNDS_PIECES ? t1 : t0 + (t1 - t0) * (float(j) / float(CHCRT_BOUNDS_PIECES)));
                vec3 p = o + d * s;
                lower[j + 1] = min(lower[j + 1], p);
                upper[j + 1] = max(upper[j + 1], p);
            }
            state = max(state, CHCRT_CULLING_CELL_BOUNDED);
        }
    }
#if CHCRT_BOUNDS_LIGHT_SWEEP
    if (state == CHCRT_CULLING_CELL_BOUNDED) {
        vec3 originLower = lower[0], originUpper = upper[0];
        for (int j = 0; j <= CHCRT_BOUNDS_PIECES; ++j) {
            float s = float(j) / float(CHCRT_BOUNDS_PIECES); // both weights >= 0: the box's corners map to corners
            lower[j + 1] = (1.0f - s) * originLower + s * lightMin;
            upper[j + 1] = (1.0f - s) * originUpper + s * lightMax;
        }
        // Directions: v / |v| for v in the box V = L - O; |v| lies between V's distance from 0 and its farthest
        // corner, and each component's bound divides by the end of that range that makes it widest.
        vec3 vLower = lightMin - originUpper, vUpper = lightMax - originLower;
        float nearest = length(max(max(vLower, -vUpper), vec3(0.0f)));
        float farthest = length(max(abs(vLower), abs(vUpper)));
        directionLength = 1.0f;
        segmentStart = 0.0f;
        segmentEnd = farthest;
        extent = maxComponent(max(abs(originLower), abs(originUpper))) + farthest;
        if (nearest > 0.0f) {
            // Widened for the rounding of these divisions and of the ray generator's (a few ulps each).
            const float rounding = 1.0e-5f;
            directionLower = mix(vLower / nearest, vLower / farthest, greaterThanEqual(vLower, vec3(0.0f))) - rounding;
            directionUpper = mix(vUpper / farthest, vUpper / nearest, greaterThanEqual(vUpper, vec3(0.0f))) + rounding;
            directionLower = max(directionLower, vec3(-1.0f - rounding));
            directionUpper = min(directionUpper, vec3(1.0f + rounding));
        } else { // the light's box reaches the origins: any direction
            directionLower = vec3(-1.0f - 1.0e-5f);
            directionUpper = vec3(1.0f + 1.0e-5f);
        }
    }
#endif
    int base = (cell.y * cellCount.x + cell.x) * CHCRT_CULLING_BOUNDS_STRIDE(CHCRT_BOUNDS_PIECES);
    cellBounds[base] = vec4(state, extent, directionLength, 0.0f);
    for (int j = 0; j < POINTS; ++j) {
        cellBounds[base + 1 + 2 * j] = vec4(lower[j], 0.0f);
        cellBounds[base + 2 + 2 * j] = vec4(upper[j], 0.0f);
    }
    cellBounds[base + 1 + 2 * POINTS] = vec4(directionLower, segmentStart);
    cellBounds[base + 2 + 2 * POINTS] = vec4(directionUpper, segmentEnd);
}
