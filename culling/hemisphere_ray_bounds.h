#pragma once
// The ray bounds grid of hemisphere rays (AO) from their surface frames (ours; culling/README.md "AO cells from the
// surface"). Every AO ray set of a G-buffer starts at the same surface points, and a ray of a set runs `length`
// along normalize(l.x T + l.y B + l.z n): n the pixel's shading normal, T and B the tangent frame the ray generator
// builds from it, l the set's cosine-weighted sample rotated per pixel by at most `maxRotation`
// (shaders/render/raygen.frag.glsl, render/sampling.glsl; TraceRequest::HemisphereRays). So one reduction per
// G-buffer of each cell's origins, normals and tangent frames (shaders/culling/surface_frames.comp.glsl) bounds the
// cells of all its sets: per set, the directions' box follows by interval arithmetic from the frames' boxes and the
// sample, and the pieces' end points from the origins' box and those directions — on the CPU, in microseconds,
// instead of a reduction and a blocking read-back per set (on llvmpipe 1.6 ms of a 14 ms city AO trace at 256²).
//
// Conservative: each bound holds every ray of the cell in every set. The frames' boxes are the reduction's (the same
// frame code as the ray generator, so the same floats); the arc of sample directions is bounded with the cosine and
// sine over the whole rotation range, widened for the shaders' sin, cos and normalize; a cell whose normals are not
// of unit length within 10^-3 is unbounded (the normalisation then moves directions too far to bound cheaply). The
// grid's padding (RayBoundsOptions::relativePad) is added on top, as for reduced cells.
#include <glm/glm.hpp>

#include <vector>

namespace chcrt {

// The surface frames of one G-buffer (RayBoundsGrid::reduceSurfaceFrames): for ray sets of width × height, cells in
// the CHCRT_CULLING_FRAMES_STRIDE layout surface_frames.comp.glsl writes. Empty: none reduced.
struct SurfaceFrames {
    std::vector<glm::vec4> values;
    int width = 0, height = 0;
};

// What one AO ray set adds to the frames it shares with the G-buffer's other sets (TraceRequest::HemisphereRays).
struct HemisphereSample {
    glm::vec2 sample{0.0f}; // the set's Halton point (cosineHemisphere's u)
    float maxRotation = 0.0f; // radians: the per-pixel rotation lies in [0, maxRotation]
    float length = 0.0f;      // every active ray's segment is [0, length]
};

// The cells of a set, in the reduction's buffer layout (CHCRT_CULLING_BOUNDS_* in shaders/shared/culling_layout.h,
// `pieces` pieces) for RayBoundsGrid::setCells, from `frames` (cellsX × cellsY cells in the
// CHCRT_CULLING_FRAMES_STRIDE layout, as surface_frames.comp.glsl writes them). Piece end points are clipped to the
// scene's box (every point of a segment that can hit lies inside it).
std::vector<glm::vec4> hemisphereRayBounds(const std::vector<glm::vec4>& frames, int cellsX, int cellsY, int pieces,
                                           const HemisphereSample& set, glm::vec3 sceneMin, glm::vec3 sceneMax);

} // namespace chcrt
