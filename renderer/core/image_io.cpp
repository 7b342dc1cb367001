#include "renderer/core/image_io.h"

#include "renderer/core/error.h"
#include "renderer/core/image_codec.h"
#include "renderer/core/output_path.h"

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>
#include <unistd.h>

namespace chcrt {

namespace fs = std::filesystem;
using detail::ImageFileKind;

namespace {

// sRGB transfer functions (IEC 61966-2-1), on values already clamped to [0, 1].
float linearToSrgb(float x) {
    return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}
float srgbToLinear(float x) {
    return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

float clamp01(float x) {
    // NaN becomes 0 rather than poisoning the 8-bit conversion.
    return x > 0.0f ? std::min(x, 1.0f) : 0.0f;
}

// Writes `bytes` to `file` with every write checked and synced: a full disk (ENOSPC) or a file size limit (EFBIG)
// must be an error, never a short file renamed into place.
void writeBytesChecked(const fs::path& file, const std::vector<unsigned char>& bytes) {
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) throw std::runtime_error(std::string("cannot create the file: ") + std::strerror(errno));
    size_t written = 0;
    while (written < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int error = n < 0 ? errno : ENOSPC;
            ::close(fd);
            throw std::runtime_error(std::string("write failed: ") + std::strerror(error));
        }
        written += size_t(n);
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0) throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
}

// The formats this build writes, for error messages.
const char* writableExtensions() {
#if CHCRT_WITH_OIIO
    return ".png, .jpg, .exr, .hdr or .tif";
#else
    return ".png, .jpg, .exr or .hdr";
#endif
}

ImageFileKind imageKindOf(const fs::path& file) {
    const std::optional<ImageFileKind> kind = detail::imageKindFromExtension(file);
    if (!kind) {
        throw InputError(file.string() + ": unsupported image extension \"" + file.extension().string() +
                         "\" (use " + writableExtensions() + ")");
    }
#if !CHCRT_WITH_OIIO
    if (!detail::builtinCodecWrites(*kind)) {
        throw InputError(file.string() + ": this build has no OpenImageIO (CHCRT_WITH_OIIO=OFF) and writes " +
                         writableExtensions() + " only");
    }
#endif
    return *kind;
}

// Encodes `image` in memory in the format `file`'s extension selects, with OpenImageIO when the build has it and
// the built-in codec otherwise. Throws std::runtime_error with the reason.
std::vector<unsigned char> encodeImage(const fs::path& file, const ImageRgba32f& image, ImageFileKind kind,
                                       bool alreadyDisplayEncoded) {
    const detail::FilePixels pixels = detail::toFilePixels(image, kind, alreadyDisplayEncoded);
#if CHCRT_WITH_OIIO
    return detail::encodeOiio(pixels, kind, file);
#else
    (void)file;
    return detail::encodeBuiltin(pixels, kind);
#endif
}

} // namespace

namespace detail {

std::optional<ImageFileKind> imageKindFromExtension(const fs::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".png") return ImageFileKind::Png;
    if (ext == ".jpg" || ext == ".jpeg") return ImageFileKind::Jpeg;
    if (ext == ".exr") return ImageFileKind::Exr;
    if (ext == ".hdr") return ImageFileKind::Hdr;
    if (ext == ".tif" || ext == ".tiff") return ImageFileKind::Tiff;
    return std::nullopt;
}

FilePixels toFilePixels(const ImageRgba32f& image, ImageFileKind kind, bool alreadyDisplayEncoded) {
    FilePixels out;
    out.width = image.width;
    out.height = image.height;
    const size_t pixelCount = size_t(image.width) * size_t(image.height);
    if (kind == ImageFileKind::Png || kind == ImageFileKind::Jpeg) {
        out.channels = kind == ImageFileKind::Jpeg ? 3 : 4; // JPEG has no alpha
        out.bytes.resize(pixelCount * size_t(out.channels));
        for (size_t i = 0; i < pixelCount; ++i) {
            for (int c = 0; c < out.channels; ++c) {
                float value = clamp01(image.pixels[i * 4 + size_t(c)]);
                if (c < 3 && !alreadyDisplayEncoded) {
                    value = linearToSrgb(value); // alpha is linear coverage, never encoded
                }
                out.bytes[i * size_t(out.channels) + size_t(c)] = uint8_t(std::lround(value * 255.0f));
            }
        }
        return out;
    }
    out.channels = kind == ImageFileKind::Hdr ? 3 : 4; // Radiance RGBE stores RGB only
    out.floats.resize(pixelCount * size_t(out.channels));
    for (size_t i = 0; i < pixelCount; ++i) {
        for (int c = 0; c < out.channels; ++c) {
            out.floats[i * size_t(out.channels) + size_t(c)] = image.pixels[i * 4 + size_t(c)];
        }
    }
    return out;
}

