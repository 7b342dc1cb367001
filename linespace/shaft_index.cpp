#include "linespace/shaft_index.h"

#include <cassert>

namespace chcrt::ls {

ShaftPatches decodeShaft(uint32_t shaft, uint32_t n, bool symmetric) {
    const uint32_t nn = n * n;
    assert(shaft < lsShaftCount(n, symmetric));
    ShaftPatches s;
    if (symmetric) {
        s.endPatch = shaft % nn;
        s.startPatch = (shaft / nn) % nn;
        uint32_t facePair = shaft / (nn * nn);
        // facePair = f1 * (11 - f1) / 2 + (f2 - f1 - 1): find f1 by walking the 5, 4, 3, 2, 1 pairs per f1.
        uint32_t f1 = 0;
        while (facePair >= 5u - f1) {
            facePair -= 5u - f1;
            ++f1;
        }
        s.startFace = f1;
        s.endFace = f1 + 1u + facePair;
        return s;
    }
    s.endPatch = shaft % nn;
    const uint32_t relativeEnd = (shaft / nn) % 5u;
    s.startPatch = (shaft / (nn * 5u)) % nn;
    s.startFace = shaft / (nn * 5u * nn);
    s.endFace = relativeEnd < s.startFace ? relativeEnd : relativeEnd + 1u;
    return s;
}

uint32_t shaftIndexForRay(const Aabb& box, uint32_t n, bool symmetric, const glm::vec3& origin,
                          const glm::vec3& direction) {
    return gpu::lsShaftIndex(origin, direction, gpu::safeInverseDirection(direction), box.lower, box.upper, n,
                             symmetric);
}

} // namespace chcrt::ls
