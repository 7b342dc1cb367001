#pragma once
// Internal to chcrt_core (and its tests): the two image codecs behind image_io.h. Both see the same pixels: the
// conversion between ImageRgba32f and what a file stores (8-bit sRGB display values or linear floats) is done once,
// here, so a build with OpenImageIO and one without write the same values.
//   - OpenImageIO (CMake option CHCRT_WITH_OIIO, on by default): every format of image_io.h, reading any format
//     OIIO reads.
//   - built-in (always compiled): PNG, JPEG and Radiance HDR through stb_image_write / stb_image (Debian's libstb,
//     which tinygltf uses already), OpenEXR through tinyexr (float RGBA, ZIP compression). Writing and reading
//     images without OpenImageIO and its ~250 shared libraries is what lets the GPU bundle travel (docs/gpu.md).
#include "renderer/core/image_io.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace chcrt::detail {

enum class ImageFileKind { Png, Jpeg, Exr, Hdr, Tiff };

// By extension, case-insensitively: .png, .jpg/.jpeg, .exr, .hdr, .tif/.tiff.
std::optional<ImageFileKind> imageKindFromExtension(const std::filesystem::path& file);

// Pixels laid out as the file stores them: 8-bit display values (PNG: RGBA, JPEG: RGB) or linear floats
// (EXR, TIFF: RGBA; HDR: RGB), rows top to bottom.
struct FilePixels {
    int width = 0;
    int height = 0;
    int channels = 4;
    std::vector<uint8_t> bytes;  // 8-bit kinds
    std::vector<float> floats;   // float kinds
};
FilePixels toFilePixels(const ImageRgba32f& image, ImageFileKind kind, bool alreadyDisplayEncoded);

// Pixels as a reader returns them: `channels` values per pixel (1 gray, 2 gray + alpha, 3 RGB, 4+ RGBA + extra),
// integer sources normalised to [0, 1].
struct DecodedPixels {
    int width = 0;
    int height = 0;
    int channels = 0;
    bool integerSource = false; // 8- or 16-bit file: display values, sRGB-decoded unless `linearTagged`
    bool linearTagged = false;  // the file says its integer values are linear
    std::vector<float> values;
};
// Expands to linear RGBA (gray to RGB, alpha 1 when absent, sRGB decode of integer sources).
ImageRgba32f fromDecodedPixels(const DecodedPixels& pixels);

// Built-in codec. encodeBuiltin supports PNG, JPEG, EXR and HDR (TIFF: throws). decodeBuiltin recognises the format
// from the bytes (EXR by its magic number, the rest through stb_image). Both throw std::runtime_error with the reason.
bool builtinCodecWrites(ImageFileKind kind);
std::vector<unsigned char> encodeBuiltin(const FilePixels& pixels, ImageFileKind kind);
DecodedPixels decodeBuiltin(const std::vector<unsigned char>& bytes);

#if CHCRT_WITH_OIIO
// OpenImageIO codec: encodes in memory (OIIO's file writers do not report a short write) in the format `file`'s
// extension selects; decodes any file OIIO reads. Both throw std::runtime_error with the reason.
std::vector<unsigned char> encodeOiio(const FilePixels& pixels, ImageFileKind kind, const std::filesystem::path& file);
DecodedPixels decodeOiio(const std::filesystem::path& file);
#endif

} // namespace chcrt::detail
