#include "renderer/core/image_io.h"

#include "renderer/core/error.h"
#include "renderer/core/output_path.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <limits>
#include <optional>
#include <vector>
#include <unistd.h>

namespace chcrt {

namespace fs = std::filesystem;

namespace {

enum class FileKind { Png, Jpeg, Exr, Hdr, Tiff };

std::optional<FileKind> kindFromExtension(const fs::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".png") return FileKind::Png;
    if (ext == ".jpg" || ext == ".jpeg") return FileKind::Jpeg;
    if (ext == ".exr") return FileKind::Exr;
    if (ext == ".hdr") return FileKind::Hdr;
    if (ext == ".tif" || ext == ".tiff") return FileKind::Tiff;
    return std::nullopt;
}

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

// The pixel data OIIO gets: 8-bit display values for PNG/JPEG, linear floats otherwise.
struct EncodedPixels {
    OIIO::TypeDesc type;
    int channels = 4;
    std::vector<uint8_t> bytes;
    std::vector<float> floats;
    const void* data() const { return bytes.empty() ? static_cast<const void*>(floats.data()) : bytes.data(); }
};

EncodedPixels encodePixels(const ImageRgba32f& image, FileKind kind, bool alreadyDisplayEncoded) {
    EncodedPixels out;
    const size_t pixelCount = size_t(image.width) * size_t(image.height);
    if (kind == FileKind::Png || kind == FileKind::Jpeg) {
        out.type = OIIO::TypeDesc::UINT8;
        out.channels = kind == FileKind::Jpeg ? 3 : 4; // JPEG has no alpha
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
    out.type = OIIO::TypeDesc::FLOAT;
    out.channels = kind == FileKind::Hdr ? 3 : 4; // Radiance RGBE stores RGB only
    out.floats.resize(pixelCount * size_t(out.channels));
    for (size_t i = 0; i < pixelCount; ++i) {
        for (int c = 0; c < out.channels; ++c) {
            out.floats[i * size_t(out.channels) + size_t(c)] = image.pixels[i * 4 + size_t(c)];
        }
    }
    return out;
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

// Encodes `image` in memory in the format `file`'s extension selects, then writes it with writeBytesChecked: OIIO's
// own file writers do not report a short write (a truncated PNG was written with success), its in-memory proxy
// cannot fail that way. Throws std::runtime_error with the reason.
void writeWithOiio(const fs::path& file, const ImageRgba32f& image, FileKind kind, bool alreadyDisplayEncoded) {
    const EncodedPixels pixels = encodePixels(image, kind, alreadyDisplayEncoded);
    std::vector<unsigned char> encoded;
    OIIO::Filesystem::IOVecOutput memory(encoded);
    auto output = OIIO::ImageOutput::create(file.string());
    if (!output) {
        throw std::runtime_error("cannot create an image writer: " + OIIO::geterror());
    }
    OIIO::ImageSpec spec(image.width, image.height, pixels.channels, pixels.type);
    if (kind == FileKind::Png || kind == FileKind::Jpeg) {
        spec.attribute("oiio:ColorSpace", "sRGB");
    } else {
        spec.attribute("oiio:ColorSpace", "Linear");
    }
    if (kind == FileKind::Jpeg) {
        spec.attribute("Compression", "jpeg:95");
    }
    // Our alpha is straight (unassociated): without this OIIO would divide colour by alpha for PNG.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!output->supports("ioproxy")) throw std::runtime_error("the image writer cannot encode in memory");
    void* proxy = &memory;
    spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    if (!output->open(file.string(), spec)) {
        throw std::runtime_error(output->geterror());
    }
    const bool written = output->write_image(pixels.type, pixels.data());
    const std::string writeError = written ? std::string() : output->geterror();
    if (!output->close() || !written) {
        throw std::runtime_error(written ? output->geterror() : writeError);
    }
    writeBytesChecked(file, encoded);
}

} // namespace

namespace {

FileKind imageKindOf(const fs::path& file) {
    const std::optional<FileKind> kind = kindFromExtension(file);
    if (!kind) {
        throw InputError(file.string() + ": unsupported image extension \"" + file.extension().string() +
                         "\" (use .png, .jpg, .exr, .hdr or .tif)");
    }
    return *kind;
}

} // namespace

void checkImageOutputPath(const fs::path& file) {
    imageKindOf(file);
    checkOutputPath(file);
}

void writeImage(const fs::path& file, const ImageRgba32f& image, bool alreadyDisplayEncoded) {
    const FileKind kind = imageKindOf(file);
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
        writeWithOiio(temp, image, kind, alreadyDisplayEncoded);
        fs::rename(temp, file);
    } catch (const std::runtime_error& e) {
        fs::remove(temp, ec);
        throw InputError(file.string() + ": " + e.what());
    }
}

ImageRgba32f readImage(const fs::path& file) {
    // Keep PNG's straight alpha as stored instead of letting OIIO premultiply it.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto input = OIIO::ImageInput::open(file.string(), &config);
    if (!input) {
        throw InputError(file.string() + ": " + OIIO::geterror());
    }
    const OIIO::ImageSpec& spec = input->spec();
    const int channels = spec.nchannels;
    if (spec.width <= 0 || spec.height <= 0 || channels <= 0) {
        throw InputError(file.string() + ": image has no pixels");
    }
    std::vector<float> raw(size_t(spec.width) * size_t(spec.height) * size_t(channels));
    if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, raw.data())) {
        throw InputError(file.string() + ": " + input->geterror());
    }
    // Integer formats (PNG, JPEG, 8/16-bit TIFF) hold display values; decode them unless the file says linear.
    const std::string colorSpace = spec.get_string_attribute("oiio:ColorSpace");
    const bool isInteger = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                           spec.format.basetype == OIIO::TypeDesc::UINT16;
    const bool decode = isInteger && colorSpace != "Linear" && colorSpace != "linear";
    // 1 = gray, 2 = gray + alpha, 3 = RGB, 4+ = RGBA (+ extra channels, dropped).
    const bool hasAlpha = channels == 2 || channels >= 4;
    const int colorChannels = channels >= 3 ? 3 : 1;

    ImageRgba32f image;
    image.width = spec.width;
    image.height = spec.height;
    image.pixels.resize(size_t(image.width) * size_t(image.height) * 4);
    const size_t pixelCount = size_t(image.width) * size_t(image.height);
    for (size_t i = 0; i < pixelCount; ++i) {
        const float* src = &raw[i * size_t(channels)];
        float* dst = &image.pixels[i * 4];
        for (int c = 0; c < 3; ++c) {
            const float value = src[colorChannels == 3 ? c : 0];
            dst[c] = decode ? srgbToLinear(clamp01(value)) : value;
        }
        dst[3] = hasAlpha ? src[colorChannels] : 1.0f;
    }
    return image;
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

} // namespace chcrt
