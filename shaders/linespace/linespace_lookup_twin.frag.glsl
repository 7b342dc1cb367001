#version 450 core
// Twin test of shaders/linespace/linespace_lookup.glsl (tests/linespace/linespace_lookup_twin_test.cpp): one
// ray per pixel against Line Space `space` of a built set; the test compares with the C++ pools' lookups.
// Host defines: LS_N (patches per face edge). Per case, 2 RGBA32F texels: origin + space bits, direction.
#include "shared/linespace_layout.h"
#include "linespace/linespace_lookup.glsl"

layout(binding = 0) uniform samplerBuffer cases;
layout(binding = 1) uniform samplerBuffer lsNodes;
layout(binding = 2) uniform usamplerBuffer lsBinaryWords;
layout(binding = 3) uniform usamplerBuffer lsCandidateWords;
layout(binding = 4) uniform usamplerBuffer lsCandidateOffsets;
layout(binding = 5) uniform usamplerBuffer lsCandidateData;
uniform int width;
uniform int caseCount;
layout(location = 0) out uvec4 outLookup; // binary filled (0/1), candidate, 0, 0

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int index = pixel.y * width + pixel.x;
    if (index >= caseCount) {
        discard;
    }
    vec4 a = texelFetch(cases, index * 2);
    vec3 direction = texelFetch(cases, index * 2 + 1).xyz;
    uint space = floatBitsToUint(a.w);
    vec3 invDir = safeInverseDirection(direction);
    bool filled = lsBinaryFilledForRay(lsNodes, lsBinaryWords, space, uint(LS_N), a.xyz, direction, invDir);
    uint candidate = lsCandidateForRay(lsNodes, lsCandidateWords, lsCandidateOffsets, lsCandidateData, space,
                                       uint(LS_N), a.xyz, direction, invDir);
    outLookup = uvec4(filled ? 1u : 0u, candidate, 0u, 0u);
}
