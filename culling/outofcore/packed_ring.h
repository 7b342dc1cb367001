#pragma once
// Entries of different sizes packed one after another into fixed ranges of several buffers, one ring per buffer
// (the GPU subtree cache's LOD proxy pools, gpu_subtree_cache.h). A proxy level's entries differ in size by 10× and
// more — the 350M city's coarsest proxies average 36 KB with a 95th percentile of 148 KB — so equal slots sized
// for the large ones hold a third of what packing holds: all 7,856 of that level take 273 MB packed, but
// 95th-percentile slots fit 2,300 of them into the 341 MB the level may take, and a far view asks for nearly all.
//
// An entry takes `size[p]` units in each part p (nodes, triangles, vertices: its own shape, nothing rounded up).
// Each part's cursor moves forward through the part and starts again from the beginning where the entry would not
// fit before the end; whatever an entry is placed over is evicted (in every part: an entry is resident whole or not
// at all), so the order of eviction is the order of placement, as with a round-robin policy over equal slots, but
// entries a caller pins are never evicted: the cursor moves past them. When everything placed fits (the sum of the
// sizes within each part's capacity), nothing is ever evicted.
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

namespace chcrt::outofcore {

class PackedRing {
public:
    static constexpr size_t kParts = 3;
    using Units = std::array<uint64_t, kParts>;

    // `keys`: entries are keyed 0 ... keys - 1 (subtree indices).
    PackedRing(const Units& capacity, uint32_t keys);

    // Whether an entry of `size` can be placed at all (each part within its capacity).
    bool fits(const Units& size) const;
    // Places `key` (not resident) with `size`, appending the keys it evicted to `evicted`. Returns false — placing
    // nothing, evicting nothing — when no place holds it without evicting a pinned entry within one lap of a cursor.
    bool place(uint32_t key, const Units& size, const std::function<bool(uint32_t)>& pinned, std::vector<uint32_t>& evicted);
    bool resident(uint32_t key) const { return key < resident_.size() && resident_[key] != 0; }
    // Where a resident entry starts in each part, in units from the part's start.
    const Units& offset(uint32_t key) const { return offset_.at(key); }
    const Units& capacity() const { return capacity_; }

private:
    void remove(uint32_t key);

    Units capacity_;
    Units cursor_{};
    std::array<std::map<uint64_t, uint32_t>, kParts> byStart_; // per part: entry start -> key (sizes > 0 only)
    std::vector<Units> offset_, size_;
    std::vector<uint8_t> resident_;
};

} // namespace chcrt::outofcore
