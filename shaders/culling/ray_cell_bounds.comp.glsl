#version 450 core
// Ray extent grid (culling/ray_extent_grid.h): one invocation per screen cell of CHCRT_CULLING_RAY_CELL²
// pixels writes the box around the segments [origin + tmin·d, origin + tmax·d] of the cell's active rays (a ray
// is active when tmax > tmin, as in every tracing pass), or marks the cell empty or unbounded.
#include "shared/render_layout.h"
#include "shared/culling_layout.h"

layout(local_size_x = 8, local_size_y = 8) in;

layout(binding = CHCRT_UNIT_RAY_ORIGIN) uniform sampler2D rayOrigins;
layout(binding = CHCRT_UNIT_RAY_DIRECTION) uniform sampler2D rayDirections;
layout(binding = CHCRT_CULLING_IMAGE_CELL_LOWER, rgba32f) writeonly uniform image2D cellLower;
layout(binding = CHCRT_CULLING_IMAGE_CELL_UPPER, rgba32f) writeonly uniform image2D cellUpper;

uniform ivec2 raySize; // the ray set's size in pixels
uniform ivec2 cellCount;

void main() {
    ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
    if (cell.x >= cellCount.x || cell.y >= cellCount.y) {
        return;
    }
    const float big = 3.0e38f;
    vec3 lower = vec3(big);
    vec3 upper = vec3(-big);
    float state = CHCRT_CULLING_CELL_EMPTY;
    ivec2 begin = cell * CHCRT_CULLING_RAY_CELL;
    ivec2 end = min(begin + CHCRT_CULLING_RAY_CELL, raySize);
    // At most CHCRT_CULLING_RAY_CELL² iterations, far below llvmpipe's loop cap (PLATFORM.md).
    for (int y = begin.y; y < end.y; ++y) {
        for (int x = begin.x; x < end.x; ++x) {
            vec4 originTmin = texelFetch(rayOrigins, ivec2(x, y), 0);
            vec4 directionTmax = texelFetch(rayDirections, ivec2(x, y), 0);
            if (!(directionTmax.w > originTmin.w)) {
                continue; // inactive
            }
            // isnan/isinf rather than comparisons: GLSL leaves comparisons with NaN to the implementation.
            bool finite = !any(isnan(originTmin)) && !any(isinf(originTmin)) && !any(isnan(directionTmax.xyz)) &&
                          !any(isinf(directionTmax.xyz));
            if (isnan(directionTmax.w) || !(directionTmax.w <= float(CHCRT_CULLING_RAY_UNBOUNDED_T)) || !finite) {
                state = CHCRT_CULLING_CELL_UNBOUNDED; // also NaN and infinite values: nothing is assumed
                continue;
            }
            vec3 a = originTmin.xyz + directionTmax.xyz * originTmin.w;
            vec3 b = originTmin.xyz + directionTmax.xyz * directionTmax.w;
            lower = min(lower, min(a, b));
            upper = max(upper, max(a, b));
            state = max(state, CHCRT_CULLING_CELL_BOUNDED);
        }
    }
    imageStore(cellLower, cell, vec4(lower, state));
    imageStore(cellUpper, cell, vec4(upper, 0.0f));
}
