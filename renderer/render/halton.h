#pragma once
// The 2D Halton sequence (bases 2 and 3). CHC+RT §5.3: every pixel of a pass uses the same Halton sample,
// perturbed per pixel; the sample is therefore computed once per pass on the CPU and passed to the ray
// generation shader as a uniform.
#include <glm/glm.hpp>

#include <cstdint>

namespace chcrt {

inline double radicalInverse(uint32_t index, uint32_t base) {
    const double inverseBase = 1.0 / base;
    double factor = inverseBase;
    double result = 0.0;
    while (index > 0) {
        result += double(index % base) * factor;
        index /= base;
        factor *= inverseBase;
    }
    return result;
}

// Halton point `index` in [0, 1)^2 (index 0 is (0, 0)).
inline glm::vec2 halton2D(uint32_t index) {
    return glm::vec2(float(radicalInverse(index, 2)), float(radicalInverse(index, 3)));
}

} // namespace chcrt
