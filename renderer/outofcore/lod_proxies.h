#pragma once
// Level-of-detail proxies of a termination subtree (issue #19): coarser copies of the subtree's geometry, each with
// a bounded geometric error in world units, stored beside the subtree in a prepared scene (chs_format.h) and traced
// by the approximate method chcrt-lod instead of the subtree when their error projects below a pixel threshold
// (culling/outofcore/gpu_subtree_cache.h). Far views, where most subtrees are visible but small on screen, then
// move a small fraction of the bytes through the GPU cache.
//
// How the levels are made: the subtree's triangle soup is welded on positions (meshopt_generateVertexRemap), then each
// material's triangles are simplified on their own, so that every proxy triangle has one material. Each level starts
// from the previous one. Levels 1 ... N-1 are edge collapses with quadric error metrics (meshopt_simplify, Garland &
// Heckbert 1997) as far as a relative error of kLodBaseRelativeError × kLodErrorStep^(l-1) of the subtree's extent
// allows: the error, not a triangle count, is the target, since collapsing a city's boxes to a count made errors of
// tens of metres (measured: 1/8 of city:1m's triangles at a median 16 m) where an error bound of 0.2 % keeps 12 % of
// them at 0.24 m. Collapses keep the topology, so they stop at a few per cent (each facade detail is a closed part);
// the coarsest level N therefore clusters vertices (meshopt_simplifySloppy) towards 1 / kLodCoarsestRatio of the
// subtree's triangles, at metres of error, for views where one pixel covers metres (the 140M city from above). A
// level's error is the sum of its steps' (meshopt reports each relative to the mesh extent; times
// meshopt_simplifyScale is world units). Both simplifiers only move vertices onto existing ones, so a proxy lies
// inside its subtree's box (checked here: std::logic_error otherwise).
//
// Proxy triangles carry a representative original id: an original triangle of the subtree with the same material,
// a different one per proxy triangle (preferring one that touches the proxy triangle's corners), so hits shade
// with the right material and primary resolves find them by id (culling/outofcore/primary_resolve.h). Their
// vertex normals are the original normal at the corner that agrees best with the proxy face (sharp box edges stay
// sharp, smooth surfaces stay smooth), or the face normal where none agrees.
#include "renderer/bvh/bvh.h"

#include <cstdint>
#include <vector>

namespace chcrt::outofcore {

// The levels (all in one place): built by default (`chcrt prepare --lod-levels`), the most a file holds, the error
// bounds of the collapse levels (relative to the subtree's extent: 0.2 %, 1 %, 5 %, ...) and the coarsest level's
// triangle target.
inline constexpr uint32_t kDefaultLodLevels = 3;
inline constexpr uint32_t kMaxLodLevels = 4;
inline constexpr float kLodBaseRelativeError = 0.002f;
inline constexpr float kLodErrorStep = 5.0f;
inline constexpr uint32_t kLodCoarsestRatio = 64;
// A level is kept only when it has at most this share of the next finer level's triangles: a proxy that barely
// simplifies saves too little upload to be worth its file bytes and cache slots.
inline constexpr float kLodMaxKeptShare = 0.75f;

// One proxy level: a BVH blob in the subtree layout of chs_format.h (local indices, root 0), empty when the level
// was not kept (the simplifier could not reduce the finer level enough).
struct LodProxy {
    float errorWorld = 0.0f; // geometric error bound, world units
    std::vector<BvhNodeGpu> nodes;
    std::vector<TriangleGpu> triangles; // representative original ids, their materials
    std::vector<glm::vec3> normals;     // 3 per triangle
    std::vector<glm::vec2> texcoords;   // 3 per triangle when the subtree has them
    bool empty() const { return triangles.empty(); }
};

// Builds `levels` proxy levels (1 ... levels) of a subtree given as its triangles (any order; original ids and
// materials as written), their vertex normals (3 per triangle) and texture coordinates (3 per triangle or none).
// Deterministic. Returns `levels` entries, the ones not kept empty.
std::vector<LodProxy> buildLodProxies(const std::vector<TriangleGpu>& triangles, const std::vector<glm::vec3>& normals,
                                      const std::vector<glm::vec2>& texcoords, uint32_t levels);

} // namespace chcrt::outofcore
