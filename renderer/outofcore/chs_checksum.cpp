#include "renderer/outofcore/chs_format.h"

#include <cstring>

namespace chcrt::outofcore {

uint64_t chsChecksum(const void* data, size_t bytes, uint64_t seed) {
    // Four independent lanes so the multiplies pipeline (~several GB/s); each lane is a multiply-rotate of
    // 8-byte words, the tail is zero-padded and the length mixed in, so truncation changes the result.
    constexpr uint64_t kPrime1 = 0x9E3779B185EBCA87ull, kPrime2 = 0xC2B2AE3D27D4EB4Full;
    auto rotl = [](uint64_t x, int r) { return (x << r) | (x >> (64 - r)); };
    auto round = [&](uint64_t acc, uint64_t word) { return rotl(acc + word * kPrime2, 31) * kPrime1; };
    const auto* p = static_cast<const unsigned char*>(data);
    uint64_t lane[4] = {seed + kPrime1 + kPrime2, seed + kPrime2, seed, seed - kPrime1};
    size_t i = 0;
    for (; i + 32 <= bytes; i += 32) {
        uint64_t w[4];
        std::memcpy(w, p + i, 32);
        for (int k = 0; k < 4; ++k) lane[k] = round(lane[k], w[k]);
    }
    uint64_t h = rotl(lane[0], 1) + rotl(lane[1], 7) + rotl(lane[2], 12) + rotl(lane[3], 18);
    for (; i < bytes; i += 8) {
        uint64_t w = 0;
        std::memcpy(&w, p + i, bytes - i < 8 ? bytes - i : 8);
        h = rotl(h ^ round(0, w), 27) * kPrime1 + kPrime2;
    }
    h ^= uint64_t(bytes) * kPrime2;
    h ^= h >> 33;
    h *= kPrime2;
    h ^= h >> 29;
    return h;
}

} // namespace chcrt::outofcore
