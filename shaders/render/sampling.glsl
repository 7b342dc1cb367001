// Sampling helpers for ray generation.

const float kPi = 3.14159265358979f;

// Orthonormal basis around a unit normal, aligned with the world: the bitangent is the world up direction
// projected onto the surface (x for horizontal surfaces). CHC+RT §5.3 shoots the same tangent-space direction from
// every pixel; with a world-aligned frame that direction means the same thing on every wall (e.g. "up and to the
// side"), whichever way the wall faces. (A frame that is merely continuous, such as Duff et al.'s, flips "up" to
// "down" between walls facing +z and -z, so at low sample counts one street side got only ground-facing AO rays.)
void buildTangentFrame(vec3 n, out vec3 tangent, out vec3 bitangent) {
    vec3 reference = abs(n.y) < 0.999f ? vec3(0.0f, 1.0f, 0.0f) : vec3(1.0f, 0.0f, 0.0f);
    tangent = normalize(cross(reference, n));
    bitangent = cross(n, tangent);
}

// Cosine-weighted hemisphere direction (z up) for u in [0,1)^2, rotated about z by `rotation` radians.
// CHC+RT §5.3 (after Mittring's SSAO): a per-pixel rotation in tangent space decorrelates pixels while
// keeping the pass's rays nearly parallel when the maximum angle is small.
vec3 cosineHemisphere(vec2 u, float rotation) {
    float r = sqrt(u.x);
    float phi = 2.0f * kPi * u.y + rotation;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0f, 1.0f - u.x)));
}
