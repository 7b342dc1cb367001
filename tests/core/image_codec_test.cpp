// The built-in image codec (stb, tinyexr; the only one of a build without OpenImageIO, such as the GPU bundle)
// against OpenImageIO, in a build that has both: files either one writes read back with the other as the same
// values, so the travelling build's PNG and EXR images are the normal build's.
#include "renderer/core/image_codec.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <random>

namespace chcrt::detail {
namespace {

namespace fs = std::filesystem;

class ImageCodecTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("chcrt_image_codec_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path save(const std::string& name, const std::vector<unsigned char>& bytes) const {
        const fs::path file = dir_ / name;
        std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        return file;
    }
    static std::vector<unsigned char> load(const fs::path& file) {
        std::ifstream in(file, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }

    fs::path dir_;
};

// Every 8-bit value in every channel, alpha included (a straight alpha of 0 must not lose the colour), and a few
// values out of [0, 1] that clamp.
ImageRgba32f testImage(int width, int height) {
    ImageRgba32f image;
    image.width = width;
    image.height = height;
    image.pixels.resize(size_t(width) * size_t(height) * 4);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> value(-0.1f, 1.1f);
    for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = i < 1024 ? float(i % 256) / 255.0f : value(rng);
    return image;
}

// Decoded 8-bit values back to bytes (each reader turns v into v / 255 in its own float arithmetic).
std::vector<int> toBytes(const DecodedPixels& pixels) {
    std::vector<int> bytes(pixels.values.size());
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = int(std::lround(pixels.values[i] * 255.0f));
    return bytes;
}

std::vector<int> toInts(const std::vector<uint8_t>& bytes) { return {bytes.begin(), bytes.end()}; }

TEST_F(ImageCodecTest, PngOfEitherCodecReadsBackIdenticallyWithTheOther) {
    const ImageRgba32f image = testImage(37, 29);
    const FilePixels pixels = toFilePixels(image, ImageFileKind::Png, false);
    const fs::path builtin = save("builtin.png", encodeBuiltin(pixels, ImageFileKind::Png));
    const fs::path oiio = save("oiio.png", encodeOiio(pixels, ImageFileKind::Png, dir_ / "oiio.png"));

    const DecodedPixels builtinByOiio = decodeOiio(builtin);
    const DecodedPixels oiioByBuiltin = decodeBuiltin(load(oiio));
    for (const DecodedPixels* read : {&builtinByOiio, &oiioByBuiltin}) {
        ASSERT_EQ(read->width, 37);
        ASSERT_EQ(read->height, 29);
        ASSERT_EQ(read->channels, 4);
        EXPECT_TRUE(read->integerSource);
        EXPECT_FALSE(read->linearTagged);
        EXPECT_EQ(toBytes(*read), toInts(pixels.bytes));
    }
    // readImage's result (linear RGBA) is the same whichever codec wrote or read the file.
    const ImageRgba32f a = fromDecodedPixels(builtinByOiio);
    const ImageRgba32f b = fromDecodedPixels(decodeBuiltin(load(builtin)));
    const ImageRgba32f c = fromDecodedPixels(decodeOiio(oiio));
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        ASSERT_NEAR(a.pixels[i], b.pixels[i], 1e-6f) << i;
        ASSERT_NEAR(c.pixels[i], b.pixels[i], 1e-6f) << i;
    }
}

TEST_F(ImageCodecTest, ExrOfEitherCodecReadsBackBitIdenticallyWithTheOther) {
    ImageRgba32f image = testImage(23, 11);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> value(-5.0f, 1000.0f);
    for (float& p : image.pixels) p = value(rng);
    image.pixels[1] = 1e-30f;
    image.pixels[2] = 0.0f;
    const FilePixels pixels = toFilePixels(image, ImageFileKind::Exr, false);
    const fs::path builtin = save("builtin.exr", encodeBuiltin(pixels, ImageFileKind::Exr));
    const fs::path oiio = save("oiio.exr", encodeOiio(pixels, ImageFileKind::Exr, dir_ / "oiio.exr"));

    const DecodedPixels builtinByOiio = decodeOiio(builtin);
    const DecodedPixels oiioByBuiltin = decodeBuiltin(load(oiio));
    const DecodedPixels builtinByBuiltin = decodeBuiltin(load(builtin));
    for (const DecodedPixels* read : {&builtinByOiio, &oiioByBuiltin, &builtinByBuiltin}) {
        ASSERT_EQ(read->width, 23);
        ASSERT_EQ(read->height, 11);
        ASSERT_EQ(read->channels, 4);
        EXPECT_FALSE(read->integerSource);
        EXPECT_EQ(read->values, pixels.floats);
        EXPECT_EQ(fromDecodedPixels(*read).pixels, image.pixels);
    }
}

TEST_F(ImageCodecTest, HdrAndJpegOfTheBuiltinCodecReadWithOpenImageIo) {
    ImageRgba32f image = testImage(16, 8);
    for (float& p : image.pixels) p = std::abs(p) * 3.0f;
    const FilePixels hdr = toFilePixels(image, ImageFileKind::Hdr, false);
    const DecodedPixels hdrRead = decodeOiio(save("builtin.hdr", encodeBuiltin(hdr, ImageFileKind::Hdr)));
    ASSERT_EQ(hdrRead.channels, 3);
    ASSERT_EQ(hdrRead.values.size(), hdr.floats.size());
    for (size_t i = 0; i < hdr.floats.size(); i += 3) {
        const float largest = std::max({hdr.floats[i], hdr.floats[i + 1], hdr.floats[i + 2]});
        for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(hdrRead.values[i + c], hdr.floats[i + c], largest / 128.0f + 1e-6f) << i;
    }
    ImageRgba32f flat = image;
    for (float& p : flat.pixels) p = 0.3f; // JPEG is lossy: a flat image survives within a step or two
    const FilePixels jpeg = toFilePixels(flat, ImageFileKind::Jpeg, false);
    const DecodedPixels jpegRead = decodeOiio(save("builtin.jpg", encodeBuiltin(jpeg, ImageFileKind::Jpeg)));
    ASSERT_EQ(jpegRead.channels, 3);
    const std::vector<int> bytes = toBytes(jpegRead);
    for (size_t i = 0; i < bytes.size(); ++i) EXPECT_NEAR(bytes[i], int(jpeg.bytes[i]), 2) << i;
}

TEST_F(ImageCodecTest, BuiltinDecoderRefusesGarbageAndTruncatedFiles) {
    EXPECT_THROW(decodeBuiltin({'n', 'o', 't', ' ', 'a', 'n', ' ', 'i', 'm', 'a', 'g', 'e'}), std::runtime_error);
    EXPECT_THROW(decodeBuiltin({}), std::runtime_error);
    const FilePixels exr = toFilePixels(testImage(8, 8), ImageFileKind::Exr, false);
    std::vector<unsigned char> bytes = encodeBuiltin(exr, ImageFileKind::Exr);
    bytes.resize(bytes.size() / 2);
    EXPECT_THROW(decodeBuiltin(bytes), std::runtime_error);
    const FilePixels png = toFilePixels(testImage(8, 8), ImageFileKind::Png, false);
    bytes = encodeBuiltin(png, ImageFileKind::Png);
    bytes.resize(bytes.size() / 2);
    EXPECT_THROW(decodeBuiltin(bytes), std::runtime_error);
}

} // namespace
} // namespace chcrt::detail
