#pragma once
// The ray bounds grid of a pinhole camera's primary rays, from the camera alone (ours; culling/README.md "The ray
// bounds grid"). Primary rays without hits are a function of the camera: the ray of a pixel starts at the eye and
// points through the pixel's centre (PrimaryRayBasis, renderer/render/camera_math.h). So their cells' boxes — what
// the GPU reduction (shaders/culling/ray_bounds.comp.glsl) would compute from the ray textures — can be bounded on the
// CPU by interval arithmetic over each cell's pixel centres, in microseconds, with no reduction pass and no blocking
// read-back (on llvmpipe those took 0.8 ms of a 7.6 ms city primary trace at 256²).
//
// Conservative: every box holds the reduction's box for the same cell. A cell's directions are bounded from the
// corners of its pixel-centre rectangle (the unnormalised direction is affine in the pixel, its length is convex),
// widened for the shader's float rounding; the segment ends from slab intervals against the scene's box; a piece end
// point o + d·s from the intervals of d and s, clipped to the scene's box (every point of a segment that can hit
// lies inside it). The grid's padding (RayBoundsOptions::relativePad) is added on top, as for reduced cells. A cell
// whose bounds are not finite is unbounded (culls nothing).
#include "renderer/render/camera_math.h"

#include <glm/glm.hpp>

#include <vector>

namespace chcrt {

// The cells of a basis.width × basis.height ray set in cellSize² blocks, in the reduction's buffer layout
// (CHCRT_CULLING_BOUNDS_* in shaders/shared/culling_layout.h, `pieces` pieces), for RayBoundsGrid::setCells.
std::vector<glm::vec4> cameraRayBounds(const PrimaryRayBasis& basis, int cellSize, int pieces, glm::vec3 sceneMin,
                                       glm::vec3 sceneMax);

} // namespace chcrt
