// Deterministic per-pixel randomness and the Halton sequence used for stratified ray generation.
// CHC+RT §5.3: the same Halton sample is used by every pixel in a pass and perturbed per pixel, so rays of a
// pass stay coherent.

// PCG hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering"): good quality for one 32-bit input.
uint pcgHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform float in [0, 1) from a hash (24 mantissa bits).
float hashToUnit(uint h) {
    return float(h >> 8u) * (1.0f / 16777216.0f);
}

// Two independent uniforms for a pixel and seed.
vec2 pixelRandom2(uvec2 pixel, uint seed) {
    uint h0 = pcgHash(pixel.x + pcgHash(pixel.y + pcgHash(seed)));
    uint h1 = pcgHash(h0 ^ 0x9E3779B9u);
    return vec2(hashToUnit(h0), hashToUnit(h1));
}

// Radical inverse in base 2 (van der Corput) and base 3: the 2D Halton point of `index`.
float radicalInverseBase2(uint index) {
    return float(bitfieldReverse(index) >> 8u) * (1.0f / 16777216.0f);
}
float radicalInverseBase3(uint index) {
    float inverseBase = 1.0f / 3.0f;
    float factor = inverseBase;
    float result = 0.0f;
    // At most 21 digits for a 32-bit index.
    for (int digit = 0; digit < 21 && index > 0u; ++digit) {
        result += float(index % 3u) * factor;
        index /= 3u;
        factor *= inverseBase;
    }
    return result;
}
vec2 halton2D(uint index) {
    return vec2(radicalInverseBase2(index), radicalInverseBase3(index));
}
