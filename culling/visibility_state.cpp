#include "culling/visibility_state.h"

#include <cassert>

namespace chcrt {

VisibilityState::VisibilityState(int width, int height, uint32_t seed)
    : width_(width), height_(height), random_(0x9E3779B97F4A7C15ull ^ seed) {
    const int32_t root = allocate();
    QueryPair& p = pairs_[size_t(root)];
    p.tile = Tile{0, 0, width, height};
    p.bvhNode = 0;
}

uint32_t VisibilityState::nextRandom() {
    // splitmix64: deterministic per state, so a walkthrough's query schedule is reproducible.
    uint64_t z = (random_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return uint32_t((z ^ (z >> 31)) >> 32);
}

int32_t VisibilityState::allocate() {
    int32_t index;
    if (!free_.empty()) {
        index = free_.back();
        free_.pop_back();
    } else {
        index = int32_t(pairs_.size());
        pairs_.emplace_back();
    }
    pairs_[size_t(index)] = QueryPair{};
    pairs_[size_t(index)].alive = true;
    return index;
}

void VisibilityState::release(int32_t index) {
    pairs_[size_t(index)].alive = false;
    free_.push_back(index);
}

int VisibilityState::subdivide(int32_t index, const Tile* tiles, const uint32_t* nodes, int count, int32_t* out,
                               uint32_t requeryInterval) {
    assert(pairs_[size_t(index)].isLeaf() && count >= 2 && count <= 4);
    for (int i = 0; i < count; ++i) {
        const int32_t child = allocate();
        QueryPair& c = pairs_[size_t(child)];
        c.tile = tiles[i];
        c.bvhNode = nodes[i];
        c.parent = index;
        // §5.1: the first lazy re-query of a visible pair falls on a random frame in 1..n.
        c.requeryPhase = uint8_t(requeryInterval > 1 ? nextRandom() % requeryInterval : 0);
        out[i] = child;
    }
    QueryPair& p = pairs_[size_t(index)];
    p.childCount = uint8_t(count);
    for (int i = 0; i < 4; ++i) p.children[size_t(i)] = i < count ? out[i] : -1;
    p.visible = true;
    return count;
}

int VisibilityState::pullUpInvisibility() {
    std::vector<int32_t> merge;
    for (size_t i = 0; i < pairs_.size(); ++i) {
        const QueryPair& p = pairs_[i];
        if (!p.alive || p.isLeaf()) continue;
        bool allInvisible = true;
        for (int c = 0; c < p.childCount && allInvisible; ++c) {
            const QueryPair& child = pairs_[size_t(p.children[size_t(c)])];
            allInvisible = child.isLeaf() && !child.visible;
        }
        if (allInvisible) merge.push_back(int32_t(i));
    }
    for (int32_t index : merge) {
        QueryPair& p = pairs_[size_t(index)];
        for (int c = 0; c < p.childCount; ++c) release(p.children[size_t(c)]);
        p.children = {-1, -1, -1, -1};
        p.childCount = 0;
        p.visible = false;
    }
    return int(merge.size());
}

void VisibilityState::collectLeaves(std::vector<int32_t>& visible, std::vector<int32_t>& invisible) const {
    visible.clear();
    invisible.clear();
    for (size_t i = 0; i < pairs_.size(); ++i) {
        const QueryPair& p = pairs_[i];
        if (!p.alive || !p.isLeaf()) continue;
        (p.visible ? visible : invisible).push_back(int32_t(i));
    }
}

void VisibilityState::collectInvisibleNextToVisible(std::vector<uint32_t>& nodes) const {
    for (const QueryPair& p : pairs_) {
        if (!p.alive || !p.isLeaf() || p.visible || p.parent < 0) continue;
        const QueryPair& parent = pairs_[size_t(p.parent)];
        for (int c = 0; c < parent.childCount; ++c) {
            const QueryPair& sibling = pairs_[size_t(parent.children[size_t(c)])];
            if (sibling.visible || !sibling.isLeaf()) {
                nodes.push_back(p.bvhNode);
                break;
            }
        }
    }
}

} // namespace chcrt
