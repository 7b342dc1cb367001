#pragma once
// Image files through OpenImageIO, or, in a build without it (CMake option CHCRT_WITH_OIIO=OFF), through the
// built-in codec (stb for PNG/JPEG/HDR, tinyexr for EXR; renderer/core/image_codec.h). Both write the same pixel
// values. Writes are atomic: the image goes to "<name>.tmp<pid><ext>" next to the target and is renamed into place,
// so an error never leaves a partial output file.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace chcrt {

// Linear float RGBA image, rows top to bottom. Alpha is straight (not premultiplied) and is written and
// read as stored, without OIIO's premultiplication.
struct ImageRgba32f {
    int width = 0;
    int height = 0;
    std::vector<float> pixels; // width * height * 4
    float* at(int x, int y) { return &pixels[(size_t(y) * width + x) * 4]; }
    const float* at(int x, int y) const { return &pixels[(size_t(y) * width + x) * 4]; }
};

// "OpenImageIO" or "built-in (stb, tinyexr)": the codec this build reads and writes image files with.
const char* imageCodecName();

// Writes PNG/JPEG (8-bit sRGB-encoded from linear, alpha dropped for JPEG) or EXR/HDR/TIFF (float, linear)
// chosen by extension; TIFF only with OpenImageIO. `alreadyDisplayEncoded` skips the sRGB encode (for tone-mapped or debug images whose
// values are display values). Throws InputError for an unsupported extension or an unwritable path.
void writeImage(const std::filesystem::path& file, const ImageRgba32f& image, bool alreadyDisplayEncoded = false);
// Throws InputError when writeImage could not write `file` (unknown extension, missing or unwritable directory),
// so that commands refuse before rendering.
void checkImageOutputPath(const std::filesystem::path& file);

// Reads an image file into linear float RGBA (8- and 16-bit sources are sRGB-decoded): any format OpenImageIO
// reads, or without it PNG, JPEG, HDR, EXR (and the other formats stb_image reads).
ImageRgba32f readImage(const std::filesystem::path& file);

// Image comparison used by bench/verify and image tests: RGB only (alpha is ignored), values compared after
// clamping to [0, 1], PSNR with peak 1.0. Throws InputError when the sizes differ.
struct ImageDifference {
    uint64_t differingPixels = 0; // pixels whose max RGB channel difference exceeds the threshold
    double meanAbsoluteError = 0.0; // over RGB of all pixels
    double psnrDb = 0.0;            // over RGB; +infinity when identical
    double maxAbsoluteError = 0.0; // largest RGB channel difference
};
ImageDifference compareImages(const ImageRgba32f& a, const ImageRgba32f& b, float pixelThreshold = 0.0f);

// `image` of (factor·w) × (factor·h) pixels averaged over factor × factor blocks into w × h (every channel): a
// supersampled frame box-filtered to its pixels. Throws std::invalid_argument when the size is not a multiple.
ImageRgba32f boxFilterDown(const ImageRgba32f& image, int factor);

} // namespace chcrt
