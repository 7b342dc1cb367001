// The OpenImageIO codec of image_io.h (CMake option CHCRT_WITH_OIIO): every format OIIO writes and reads.
#include "renderer/core/image_codec.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <stdexcept>

namespace chcrt::detail {

std::vector<unsigned char> encodeOiio(const FilePixels& pixels, ImageFileKind kind, const std::filesystem::path& file) {
    const bool eightBit = !pixels.bytes.empty();
    const OIIO::TypeDesc type = eightBit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    std::vector<unsigned char> encoded;
    OIIO::Filesystem::IOVecOutput memory(encoded);
    auto output = OIIO::ImageOutput::create(file.string());
    if (!output) {
        throw std::runtime_error("cannot create an image writer: " + OIIO::geterror());
    }
    OIIO::ImageSpec spec(pixels.width, pixels.height, pixels.channels, type);
    if (kind == ImageFileKind::Png || kind == ImageFileKind::Jpeg) {
        spec.attribute("oiio:ColorSpace", "sRGB");
    } else {
        spec.attribute("oiio:ColorSpace", "Linear");
    }
    if (kind == ImageFileKind::Jpeg) {
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
    const void* data = eightBit ? static_cast<const void*>(pixels.bytes.data()) : pixels.floats.data();
    const bool written = output->write_image(type, data);
    const std::string writeError = written ? std::string() : output->geterror();
    if (!output->close() || !written) {
        throw std::runtime_error(written ? output->geterror() : writeError);
    }
    return encoded;
}

DecodedPixels decodeOiio(const std::filesystem::path& file) {
    // Keep PNG's straight alpha as stored instead of letting OIIO premultiply it.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto input = OIIO::ImageInput::open(file.string(), &config);
    if (!input) {
        throw std::runtime_error(OIIO::geterror());
    }
    const OIIO::ImageSpec& spec = input->spec();
    DecodedPixels pixels;
    pixels.width = spec.width;
    pixels.height = spec.height;
    pixels.channels = spec.nchannels;
    if (pixels.width <= 0 || pixels.height <= 0 || pixels.channels <= 0) {
        return pixels; // readImage reports the empty image
    }
    pixels.values.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.values.data())) {
        throw std::runtime_error(input->geterror());
    }
    // Integer formats (PNG, JPEG, 8/16-bit TIFF) hold display values; decode them unless the file says linear.
    const std::string colorSpace = spec.get_string_attribute("oiio:ColorSpace");
    pixels.integerSource = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                           spec.format.basetype == OIIO::TypeDesc::UINT16;
    pixels.linearTagged = colorSpace == "Linear" || colorSpace == "linear";
    return pixels;
}

} // namespace chcrt::detail
