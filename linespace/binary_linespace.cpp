#include "linespace/binary_linespace.h"

#include "linespace/shaft_index.h"
#include "linespace/subtree_query.h"

namespace chcrt::ls {

namespace {

struct FacePairContext {
    const Bvh& bvh;
    uint32_t node;
    const Aabb& box;
    uint32_t n;
    double dilation;
    std::span<uint8_t> filled;
};

// Splits the rectangle with more patches along its longer side; recursion ends at single patch pairs.
void fillBlock(const FacePairContext& c, PatchRect a, PatchRect b) {
    const ShaftVolume volume(patchRegion(c.box, c.n, a, c.dilation), patchRegion(c.box, c.n, b, c.dilation));
    if (!subtreeOverlapsShaft(c.bvh, c.node, volume)) {
        return; // every shaft of the block is empty
    }
    if (a.count() == 1 && b.count() == 1) {
        const uint32_t shaft =
            lsShaftIndexFromPatches(a.face, a.v0 * c.n + a.u0, b.face, b.v0 * c.n + b.u0, c.n, true);
        c.filled[shaft] = 1;
        return;
    }
    PatchRect& larger = a.count() >= b.count() ? a : b;
    PatchRect first = larger, second = larger;
    if (larger.u1 - larger.u0 >= larger.v1 - larger.v0) {
        first.u1 = second.u0 = (larger.u0 + larger.u1) / 2;
    } else {
        first.v1 = second.v0 = (larger.v0 + larger.v1) / 2;
    }
    const bool splitA = &larger == &a;
    fillBlock(c, splitA ? first : a, splitA ? b : first);
    fillBlock(c, splitA ? second : a, splitA ? b : second);
}

} // namespace

void facePairFaces(uint32_t pair, uint32_t& f1, uint32_t& f2) {
    f1 = 0;
    while (pair >= 5u - f1) {
        pair -= 5u - f1;
        ++f1;
    }
    f2 = f1 + 1u + pair;
}

void fillBinaryFacePair(const Bvh& bvh, uint32_t node, const Aabb& box, uint32_t n, double dilation, uint32_t pair,
                        std::span<uint8_t> filled) {
    uint32_t f1 = 0, f2 = 0;
    facePairFaces(pair, f1, f2);
    const FacePairContext context{bvh, node, box, n, dilation, filled};
    fillBlock(context, PatchRect{f1, 0, n, 0, n}, PatchRect{f2, 0, n, 0, n});
}

std::vector<uint32_t> packBits(std::span<const uint8_t> filled) {
    std::vector<uint32_t> words((filled.size() + 31) / 32, 0u);
    for (size_t s = 0; s < filled.size(); ++s) {
        if (filled[s] != 0) {
            words[s / 32] |= 1u << (s % 32);
        }
    }
    return words;
}

std::vector<uint32_t> computeBinaryLineSpace(const Bvh& bvh, uint32_t node, uint32_t n, double dilation) {
    std::vector<uint8_t> filled(lsShaftCount(n, true), 0);
    const Aabb box{bvh.nodes[node].boundsMin, bvh.nodes[node].boundsMax};
    for (uint32_t pair = 0; pair < kFacePairCount; ++pair) {
        fillBinaryFacePair(bvh, node, box, n, dilation, pair, filled);
    }
    return packBits(filled);
}

} // namespace chcrt::ls
