#include "linespace/sparse_storage.h"

#include <bit>
#include <cassert>

namespace chcrt::ls {

SparseShaftStore::SparseShaftStore(uint32_t shaftsPerSpace)
    : shaftsPerSpace_(shaftsPerSpace), wordsPerSpace_((shaftsPerSpace + 31u) / 32u) {}

void packSparse(std::span<const uint32_t> dense, std::vector<uint32_t>& words, std::vector<uint32_t>& data) {
    words.assign((dense.size() + 31) / 32, 0u);
    data.clear();
    for (size_t shaft = 0; shaft < dense.size(); ++shaft) {
        if (dense[shaft] != kEmptyShaft) {
            words[shaft / 32] |= 1u << (shaft % 32);
            data.push_back(dense[shaft]);
        }
    }
}

uint32_t SparseShaftStore::append(std::span<const uint32_t> dense) {
    assert(dense.size() == shaftsPerSpace_);
    std::vector<uint32_t> words, data;
    packSparse(dense, words, data);
    return appendPacked(words, data);
}

uint32_t SparseShaftStore::appendPacked(std::span<const uint32_t> words, std::span<const uint32_t> data) {
    assert(words.size() == wordsPerSpace_);
    const uint32_t space = spaceCount();
    // Offsets: exclusive prefix sum of the popcounts, absolute in the data pool.
    uint32_t running = static_cast<uint32_t>(data_.size());
    for (const uint32_t word : words) {
        offsets_.push_back(running);
        words_.push_back(word);
        running += static_cast<uint32_t>(std::popcount(word));
    }
    assert(running == data_.size() + data.size());
    data_.insert(data_.end(), data.begin(), data.end());
    return space;
}

uint32_t SparseShaftStore::lookup(uint32_t space, uint32_t shaft) const {
    assert(space < spaceCount() && shaft < shaftsPerSpace_);
    const size_t w = size_t(space) * wordsPerSpace_ + shaft / 32u;
    const uint32_t slot = gpu::lsSparseSlot(words_[w], offsets_[w], shaft);
    return slot == CHCRT_LS_EMPTY_SLOT ? kEmptyShaft : data_[slot];
}

bool SparseShaftStore::filled(uint32_t space, uint32_t shaft) const {
    const size_t w = size_t(space) * wordsPerSpace_ + shaft / 32u;
    return ((words_[w] >> (shaft & 31u)) & 1u) != 0u;
}

bool SparseShaftStore::fromPools(uint32_t shaftsPerSpace, std::vector<uint32_t> words,
                                 std::vector<uint32_t> offsets, std::vector<uint32_t> data, SparseShaftStore& out) {
    SparseShaftStore store(shaftsPerSpace);
    if (store.wordsPerSpace_ == 0 || words.size() != offsets.size() || words.size() % store.wordsPerSpace_ != 0) {
        return false;
    }
    uint64_t running = 0;
    const uint32_t tailBits = shaftsPerSpace % 32u;
    for (size_t w = 0; w < words.size(); ++w) {
        // Bits past the last shaft of a Line Space must be clear.
        if (tailBits != 0 && w % store.wordsPerSpace_ == store.wordsPerSpace_ - 1 && (words[w] >> tailBits) != 0u) {
            return false;
        }
        if (offsets[w] != running) {
            return false;
        }
        running += static_cast<uint64_t>(std::popcount(words[w]));
    }
    if (running != data.size()) {
        return false;
    }
    store.words_ = std::move(words);
    store.offsets_ = std::move(offsets);
    store.data_ = std::move(data);
    out = std::move(store);
    return true;
}

} // namespace chcrt::ls
