#version 450 core
// Twin test of shaders/shared/linespace_layout.h (tests/linespace/shaft_index_twin_test.cpp): evaluates the
// GLSL build of the shaft index (CALCPATCH/CALCSHAFT) and the sparse lookup (Algorithm 2) for one case per
// pixel; the test compares with the C++ build of the same text.
// Host defines: CHCRT_LS_TWIN_FAST (shafts from linespace/shaft_index_fast.glsl instead). Per case, 5 RGBA32F texels: origin, direction, boxMin, boxMax, and
// (n, bitset word, word offset, shaft) as uint bit patterns.
#include "shared/linespace_layout.h"
#include "linespace/shaft_index_fast.glsl"

layout(binding = 0) uniform samplerBuffer cases;
uniform int width;
uniform int caseCount;
layout(location = 0) out uvec4 outPatches; // entry face, entry patch, exit face, exit patch
layout(location = 1) out uvec4 outShafts;  // non-symmetric shaft, symmetric shaft, sparse slot, 0

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int index = pixel.y * width + pixel.x;
    if (index >= caseCount) {
        discard;
    }
    int base = index * 5;
    vec3 origin = texelFetch(cases, base + 0).xyz;
    vec3 direction = texelFetch(cases, base + 1).xyz;
    vec3 boxMin = texelFetch(cases, base + 2).xyz;
    vec3 boxMax = texelFetch(cases, base + 3).xyz;
    uvec4 extra = floatBitsToUint(texelFetch(cases, base + 4));
    uint n = extra.x;
    vec3 invDir = safeInverseDirection(direction);
    outPatches = lsEntryExitPatches(origin, direction, invDir, boxMin, boxMax, n);
#ifdef CHCRT_LS_TWIN_FAST
    // The traversal's variant (linespace/shaft_index_fast.glsl) must give the same shafts.
    outShafts = uvec4(lsShaftIndexFast(origin, direction, invDir, boxMin, boxMax, n, false),
                      lsShaftIndexFast(origin, direction, invDir, boxMin, boxMax, n, true),
#else
    outShafts = uvec4(lsShaftIndex(origin, direction, invDir, boxMin, boxMax, n, false),
                      lsShaftIndex(origin, direction, invDir, boxMin, boxMax, n, true),
#endif
                      lsSparseSlot(extra.y, extra.z, extra.w), 0u);
}
