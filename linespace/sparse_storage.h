#pragma once
// Sparse shaft storage (representative candidate paper §3.1, Fig. 3, Algorithm 2): per Line Space one bit per
// shaft in 32-bit words, an offset per word (exclusive prefix sum of the filled shafts before it, absolute in
// the shared data pool), and the data of the filled shafts stored consecutively. Lookup is O(1): one word,
// one offset, one popcount (lsSparseSlot, shared with GLSL). Many Line Spaces share the three pools; the
// dense form exists only as the tests' oracle.
#include "shaders/shared/linespace_layout.h"

#include <cstdint>
#include <span>
#include <vector>

namespace chcrt::ls {

// Marks an empty shaft in dense input.
inline constexpr uint32_t kEmptyShaft = 0xFFFFFFFFu;

// Packs dense values (kEmptyShaft = empty) into bitset words and the filled values in shaft order.
void packSparse(std::span<const uint32_t> dense, std::vector<uint32_t>& words, std::vector<uint32_t>& data);

class SparseShaftStore {
public:
    SparseShaftStore() = default;
    explicit SparseShaftStore(uint32_t shaftsPerSpace);

    // Appends one Line Space given densely (kEmptyShaft = empty); returns its index. `dense` must hold
    // shaftsPerSpace() values. The offsets are computed by a prefix sum over the words.
    uint32_t append(std::span<const uint32_t> dense);
    // Appends one Line Space already packed by packSparse (its words and its filled shafts' data).
    uint32_t appendPacked(std::span<const uint32_t> words, std::span<const uint32_t> data);

    // Algorithm 2: the data of `shaft` in Line Space `space`, or kEmptyShaft.
    uint32_t lookup(uint32_t space, uint32_t shaft) const;
    bool filled(uint32_t space, uint32_t shaft) const;

    uint32_t shaftsPerSpace() const { return shaftsPerSpace_; }
    uint32_t wordsPerSpace() const { return wordsPerSpace_; }
    uint32_t spaceCount() const { return wordsPerSpace_ == 0 ? 0u : uint32_t(words_.size() / wordsPerSpace_); }
    uint64_t filledCount() const { return data_.size(); }
    uint64_t bytes() const { return 4ull * (words_.size() + offsets_.size() + data_.size()); }

    const std::vector<uint32_t>& words() const { return words_; }
    const std::vector<uint32_t>& offsets() const { return offsets_; }
    const std::vector<uint32_t>& data() const { return data_; }

    // Reassembles a store from its pools (cache loading); returns false when they are inconsistent (sizes,
    // offsets not the prefix sum of the popcounts), so a corrupt file is never trusted.
    static bool fromPools(uint32_t shaftsPerSpace, std::vector<uint32_t> words, std::vector<uint32_t> offsets,
                          std::vector<uint32_t> data, SparseShaftStore& out);

private:
    uint32_t shaftsPerSpace_ = 0;
    uint32_t wordsPerSpace_ = 0;
    std::vector<uint32_t> words_;
    std::vector<uint32_t> offsets_;
    std::vector<uint32_t> data_;
};

} // namespace chcrt::ls
