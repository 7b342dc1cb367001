#pragma once
// Shaft volumes and exact overlap tests for building Line Spaces conservatively.
//
// A shaft's volume is the convex hull of its two patches (Keul et al. 2016/2017: "the convex set of all line
// segments connecting any point in the start patch with any point in the end patch"). Both patches are
// axis-aligned rectangles, i.e. boxes of zero thickness, and the convex hull of two convex sets A and B is the
// union over s in [0, 1] of the Minkowski combinations (1 - s) A + s B. For boxes that combination is again a
// box whose bounds move linearly in s. A separating-axis test of a triangle (13 axes, Akenine-Moeller 2001) or
// of a box (3 axes) against that moving box gives, per axis, an interval of s in which the axis does not
// separate; the shaft and the primitive overlap iff the intersection of those intervals with [0, 1] is not
// empty. The test is therefore exact (in double precision on float inputs), not sampled.
//
// Patches may be dilated by `dilation` in all three axes so that rays whose entry or exit point is rounded
// into a neighbouring patch (or face, at edges) by the float shaft-index arithmetic still lie in the shaft
// volume they are classified into: the dilated test is conservative for the float classification.
#include "renderer/core/aabb.h"

#include <glm/glm.hpp>

#include <cstdint>

namespace chcrt::ls {

// Axis-aligned box in double precision (a patch, a block of patches, a node).
struct BoxD {
    glm::dvec3 lower{0.0};
    glm::dvec3 upper{0.0};
};

// A rectangle of patches [u0, u1) x [v0, v1) (patch coordinates) on one face of a box.
struct PatchRect {
    uint32_t face = 0;
    uint32_t u0 = 0, u1 = 1, v0 = 0, v1 = 1;
    uint32_t count() const { return (u1 - u0) * (v1 - v0); }
};

// The region of a patch rectangle on the box's face, grown by `dilation` on every side (all three axes).
BoxD patchRegion(const Aabb& box, uint32_t n, const PatchRect& rect, double dilation);

// Centroid of patch (pu, pv) of face `face` (float, as the shaft centroid ray starts there).
glm::vec3 patchCentroid(const Aabb& box, uint32_t n, uint32_t face, uint32_t pu, uint32_t pv);

// The convex hull of two boxes, as the linear family Box(s) = (1 - s) a + s b, s in [0, 1].
struct ShaftVolume {
    glm::dvec3 centerA, halfA; // Box(0)
    glm::dvec3 centerB, halfB; // Box(1)
    ShaftVolume(const BoxD& a, const BoxD& b);
};

// Does the triangle (closed) intersect the shaft volume (closed)? Exact SAT over s.
bool shaftOverlapsTriangle(const ShaftVolume& shaft, const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2);

// Does the box intersect the shaft volume? Exact.
bool shaftOverlapsBox(const ShaftVolume& shaft, const glm::dvec3& lower, const glm::dvec3& upper);

// The dilation used by the builders for a scene: 2^-16 (about 128 float ulps) of the magnitude of the scene's
// coordinates (largest absolute coordinate of the root box plus its diagonal). Entry and exit points of rays
// whose origins lie within a few scene sizes are computed with an error far below that.
double shaftDilationForScene(const Aabb& sceneBounds);

} // namespace chcrt::ls
