#include "renderer/core/error.h"
#include "renderer/core/image_io.h"

#include <gtest/gtest.h>

#include <stb_image_write.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>

namespace chcrt {
namespace {

namespace fs = std::filesystem;

class ImageIoTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("chcrt_image_io_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // Number of entries in the test directory (to prove nothing, not even a temp file, was left behind).
    size_t entryCount() const {
        return size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
    }

    fs::path dir_;
};

ImageRgba32f gradientImage(int width, int height) {
    ImageRgba32f image;
    image.width = width;
    image.height = height;
    image.pixels.resize(size_t(width) * size_t(height) * 4);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            float* p = image.at(x, y);
            p[0] = float(x) / float(width - 1);
            p[1] = float(y) / float(height - 1);
            p[2] = float((x * 7 + y * 3) % 11) / 10.0f;
            p[3] = float((x + y) % 4) / 3.0f;
        }
    }
    return image;
}

ImageRgba32f flatImage(int width, int height, float value) {
    ImageRgba32f image;
    image.width = width;
    image.height = height;
    image.pixels.assign(size_t(width) * size_t(height) * 4, value);
    return image;
}

float toSrgb(float linear) {
    linear = std::clamp(linear, 0.0f, 1.0f);
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

TEST_F(ImageIoTest, PngRoundTripWithinOneStepOfEightBits) {
    const ImageRgba32f image = gradientImage(17, 9);
    const fs::path file = dir_ / "gradient.png";
    writeImage(file, image);
    const ImageRgba32f read = readImage(file);
    ASSERT_EQ(read.width, image.width);
    ASSERT_EQ(read.height, image.height);
    for (size_t i = 0; i < image.pixels.size(); i += 4) {
        for (size_t c = 0; c < 3; ++c) {
            // Quantisation happens in display space: half a step there, plus float noise.
            EXPECT_NEAR(toSrgb(read.pixels[i + c]), toSrgb(image.pixels[i + c]), 0.5f / 255.0f + 1e-5f) << i;
        }
        EXPECT_NEAR(read.pixels[i + 3], image.pixels[i + 3], 0.5f / 255.0f + 1e-6f) << "alpha is linear";
    }
    EXPECT_EQ(entryCount(), 1u);
}

TEST_F(ImageIoTest, PngEncodesLinearToSrgbUnlessAlreadyEncoded) {
    const fs::path file = dir_ / "mid.png";
    writeImage(file, flatImage(2, 2, 0.5f));
    EXPECT_NEAR(readImage(file).pixels[0], 0.5f, 0.003f);
    // Stored as the display value 128/255, which decodes to linear ~0.2158.
    writeImage(file, flatImage(2, 2, 0.5f), true);
    EXPECT_NEAR(readImage(file).pixels[0], 0.2158f, 0.002f);
}

TEST_F(ImageIoTest, ExrRoundTripIsExact) {
    ImageRgba32f image = flatImage(13, 7, 0.0f);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(-2.0f, 50.0f);
    for (float& p : image.pixels) {
        p = value(rng);
    }
    image.pixels[5] = 1e-7f;
    const fs::path file = dir_ / "random.exr";
    writeImage(file, image);
    const ImageRgba32f read = readImage(file);
    ASSERT_EQ(read.width, image.width);
    ASSERT_EQ(read.height, image.height);
    EXPECT_EQ(read.pixels, image.pixels);
}

TEST_F(ImageIoTest, ExtensionIsCaseInsensitiveAndJpegDropsAlpha) {
    const fs::path file = dir_ / "flat.JPG";
    ImageRgba32f image = flatImage(16, 16, 0.25f);
    writeImage(file, image);
    const ImageRgba32f read = readImage(file);
    EXPECT_NEAR(read.pixels[0], 0.25f, 0.01f);
    EXPECT_EQ(read.pixels[3], 1.0f);
    writeImage(dir_ / "upper.EXR", image);
    EXPECT_EQ(readImage(dir_ / "upper.EXR").pixels, image.pixels);
}

TEST_F(ImageIoTest, HdrRoundTripWithinRgbePrecision) {
    ImageRgba32f image = gradientImage(9, 5);
    image.at(3, 2)[0] = 40.0f;
    const fs::path file = dir_ / "radiance.hdr";
    writeImage(file, image);
    const ImageRgba32f read = readImage(file);
    ASSERT_EQ(read.width, image.width);
    ASSERT_EQ(read.height, image.height);
    for (size_t i = 0; i < image.pixels.size(); i += 4) {
        const float largest = std::max({image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]});
        for (size_t c = 0; c < 3; ++c) {
            // RGBE: 8 mantissa bits shared under the largest channel's exponent.
            EXPECT_NEAR(read.pixels[i + c], image.pixels[i + c], largest / 128.0f + 1e-6f) << i;
        }
        EXPECT_EQ(read.pixels[i + 3], 1.0f) << "HDR stores no alpha";
    }
}

