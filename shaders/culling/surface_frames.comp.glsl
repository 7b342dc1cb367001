#version 450 core
// Surface frames of hemisphere rays (culling/hemisphere_ray_bounds.h): one invocation per screen cell of
// CHCRT_BOUNDS_CELL² pixels reduces, over its pixels with a surface point, the boxes of the ray origins, of the
// G-buffer's shading normals and of the tangent frames the ray generator builds from them, per class of normals
// (CHCRT_CULLING_FRAMES_STRIDE layout, shared/culling_layout.h) — what every AO ray set of the G-buffer shares
// (TraceRequest::HemisphereRays). The CPU bounds each set's cells from these boxes and the set's sample, so the sets
// need no reduction of their own. One invocation per cell looping over its pixels, as in ray_bounds.comp.glsl (and
// for its reason: barriers are slow on llvmpipe). Runs once per G-buffer.
// Host defines: CHCRT_BOUNDS_CELL (1..32, a power of two).
#include "shared/render_layout.h"
#include "shared/culling_layout.h"
#include "render/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_UNIT_GBUFFER_NORMAL) uniform sampler2D shadingNormals;
layout(std430, binding = CHCRT_CULLING_BOUNDS_BUFFER) writeonly buffer CellFrames {
    vec4 cellFrames[];
};

uniform ivec2 raySize; // the ray set's size in pixels

#define BOXES (CHCRT_CULLING_FRAME_BOXES * CHCRT_CULLING_FRAME_CLASSES)

// The class of a normal: 2 · (axis of its largest component) + (1 if that component is negative).
int normalClass(vec3 n) {
    vec3 a = abs(n);
    int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    return 2 * axis + (n[axis] < 0.0f ? 1 : 0);
}

void main() {
    ivec2 cellCount = (raySize + CHCRT_BOUNDS_CELL - 1) / CHCRT_BOUNDS_CELL;
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    if (cell.x >= cellCount.x || cell.y >= cellCount.y) {
        return;
    }
    const float big = 3.0e38f;
    vec3 lower[BOXES];
    vec3 upper[BOXES];
    for (int j = 0; j < BOXES; ++j) {
        lower[j] = vec3(big);
        upper[j] = vec3(-big);
    }
    float state = CHCRT_CULLING_CELL_EMPTY;
    float shortestNormal = big;
    float longestNormal = 0.0f;
    ivec2 first = cell * CHCRT_BOUNDS_CELL;
    ivec2 end = min(first + CHCRT_BOUNDS_CELL, raySize);
    // At most 32² iterations, far below llvmpipe's 65,535-iteration loop cap.
    for (int y = first.y; y < end.y; ++y) {
        for (int x = first.x; x < end.x; ++x) {
            ivec2 pixel = ivec2(x, y);
            vec4 originTmin = texelFetch(rayOrigins, pixel, 0);
            vec4 directionTmax = texelFetch(rayDirections, pixel, 0);
            // A surface point: an active ray, or an inactive one that kept its origin (an all-zero direction).
            if (!(directionTmax.w > originTmin.w) && directionTmax != vec4(0.0f)) {
                continue;
            }
            vec3 n = texelFetch(shadingNormals, pixel, 0).xyz;
            vec3 tangent, bitangent;
            buildTangentFrame(n, tangent, bitangent);
            // isnan/isinf rather than comparisons: GLSL leaves comparisons with NaN to the implementation.
            if (any(isnan(originTmin)) || any(isinf(originTmin)) || any(isnan(directionTmax)) ||
                any(isinf(directionTmax)) || any(isnan(n)) || any(isinf(n)) || any(isnan(tangent)) ||
                any(isnan(bitangent))) {
                state = CHCRT_CULLING_CELL_UNBOUNDED;
                continue;
            }
            int base = CHCRT_CULLING_FRAME_BOXES * normalClass(n);
            lower[base] = min(lower[base], originTmin.xyz);
            upper[base] = max(upper[base], originTmin.xyz);
            lower[base + 1] = min(lower[base + 1], n);
            upper[base + 1] = max(upper[base + 1], n);
            lower[base + 2] = min(lower[base + 2], tangent);
            upper[base + 2] = max(upper[base + 2], tangent);
            lower[base + 3] = min(lower[base + 3], bitangent);
            upper[base + 3] = max(upper[base + 3], bitangent);
            float normalLength = length(n);
            shortestNormal = min(shortestNormal, normalLength);
            longestNormal = max(longestNormal, normalLength);
            state = max(state, CHCRT_CULLING_CELL_BOUNDED);
        }
    }
    int out0 = (cell.y * cellCount.x + cell.x) * CHCRT_CULLING_FRAMES_STRIDE;
    cellFrames[out0] = vec4(state, shortestNormal, longestNormal, 0.0f);
    for (int j = 0; j < BOXES; ++j) {
        // w of a class's origin box: whether the class has a point.
        float used = j % CHCRT_CULLING_FRAME_BOXES == 0 && lower[j].x <= upper[j].x ? 1.0f : 0.0f;
        cellFrames[out0 + 1 + 2 * j] = vec4(lower[j], used);
        cellFrames[out0 + 2 + 2 * j] = vec4(upper[j], 0.0f);
    }
}
