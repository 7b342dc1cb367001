#pragma once
// A small, portable random number generator for the procedural scenes: PCG32 (O'Neill 2014, XSH-RR
// output) seeded through splitmix64. std:: distributions are deliberately not used: their output differs
// between standard libraries, and a scene must be identical for a seed on every platform.
#include <cstdint>

namespace chcrt::procedural {

inline uint64_t splitmix64(uint64_t& state) {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

class Rng {
public:
    // `stream` separates independent sequences drawn from one seed (layout, details, paths, ...), so that
    // changing how many numbers one part draws does not shift the others.
    Rng(uint64_t seed, uint64_t stream) {
        uint64_t mix = seed * 0x2545F4914F6CDD1Dull + stream;
        state_ = splitmix64(mix);
        increment_ = splitmix64(mix) | 1u;
        next();
    }

    uint32_t next() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ull + increment_;
        const uint32_t xorShifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = uint32_t(old >> 59u);
        return (xorShifted >> rot) | (xorShifted << ((32u - rot) & 31u));
    }
    // Uniform in [0, 1) with 24 bits, exactly representable as float.
    float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    // Uniform integer in [0, n) for n > 0 (multiply-shift; the bias is below 2^-32 * n, irrelevant here).
    uint32_t below(uint32_t n) { return uint32_t((uint64_t(next()) * n) >> 32); }
    int range(int lo, int hi) { return lo + int(below(uint32_t(hi - lo + 1))); } // inclusive
    bool chance(float p) { return uniform() < p; }

private:
    uint64_t state_ = 0;
    uint64_t increment_ = 1;
};

} // namespace chcrt::procedural
