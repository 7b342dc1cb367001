#pragma once
// Binary Line Space of one box (Keul et al. 2016/2017): one bit per shaft, set iff some triangle of the node's
// subtree intersects the shaft volume. Stored in the symmetric layout (15 N^4 bits): the volume of the shaft
// from patch a to patch b is the volume from b to a.
//
// Built conservatively, never by sampling: the patches of a face pair are split recursively into blocks of
// patches (a block's hull contains the hulls of all its shafts), a block whose hull meets no triangle of the
// subtree is empty as a whole, and single shafts are decided by the exact shaft/triangle test
// (shaft_geometry.h) with patches dilated by `dilation` against float rounding of the shaft index.
#include "linespace/shaft_geometry.h"
#include "renderer/bvh/bvh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace chcrt::ls {

// Number of unordered face pairs (f1 < f2), the unit of parallel work.
inline constexpr uint32_t kFacePairCount = 15;
// The faces of face pair `pair` (0..14), f1 < f2, in the order of lsShaftIndexFromPatches' symmetric layout.
void facePairFaces(uint32_t pair, uint32_t& f1, uint32_t& f2);

// Sets filled[symmetricShaft] = 1 for every non-empty shaft between faces of face pair `pair` of `box`
// (normally the node's bounds), testing the triangles of `node`'s subtree. `filled` holds 15 N^4 bytes; the
// other face pairs' entries are not touched (so threads may fill different pairs of one array).
void fillBinaryFacePair(const Bvh& bvh, uint32_t node, const Aabb& box, uint32_t n, double dilation, uint32_t pair,
                        std::span<uint8_t> filled);

// The whole binary Line Space of a node, packed into 32-bit words (bit s of word s / 32 = shaft s, symmetric
// layout). Single-threaded; the BVH builder (linespace_build.h) runs face pairs in parallel instead.
std::vector<uint32_t> computeBinaryLineSpace(const Bvh& bvh, uint32_t node, uint32_t n, double dilation);

// Packs one byte per shaft into bitset words.
std::vector<uint32_t> packBits(std::span<const uint8_t> filled);

} // namespace chcrt::ls