ImageRgba32f fromDecodedPixels(const DecodedPixels& pixels) {
    const int channels = pixels.channels;
    const bool decode = pixels.integerSource && !pixels.linearTagged;
    // 1 = gray, 2 = gray + alpha, 3 = RGB, 4+ = RGBA (+ extra channels, dropped).
    const bool hasAlpha = channels == 2 || channels >= 4;
    const int colorChannels = channels >= 3 ? 3 : 1;
    ImageRgba32f image;
    image.width = pixels.width;
    image.height = pixels.height;
    const size_t pixelCount = size_t(image.width) * size_t(image.height);
    image.pixels.resize(pixelCount * 4);
    for (size_t i = 0; i < pixelCount; ++i) {
        const float* src = &pixels.values[i * size_t(channels)];
        float* dst = &image.pixels[i * 4];
        for (int c = 0; c < 3; ++c) {
            const float value = src[colorChannels == 3 ? c : 0];
            dst[c] = decode ? srgbToLinear(clamp01(value)) : value;
        }
        dst[3] = hasAlpha ? src[colorChannels] : 1.0f;
    }
    return image;
}

} // namespace detail

const char* imageCodecName() {
#if CHCRT_WITH_OIIO
    return "OpenImageIO";
#else
    return "built-in (stb, tinyexr)";
#endif
}

void checkImageOutputPath(const fs::path& file) {
    imageKindOf(file);
    checkOutputPath(file);
}

void writeImage(const fs::path& file, const ImageRgba32f& image, bool alreadyDisplayEncoded) {
    const ImageFileKind kind = imageKindOf(file);
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() != size_t(image.width) * size_t(image.height) * 4) {
        throw InputError(file.string() + ": invalid image (" + std::to_string(image.width) + "x" +
                         std::to_string(image.height) + " with " + std::to_string(image.pixels.size()) +
                         " floats)");
    }
    checkOutputPath(file);
    std::error_code ec;
    // Same directory as the target so that the rename cannot cross file systems (and so is atomic); the process id
    // keeps two processes writing the same image (two farm tasks) from sharing a temporary file.
    fs::path temp = file;
    temp.replace_filename(file.stem().string() + ".tmp" + std::to_string(::getpid()) + file.extension().string());
    try {
        writeBytesChecked(temp, encodeImage(temp, image, kind, alreadyDisplayEncoded));
        fs::rename(temp, file);
    } catch (const std::runtime_error& e) {
        fs::remove(temp, ec);
        throw InputError(file.string() + ": " + e.what());
    }
}

ImageRgba32f readImage(const fs::path& file) {
    detail::DecodedPixels pixels;
    try {
#if CHCRT_WITH_OIIO
        pixels = detail::decodeOiio(file);
#else
        std::ifstream in(file, std::ios::binary);
        if (!in) throw std::runtime_error(std::string("cannot open the file: ") + std::strerror(errno));
        const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) throw std::runtime_error("read failed");
        pixels = detail::decodeBuiltin(bytes);
#endif
    } catch (const std::runtime_error& e) {
        throw InputError(file.string() + ": " + e.what());
    }
    if (pixels.width <= 0 || pixels.height <= 0 || pixels.channels <= 0) {
        throw InputError(file.string() + ": image has no pixels");
    }
    return detail::fromDecodedPixels(pixels);
}

ImageDifference compareImages(const ImageRgba32f& a, const ImageRgba32f& b, float pixelThreshold) {
    if (a.width != b.width || a.height != b.height) {
        throw InputError("cannot compare images of different sizes (" + std::to_string(a.width) + "x" +
                         std::to_string(a.height) + " and " + std::to_string(b.width) + "x" +
                         std::to_string(b.height) + ")");
    }
    ImageDifference difference;
    const size_t pixelCount = size_t(a.width) * size_t(a.height);
    double sumAbs = 0.0;
    double sumSquared = 0.0;
    for (size_t i = 0; i < pixelCount; ++i) {
        float pixelMax = 0.0f;
        for (size_t c = 0; c < 3; ++c) {
            const float d = std::abs(clamp01(a.pixels[i * 4 + c]) - clamp01(b.pixels[i * 4 + c]));
            pixelMax = std::max(pixelMax, d);
            sumAbs += d;
            sumSquared += double(d) * double(d);
        }
        difference.maxAbsoluteError = std::max(difference.maxAbsoluteError, double(pixelMax));
        if (pixelMax > pixelThreshold) {
            ++difference.differingPixels;
        }
    }
    const double samples = double(pixelCount) * 3.0;
    difference.meanAbsoluteError = samples > 0.0 ? sumAbs / samples : 0.0;
    const double mse = samples > 0.0 ? sumSquared / samples : 0.0;
    // Peak signal 1.0: PSNR = 10 log10(1 / MSE).
    difference.psnrDb = mse > 0.0 ? -10.0 * std::log10(mse) : std::numeric_limits<double>::infinity();
    return difference;
}

ImageRgba32f boxFilterDown(const ImageRgba32f& image, int factor) {
    if (factor < 1 || image.width % factor != 0 || image.height % factor != 0) {
        throw std::invalid_argument("boxFilterDown: the image size is not a multiple of the factor");
    }
    ImageRgba32f out;
    out.width = image.width / factor;
    out.height = image.height / factor;
    out.pixels.assign(size_t(out.width) * size_t(out.height) * 4, 0.0f);
    const float weight = 1.0f / float(factor * factor);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const float* in = image.at(x, y);
            float* o = out.at(x / factor, y / factor);
            for (int c = 0; c < 4; ++c) o[c] += in[c] * weight;
        }
    }
    return out;
}

} // namespace chcrt
