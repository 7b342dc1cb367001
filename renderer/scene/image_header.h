#pragma once
// The dimensions an encoded image (PNG, JPEG, BMP, TGA, GIF, PSD, HDR, PNM, PIC: what stb_image decodes) declares
// in its header, read without decoding, so that a texture's size can be refused before anything is allocated
// for it (gltf_loader.cpp).
#include <cstddef>
#include <cstdint>

namespace chcrt::detail {

struct ImageHeader {
    uint64_t width = 0;
    uint64_t height = 0;
    bool sixteenBit = false; // decoded with 16 bits per channel
};

// False when the header is not one stb_image recognises (its decoder then fails with its own message).
bool readImageHeader(const unsigned char* bytes, size_t size, ImageHeader& header);

} // namespace chcrt::detail