// TIFF goes through OpenImageIO; a build without it refuses the extension before anything is written.
TEST_F(ImageIoTest, TiffNeedsOpenImageIo) {
    const fs::path file = dir_ / "float.tif";
    const ImageRgba32f image = flatImage(3, 2, 0.75f);
    if (std::string(imageCodecName()) == "OpenImageIO") {
        writeImage(file, image);
        EXPECT_EQ(readImage(file).pixels, image.pixels);
        return;
    }
    try {
        checkImageOutputPath(file);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("OpenImageIO"), std::string::npos) << e.what();
    }
    EXPECT_THROW(writeImage(file, image), InputError);
    EXPECT_EQ(entryCount(), 0u);
}

TEST_F(ImageIoTest, OverwritesExistingFile) {
    const fs::path file = dir_ / "twice.exr";
    writeImage(file, flatImage(3, 3, 1.0f));
    writeImage(file, flatImage(3, 3, 2.0f));
    EXPECT_EQ(readImage(file).pixels[0], 2.0f);
    EXPECT_EQ(entryCount(), 1u);
}

TEST_F(ImageIoTest, MissingDirectoryThrowsAndLeavesNothing) {
    const fs::path file = dir_ / "no_such_dir" / "out.png";
    try {
        writeImage(file, flatImage(2, 2, 0.5f));
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
    EXPECT_EQ(entryCount(), 0u);
}

TEST_F(ImageIoTest, UnsupportedExtensionThrowsAndLeavesNothing) {
    for (const char* name : {"out.xyz", "out"}) {
        try {
            writeImage(dir_ / name, flatImage(2, 2, 0.5f));
            ADD_FAILURE() << "no error for " << name;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("unsupported image extension"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(entryCount(), 0u);
}

TEST_F(ImageIoTest, FailedRenameRemovesTempFile) {
    // The target is a directory: the temp file is written, the rename fails, and the temp must go.
    fs::create_directory(dir_ / "taken.png");
    EXPECT_THROW(writeImage(dir_ / "taken.png", flatImage(2, 2, 0.5f)), InputError);
    EXPECT_EQ(entryCount(), 1u);
    EXPECT_FALSE(fs::exists(dir_ / "taken.tmp.png"));
}

TEST_F(ImageIoTest, InvalidImageThrows) {
    ImageRgba32f image = flatImage(2, 2, 0.5f);
    image.pixels.pop_back();
    EXPECT_THROW(writeImage(dir_ / "bad.png", image), InputError);
    EXPECT_EQ(entryCount(), 0u);
}

TEST_F(ImageIoTest, ReadErrorsAreInputErrors) {
    EXPECT_THROW(readImage(dir_ / "missing.png"), InputError);
    std::ofstream(dir_ / "garbage.png") << "not an image";
    EXPECT_THROW(readImage(dir_ / "garbage.png"), InputError);
}

// Writes raw 8-bit pixels (2 x 1) with `channels` channels directly, through stb_image_write.
void writeRawPng(const fs::path& file, int channels, const std::vector<uint8_t>& pixels) {
    ASSERT_NE(stbi_write_png(file.c_str(), 2, 1, channels, pixels.data(), 2 * channels), 0);
}

TEST_F(ImageIoTest, ReadExpandsGrayAndGrayAlpha) {
    writeRawPng(dir_ / "gray.png", 1, {0, 255});
    ImageRgba32f gray = readImage(dir_ / "gray.png");
    EXPECT_EQ(std::vector<float>(gray.pixels.begin(), gray.pixels.end()),
              std::vector<float>({0, 0, 0, 1, 1, 1, 1, 1}));
    writeRawPng(dir_ / "gray_alpha.png", 2, {255, 0, 0, 255});
    ImageRgba32f grayAlpha = readImage(dir_ / "gray_alpha.png");
    EXPECT_EQ(std::vector<float>(grayAlpha.pixels.begin(), grayAlpha.pixels.end()),
              std::vector<float>({1, 1, 1, 0, 0, 0, 0, 1}));
}

TEST(CompareImages, IdenticalImages) {
    const ImageRgba32f image = gradientImage(8, 8);
    const ImageDifference d = compareImages(image, image);
    EXPECT_EQ(d.differingPixels, 0u);
    EXPECT_EQ(d.meanAbsoluteError, 0.0);
    EXPECT_EQ(d.maxAbsoluteError, 0.0);
    EXPECT_EQ(d.psnrDb, std::numeric_limits<double>::infinity());
}

TEST(CompareImages, SinglePixelChange) {
    const ImageRgba32f a = flatImage(4, 4, 0.5f);
    ImageRgba32f b = a;
    b.at(1, 2)[0] = 0.75f;
    const ImageDifference d = compareImages(a, b);
    EXPECT_EQ(d.differingPixels, 1u);
    EXPECT_DOUBLE_EQ(d.maxAbsoluteError, 0.25);
    EXPECT_DOUBLE_EQ(d.meanAbsoluteError, 0.25 / 48.0);             // 16 pixels x 3 channels
    EXPECT_NEAR(d.psnrDb, 10.0 * std::log10(48.0 / 0.0625), 1e-12); // MSE = 0.25^2 / 48
    EXPECT_EQ(compareImages(a, b, 0.3f).differingPixels, 0u);
    EXPECT_EQ(compareImages(a, b, 0.2f).differingPixels, 1u);
}

TEST(CompareImages, ClampsAndIgnoresAlpha) {
    ImageRgba32f a = flatImage(2, 2, 1.0f);
    ImageRgba32f b = a;
    b.at(0, 0)[0] = 5.0f;  // clamps to 1
    b.at(1, 0)[3] = 0.0f;  // alpha
    b.at(0, 1)[1] = -1.0f; // clamps to 0: a real difference of 1
    const ImageDifference d = compareImages(a, b);
    EXPECT_EQ(d.differingPixels, 1u);
    EXPECT_DOUBLE_EQ(d.maxAbsoluteError, 1.0);
    EXPECT_DOUBLE_EQ(d.meanAbsoluteError, 1.0 / 12.0);
}

TEST(CompareImages, SizeMismatchThrows) {
    EXPECT_THROW(compareImages(flatImage(2, 2, 0.0f), flatImage(2, 3, 0.0f)), InputError);
}

// bench --reference-supersample: each output pixel is the mean of its factor x factor block, in every channel.
TEST(BoxFilterDown, AveragesEachBlock) {
    ImageRgba32f large = flatImage(4, 2, 0.0f);
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 4; ++x) {
            for (int c = 0; c < 4; ++c) large.at(x, y)[c] = float(10 * (y * 4 + x) + c);
        }
    }
    const ImageRgba32f small = boxFilterDown(large, 2);
    ASSERT_EQ(small.width, 2);
    ASSERT_EQ(small.height, 1);
    for (int c = 0; c < 4; ++c) {
        EXPECT_FLOAT_EQ(small.at(0, 0)[c], float((0 + 10 + 40 + 50) / 4 + c)) << c; // pixels (0,0) (1,0) (0,1) (1,1)
        EXPECT_FLOAT_EQ(small.at(1, 0)[c], float((20 + 30 + 60 + 70) / 4 + c)) << c;
    }
    EXPECT_EQ(boxFilterDown(large, 1).pixels, large.pixels);
    EXPECT_THROW(boxFilterDown(large, 3), std::invalid_argument);
    EXPECT_THROW(boxFilterDown(large, 0), std::invalid_argument);
}

} // namespace
} // namespace chcrt
