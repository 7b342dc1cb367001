#version 450 core
// Twin test of shaders/shared/intersect.h (tests/gl/intersect_twin_test.cpp): evaluates the GLSL build of
// intersectRayAabb and intersectRayTriangle for one input case per pixel; the test compares with the C++ build.
// Host defines: TWIN_TEXELS_PER_CASE (texels of one case in the input buffer, layout below).
#include "shared/intersect.h"

// Per case: origin, direction, invDir, boxMin, boxMax, v0, v1, v2 (xyz of one RGBA32F texel each).
layout(binding = 0) uniform samplerBuffer cases;
uniform int width;
uniform int caseCount;
layout(location = 0) out vec4 outBox;      // tEntry, tExit, rayHitsAabb(0, +inf), 0
layout(location = 1) out vec4 outTriangle; // t, u, v, 0

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int index = pixel.y * width + pixel.x;
    if (index >= caseCount) {
        discard;
    }
    int base = index * TWIN_TEXELS_PER_CASE;
    vec3 origin = texelFetch(cases, base + 0).xyz;
    vec3 direction = texelFetch(cases, base + 1).xyz;
    vec3 invDir = texelFetch(cases, base + 2).xyz;
    vec3 boxMin = texelFetch(cases, base + 3).xyz;
    vec3 boxMax = texelFetch(cases, base + 4).xyz;
    vec3 v0 = texelFetch(cases, base + 5).xyz;
    vec3 v1 = texelFetch(cases, base + 6).xyz;
    vec3 v2 = texelFetch(cases, base + 7).xyz;
    vec2 entryExit = intersectRayAabb(origin, invDir, boxMin, boxMax);
    outBox = vec4(entryExit, rayHitsAabb(entryExit, 0.0f, 3.402823466e+38f) ? 1.0f : 0.0f, 0.0f);
    outTriangle = vec4(intersectRayTriangle(origin, direction, v0, v1, v2), 0.0f);
}
