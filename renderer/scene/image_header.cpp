// A PNG's dimensions are read from its IHDR chunk here (stb_image's own header scan refuses a PNG of more than
// 2^30 bytes without saying how large it claims to be); every other format through stb_image's header readers
// (stbi_info_from_memory), compiled here, static, with stb's dimension limit lifted so that they report what the
// header declares. Decoding stays with tinygltf's own copy of stb_image.
#include "renderer/scene/image_header.h"

#include <climits>
#include <cstring>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO
#define STBI_MAX_DIMENSIONS INT_MAX
#include <stb/stb_image.h>

namespace chcrt::detail {
namespace {

uint32_t bigEndian32(const unsigned char* p) {
    return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

} // namespace

bool readImageHeader(const unsigned char* bytes, size_t size, ImageHeader& header) {
    if (bytes == nullptr || size == 0 || size > size_t(INT_MAX)) return false;
    // PNG: the 8-byte signature, then the IHDR chunk (length 13): width, height, bit depth, ...
    static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (size >= 8 + 8 + 13 && std::memcmp(bytes, kPng, 8) == 0 && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
        header.width = bigEndian32(bytes + 16);
        header.height = bigEndian32(bytes + 20);
        header.sixteenBit = bytes[24] == 16;
        return true;
    }
    int width = 0, height = 0, channels = 0;
    if (stbi_info_from_memory(bytes, int(size), &width, &height, &channels) == 0) return false;
    header.width = uint64_t(width);
    header.height = uint64_t(height);
    header.sixteenBit = stbi_is_16_bit_from_memory(bytes, int(size)) != 0;
    return true;
}

} // namespace chcrt::detail
