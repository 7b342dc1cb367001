#pragma once
// C++ side of the shaft index (the arithmetic itself is shared with GLSL in shaders/shared/linespace_layout.h):
// decoding an index back into its patches, and ray classification against an Aabb.
#include "renderer/core/aabb.h"
#include "shaders/shared/linespace_layout.h"

#include <cstdint>

namespace chcrt::ls {

using gpu::lsShaftCount;
using gpu::lsShaftIndexFromPatches;

struct ShaftPatches {
    uint32_t startFace = 0, startPatch = 0, endFace = 0, endPatch = 0;
};

// Inverse of lsShaftIndexFromPatches. For the symmetric layout the start is the lower face.
ShaftPatches decodeShaft(uint32_t shaft, uint32_t n, bool symmetric);

// lsShaftIndex for a ray against `box` (CHCRT_LS_NO_SHAFT when the line misses it).
uint32_t shaftIndexForRay(const Aabb& box, uint32_t n, bool symmetric, const glm::vec3& origin,
                          const glm::vec3& direction);

// Number of 32-bit bitset words of one Line Space.
inline uint32_t lsWordCount(uint32_t n, bool symmetric) { return (lsShaftCount(n, symmetric) + 31u) / 32u; }

} // namespace chcrt::ls
