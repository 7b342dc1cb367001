// Deterministic per-pixel randomness. CHC+RT §5.3: the pass's shared Halton sample (a uniform, computed on the
// CPU) is perturbed per pixel with these values, so the rays of a pass stay coherent.

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
