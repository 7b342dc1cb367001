// Line Space lookups from texture buffers (the GLSL side of linespace/linespace_build.h's pools;
// texture buffers, not SSBOs: ~10x faster on llvmpipe). Include after shared/linespace_layout.h.
//   node records  RGBA32F, CHCRT_LS_TEXELS_PER_NODE texels per Line Space (LineSpaceNodeGpu)
//   binary words  R32UI, lsShaftCount(n, true) / 32 words per Line Space (symmetric layout)
//   candidates    R32UI words and offsets (lsShaftCount(n, false) / 32 per Line Space) and R32UI data: the
//                 index of the candidate triangle in the BVH triangle buffer (Algorithm 2)
// Line Space `space` owns binary words [wordBase, ...) (wordBase = space * Wsym, in its node record) and candidate
// words/offsets [space * Wnon, ...).
#include "shared/linespace_layout.h"

// Is the ray's shaft in Line Space `space` non-empty? Misses of the box count as empty.
bool lsBinaryFilledForRay(samplerBuffer nodes, usamplerBuffer binaryWords, uint space, uint n, vec3 origin,
                          vec3 direction, vec3 invDir) {
    vec4 t0 = texelFetch(nodes, int(space) * CHCRT_LS_TEXELS_PER_NODE);
    vec4 t1 = texelFetch(nodes, int(space) * CHCRT_LS_TEXELS_PER_NODE + 1);
    uint shaft = lsShaftIndex(origin, direction, invDir, t0.xyz, t1.xyz, n, true);
    if (shaft == CHCRT_LS_NO_SHAFT) {
        return false;
    }
    uint word = texelFetch(binaryWords, int(floatBitsToUint(t1.w) + shaft / 32u)).x;
    return ((word >> (shaft & 31u)) & 1u) != 0u;
}

// The candidate triangle (BVH triangle buffer index) of the ray's shaft in Line Space `space`, or
// CHCRT_LS_EMPTY_SLOT when the shaft is empty or the line misses the box.
uint lsCandidateForRay(samplerBuffer nodes, usamplerBuffer candidateWords, usamplerBuffer candidateOffsets,
                       usamplerBuffer candidateData, uint space, uint n, vec3 origin, vec3 direction, vec3 invDir) {
    vec4 t0 = texelFetch(nodes, int(space) * CHCRT_LS_TEXELS_PER_NODE);
    vec4 t1 = texelFetch(nodes, int(space) * CHCRT_LS_TEXELS_PER_NODE + 1);
    uint shaft = lsShaftIndex(origin, direction, invDir, t0.xyz, t1.xyz, n, false);
    if (shaft == CHCRT_LS_NO_SHAFT) {
        return CHCRT_LS_EMPTY_SLOT;
    }
    int w = int(space * ((lsShaftCount(n, false) + 31u) / 32u) + shaft / 32u);
    uint slot = lsSparseSlot(texelFetch(candidateWords, w).x, texelFetch(candidateOffsets, w).x, shaft);
    return slot == CHCRT_LS_EMPTY_SLOT ? CHCRT_LS_EMPTY_SLOT : texelFetch(candidateData, int(slot)).x;
}
