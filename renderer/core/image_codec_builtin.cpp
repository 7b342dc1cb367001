// The built-in codec of image_io.h: PNG, JPEG and Radiance HDR through stb_image_write / stb_image (Debian's
// libstb, already loaded by tinygltf), OpenEXR through tinyexr. The only image path of a build without
// OpenImageIO (CHCRT_WITH_OIIO=OFF, the GPU bundle); compiled in every build so tests can hold it against OIIO.
#include "renderer/core/image_codec.h"

#include <stb_image.h>
#include <stb_image_write.h>
#include <tinyexr.h>

#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

namespace chcrt::detail {
namespace {

void appendBytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* bytes = static_cast<const unsigned char*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

void checkSize(const FilePixels& pixels) {
    const size_t values = size_t(pixels.width) * size_t(pixels.height) * size_t(pixels.channels);
    const size_t stored = pixels.bytes.empty() ? pixels.floats.size() : pixels.bytes.size();
    if (pixels.width <= 0 || pixels.height <= 0 || stored != values) {
        throw std::runtime_error("invalid pixel data for the image writer");
    }
}

// OpenEXR, scanlines, 32-bit float channels, ZIP compression (lossless): what OIIO writes for float data.
std::vector<unsigned char> encodeExr(const FilePixels& pixels) {
    if (pixels.floats.empty() || pixels.channels != 4) throw std::runtime_error("EXR takes float RGBA pixels");
    const size_t count = size_t(pixels.width) * size_t(pixels.height);
    // Planar channels in the order EXR readers expect them listed: A, B, G, R (alphabetical).
    static constexpr const char* kNames[4] = {"A", "B", "G", "R"};
    static constexpr int kSource[4] = {3, 2, 1, 0};
    std::vector<float> planes(count * 4);
    for (int plane = 0; plane < 4; ++plane) {
        for (size_t i = 0; i < count; ++i) planes[size_t(plane) * count + i] = pixels.floats[i * 4 + size_t(kSource[plane])];
    }
    unsigned char* planePointers[4];
    for (int plane = 0; plane < 4; ++plane) {
        planePointers[plane] = reinterpret_cast<unsigned char*>(&planes[size_t(plane) * count]);
    }
    EXRImage image;
    InitEXRImage(&image);
    image.images = planePointers;
    image.width = pixels.width;
    image.height = pixels.height;
    image.num_channels = 4;

    EXRHeader header;
    InitEXRHeader(&header);
    EXRChannelInfo channels[4];
    int pixelTypes[4];
    int requestedTypes[4];
    for (int c = 0; c < 4; ++c) {
        std::memset(&channels[c], 0, sizeof(EXRChannelInfo));
        std::strncpy(channels[c].name, kNames[c], sizeof(channels[c].name) - 1);
        pixelTypes[c] = TINYEXR_PIXELTYPE_FLOAT;
        requestedTypes[c] = TINYEXR_PIXELTYPE_FLOAT;
    }
    header.num_channels = 4;
    header.channels = channels;
    header.pixel_types = pixelTypes;
    header.requested_pixel_types = requestedTypes;
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

    unsigned char* memory = nullptr;
    const char* error = nullptr;
    const size_t size = SaveEXRImageToMemory(&image, &header, &memory, &error);
    if (size == 0 || memory == nullptr) {
        const std::string reason = error != nullptr ? error : "unknown error";
        if (error != nullptr) FreeEXRErrorMessage(error);
        std::free(memory);
        throw std::runtime_error("EXR encoding failed: " + reason);
    }
    std::vector<unsigned char> out(memory, memory + size);
    std::free(memory);
    return out;
}

DecodedPixels decodeExr(const std::vector<unsigned char>& bytes) {
    float* rgba = nullptr;
    int width = 0;
    int height = 0;
    const char* error = nullptr;
    if (LoadEXRFromMemory(&rgba, &width, &height, bytes.data(), bytes.size(), &error) != TINYEXR_SUCCESS) {
        const std::string reason = error != nullptr ? error : "unknown error";
        if (error != nullptr) FreeEXRErrorMessage(error);
        std::free(rgba);
        throw std::runtime_error("not a readable EXR file: " + reason);
    }
    std::unique_ptr<float, decltype(&std::free)> owner(rgba, &std::free);
    DecodedPixels pixels;
    pixels.width = width;
    pixels.height = height;
    pixels.channels = 4; // tinyexr expands gray and RGB, alpha 1 when the file has none
    pixels.values.assign(rgba, rgba + size_t(width) * size_t(height) * 4);
    return pixels;
}

[[noreturn]] void throwStbFailure() {
    const char* reason = stbi_failure_reason();
    throw std::runtime_error(std::string("cannot decode the image: ") + (reason != nullptr ? reason : "unknown format"));
}

} // namespace

bool builtinCodecWrites(ImageFileKind kind) { return kind != ImageFileKind::Tiff; }

std::vector<unsigned char> encodeBuiltin(const FilePixels& pixels, ImageFileKind kind) {
    checkSize(pixels);
    std::vector<unsigned char> out;
    int ok = 0;
    switch (kind) {
    case ImageFileKind::Png:
        if (pixels.bytes.empty()) throw std::runtime_error("PNG takes 8-bit pixels");
        ok = stbi_write_png_to_func(&appendBytes, &out, pixels.width, pixels.height, pixels.channels,
                                    pixels.bytes.data(), pixels.width * pixels.channels);
        break;
    case ImageFileKind::Jpeg:
        if (pixels.bytes.empty()) throw std::runtime_error("JPEG takes 8-bit pixels");
        ok = stbi_write_jpg_to_func(&appendBytes, &out, pixels.width, pixels.height, pixels.channels,
                                    pixels.bytes.data(), 95);
        break;
    case ImageFileKind::Hdr:
        if (pixels.floats.empty()) throw std::runtime_error("HDR takes float pixels");
        ok = stbi_write_hdr_to_func(&appendBytes, &out, pixels.width, pixels.height, pixels.channels,
                                    pixels.floats.data());
        break;
    case ImageFileKind::Exr: return encodeExr(pixels);
    case ImageFileKind::Tiff:
        throw std::runtime_error("TIFF needs a build with OpenImageIO");
    }
    if (ok == 0 || out.empty()) throw std::runtime_error("image encoding failed");
    return out;
}

DecodedPixels decodeBuiltin(const std::vector<unsigned char>& bytes) {
    static constexpr unsigned char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
    if (bytes.size() >= 4 && std::memcmp(bytes.data(), kExrMagic, 4) == 0) return decodeExr(bytes);
    if (bytes.size() > size_t(std::numeric_limits<int>::max())) throw std::runtime_error("image file too large");
    const auto* data = bytes.data();
    const int size = int(bytes.size());
    int width = 0;
    int height = 0;
    int channels = 0;
    DecodedPixels pixels;
    if (stbi_is_hdr_from_memory(data, size)) {
        float* values = stbi_loadf_from_memory(data, size, &width, &height, &channels, 0);
        if (values == nullptr) throwStbFailure();
        pixels.values.assign(values, values + size_t(width) * size_t(height) * size_t(channels));
        stbi_image_free(values);
    } else if (stbi_is_16_bit_from_memory(data, size)) {
        stbi_us* values = stbi_load_16_from_memory(data, size, &width, &height, &channels, 0);
        if (values == nullptr) throwStbFailure();
        const size_t count = size_t(width) * size_t(height) * size_t(channels);
        pixels.values.resize(count);
        for (size_t i = 0; i < count; ++i) pixels.values[i] = float(values[i]) / 65535.0f;
        stbi_image_free(values);
        pixels.integerSource = true;
    } else {
        stbi_uc* values = stbi_load_from_memory(data, size, &width, &height, &channels, 0);
        if (values == nullptr) throwStbFailure();
        const size_t count = size_t(width) * size_t(height) * size_t(channels);
        pixels.values.resize(count);
        for (size_t i = 0; i < count; ++i) pixels.values[i] = float(values[i]) / 255.0f;
        stbi_image_free(values);
        pixels.integerSource = true;
    }
    pixels.width = width;
    pixels.height = height;
    pixels.channels = channels;
    return pixels;
}

} // namespace chcrt::detail
