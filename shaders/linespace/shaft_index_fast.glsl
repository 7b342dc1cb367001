// Shaft index for traversal: the same IEEE operations as lsEntryExitPatches/lsShaftIndex of
// shared/linespace_layout.h (so the same shaft, bit for bit: tests/linespace/shaft_index_twin_test.cpp runs both
// against C++), written without dynamic vector indexing and integer modulo. llvmpipe turns `p[axis]` with a
// varying axis into per-lane scalar code; here the patch coordinates of all three axes are computed as vectors
// and the two of the face are selected by swizzles. Measured: exact skipping on the 100k city at 256², primary
// rays, 2x slower than pure BVH with lsShaftIndex in the traversal loop (docs/benchmarks.md, Line Space section).
#include "shared/linespace_layout.h"

// Patch coordinates (0..n-1) of point p in all three axes of the box (lsPatchCoordinate per component).
uvec3 lsPatchCoordinates3(vec3 p, vec3 boxMin, vec3 boxMax, uint n) {
    vec3 extent = boxMax - boxMin;
    precise vec3 scaled = (p - boxMin) / extent * float(n);
    scaled = mix(vec3(0.0f), scaled, greaterThan(extent, vec3(0.0f)));
    return uvec3(clamp(floor(scaled), vec3(0.0f), vec3(float(n - 1u))));
}

// Patch (pv * n + pu) on a face of `axis`: u = (axis + 1) % 3, v = (axis + 2) % 3.
uint lsPatchOfAxis(uvec3 pc, int axis, uint n) {
    uvec2 uv = axis == 0 ? pc.yz : (axis == 1 ? pc.zx : pc.xy);
    return uv.y * n + uv.x;
}

uint lsShaftIndexFast(vec3 origin, vec3 direction, vec3 invDir, vec3 boxMin, vec3 boxMax, uint n, bool symmetric) {
    vec3 t0 = (boxMin - origin) * invDir;
    vec3 t1 = (boxMax - origin) * invDir;
    vec3 tNear = min(t0, t1);
    vec3 tFar = max(t0, t1);
    int entryAxis = 0;
    float tEntry = tNear.x;
    if (tNear.y > tEntry) {
        entryAxis = 1;
        tEntry = tNear.y;
    }
    if (tNear.z > tEntry) {
        entryAxis = 2;
        tEntry = tNear.z;
    }
    int exitAxis = 0;
    float tExit = tFar.x;
    if (tFar.y < tExit) {
        exitAxis = 1;
        tExit = tFar.y;
    }
    if (tFar.z < tExit) {
        exitAxis = 2;
        tExit = tFar.z;
    }
    if (!(tEntry <= tExit)) {
        return CHCRT_LS_NO_SHAFT;
    }
    float entryInv = entryAxis == 0 ? invDir.x : (entryAxis == 1 ? invDir.y : invDir.z);
    float exitInv = exitAxis == 0 ? invDir.x : (exitAxis == 1 ? invDir.y : invDir.z);
    uint entryFace = uint(entryAxis) * 2u + (entryInv >= 0.0f ? 0u : 1u);
    uint exitFace = uint(exitAxis) * 2u + (exitInv >= 0.0f ? 1u : 0u);
    precise vec3 entryPoint = origin + tEntry * direction;
    precise vec3 exitPoint = origin + tExit * direction;
    uint entryPatch = lsPatchOfAxis(lsPatchCoordinates3(entryPoint, boxMin, boxMax, n), entryAxis, n);
    uint exitPatch = lsPatchOfAxis(lsPatchCoordinates3(exitPoint, boxMin, boxMax, n), exitAxis, n);
    return lsShaftIndexFromPatches(entryFace, entryPatch, exitFace, exitPatch, n, symmetric);
}
