// Sampling helpers for ray generation.

const float kPi = 3.14159265358979f;

// Orthonormal basis around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis, Revisited"):
// continuous except at n.z = -1 handled by the sign, so neighbouring pixels get neighbouring frames and the
// shared Halton direction stays coherent in world space.
void buildTangentFrame(vec3 n, out vec3 tangent, out vec3 bitangent) {
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z);
    float b = n.x * n.y * a;
    tangent = vec3(1.0f + s * n.x * n.x * a, s * b, -s * n.x);
    bitangent = vec3(b, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted hemisphere direction (z up) for u in [0,1)^2, rotated about z by `rotation` radians.
// CHC+RT §5.3 (after Mittring's SSAO): a per-pixel rotation in tangent space decorrelates pixels while
// keeping the pass's rays nearly parallel when the maximum angle is small.
vec3 cosineHemisphere(vec2 u, float rotation) {
    float r = sqrt(u.x);
    float phi = 2.0f * kPi * u.y + rotation;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0f, 1.0f - u.x)));
}
