#include "culling/outofcore/packed_ring.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

namespace chcrt::outofcore {

PackedRing::PackedRing(const Units& capacity, uint32_t keys)
    : capacity_(capacity), offset_(keys, Units{}), size_(keys, Units{}), resident_(keys, 0) {}

bool PackedRing::fits(const Units& size) const {
    for (size_t p = 0; p < kParts; ++p) {
        if (size[p] > capacity_[p]) return false;
    }
    return true;
}

bool PackedRing::place(uint32_t key, const Units& size, const std::function<bool(uint32_t)>& pinned,
                       std::vector<uint32_t>& evicted) {
    if (key >= resident_.size() || resident_[key] != 0) throw std::logic_error("PackedRing::place: key out of range or resident");
    if (!fits(size)) return false;
    // The entries of part p that overlap [begin, begin + units), in order of their starts.
    const auto overlapping = [&](size_t p, uint64_t begin, uint64_t units, auto&& visit) {
        const std::map<uint64_t, uint32_t>& entries = byStart_[p];
        auto it = entries.upper_bound(begin);
        if (it != entries.begin()) {
            const auto before = std::prev(it);
            if (before->first + size_[before->second][p] > begin) it = before;
        }
        for (; it != entries.end() && it->first < begin + units; ++it) {
            if (!visit(it->second)) return;
        }
    };
    // Per part, the first start from its cursor on where no pinned entry is in the way; within one lap.
    Units start = cursor_;
    for (size_t p = 0; p < kParts; ++p) {
        if (size[p] == 0) continue;
        uint64_t travelled = 0;
        for (;;) {
            if (start[p] + size[p] > capacity_[p]) { // the rest of the part is too short: start again from its beginning
                travelled += capacity_[p] - start[p];
                start[p] = 0;
            }
            if (travelled >= capacity_[p]) return false;
            uint64_t pinnedEnd = 0;
            overlapping(p, start[p], size[p], [&](uint32_t other) {
                if (!pinned(other)) return true;
                pinnedEnd = offset_[other][p] + size_[other][p];
                return false;
            });
            if (pinnedEnd == 0) break;
            travelled += pinnedEnd - start[p];
            start[p] = pinnedEnd;
        }
    }
    std::vector<uint32_t> victims;
    for (size_t p = 0; p < kParts; ++p) {
        if (size[p] == 0) continue;
        overlapping(p, start[p], size[p], [&](uint32_t other) {
            if (std::find(victims.begin(), victims.end(), other) == victims.end()) victims.push_back(other);
            return true;
        });
    }
    for (uint32_t victim : victims) remove(victim);
    evicted.insert(evicted.end(), victims.begin(), victims.end());
    for (size_t p = 0; p < kParts; ++p) {
        if (size[p] == 0) continue;
        byStart_[p].emplace(start[p], key);
        cursor_[p] = start[p] + size[p];
    }
    offset_[key] = start;
    size_[key] = size;
    resident_[key] = 1;
    return true;
}

void PackedRing::remove(uint32_t key) {
    for (size_t p = 0; p < kParts; ++p) {
        if (size_[key][p] != 0) byStart_[p].erase(offset_[key][p]);
    }
    resident_[key] = 0;
}

} // namespace chcrt::outofcore
