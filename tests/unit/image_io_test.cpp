#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

// stb_image (Debian libstb-dev) decodes the PNGs back; static so it cannot clash with anything.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "vkgi/image_io.hpp"
#include "support/test_env.hpp"

using namespace vkgi;
namespace fs = std::filesystem;

namespace {

fs::path freshDir(const std::string& name) { return test::freshOutputDir(fs::path("image_io") / name); }

HdrImage gradient(uint32_t w, uint32_t h) {
    HdrImage img(w, h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            img.at(x, y) = {float(x) * 0.37f + 1e-7f, float(y) * 1234.5f, float(x * y) - 3.25f};
    return img;
}

} // namespace

TEST(ImageIo, ExrRoundTripIsBitExact) {
    fs::path dir = freshDir("exr_roundtrip");
    HdrImage img = gradient(13, 7); // odd sizes catch stride mistakes
    img.at(3, 2) = {std::numeric_limits<float>::denorm_min(), 6.5e4f, 3.0e38f};
    fs::path file = dir / "a.exr";
    ASSERT_TRUE(writeExr(file, img).ok());
    EXPECT_EQ(test::countEntries(dir), 1u); // no temporary left beside it
    Result<HdrImage> back = readExr(file);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->width, 13u);
    ASSERT_EQ(back->height, 7u);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(back->pixels[i][c], img.pixels[i][c]) << i << " " << c;
}

TEST(ImageIo, ExrOverwriteReplacesWholeFile) {
    fs::path dir = freshDir("exr_overwrite");
    fs::path file = dir / "a.exr";
    ASSERT_TRUE(writeExr(file, gradient(64, 64)).ok());
    ASSERT_TRUE(writeExr(file, gradient(2, 3)).ok());
    Result<HdrImage> back = readExr(file);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->width, 2u);
    EXPECT_EQ(back->height, 3u);
}

TEST(ImageIo, ReadExrErrorsNameTheFile) {
    fs::path dir = freshDir("exr_bad");
    fs::path missing = dir / "missing.exr";
    Result<HdrImage> r = readExr(missing);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(missing.string()), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);

    fs::path garbage = dir / "garbage.exr";
    std::ofstream(garbage) << "this is not an OpenEXR file, just some text";
    r = readExr(garbage);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(garbage.string()), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);

    // A real EXR cut in half: the header parses, the pixel data does not.
    fs::path good = dir / "good.exr", cut = dir / "cut.exr";
    ASSERT_TRUE(writeExr(good, gradient(64, 64)).ok());
    auto size = fs::file_size(good);
    fs::copy_file(good, cut);
    fs::resize_file(cut, size / 2);
    r = readExr(cut);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(cut.string()), std::string::npos) << r.error().message;
}

TEST(ImageIo, WriteIntoMissingFolderFailsAndLeavesNothing) {
    fs::path dir = freshDir("missing_folder");
    fs::path target = dir / "no_such_folder" / "out.exr";
    Result<void> r = writeExr(target, gradient(4, 4));
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(target.string()), std::string::npos) << r.error().message;
    fs::path png = dir / "no_such_folder" / "out.png";
    Result<void> p = writePng(png, gradient(4, 4));
    ASSERT_FALSE(p.ok());
    EXPECT_NE(p.error().message.find(png.string()), std::string::npos) << p.error().message;
    EXPECT_FALSE(fs::exists(dir / "no_such_folder"));
    EXPECT_EQ(test::countEntries(dir), 0u);
}

TEST(ImageIo, WriteUnderAFileFailsAndLeavesNothing) {
    // A path whose parent is a regular file cannot be created, even by root (which ignores
    // read-only folder permissions, so chmod would not make this test fail-safe).
    fs::path dir = freshDir("not_a_folder");
    std::ofstream(dir / "plain") << "x";
    for (const char* name : {"plain/out.exr", "plain/out.png"}) {
        fs::path target = dir / name;
        Result<void> r = target.extension() == ".exr" ? writeExr(target, gradient(4, 4))
                                                      : writePng(target, gradient(4, 4));
        ASSERT_FALSE(r.ok()) << name;
        EXPECT_NE(r.error().message.find(target.string()), std::string::npos) << r.error().message;
    }
    EXPECT_EQ(test::countEntries(dir), 1u);
    EXPECT_EQ(fs::file_size(dir / "plain"), 1u);
}

TEST(ImageIo, EmptyImageIsAnError) {
    fs::path dir = freshDir("empty");
    EXPECT_FALSE(writeExr(dir / "e.exr", HdrImage{}).ok());
    EXPECT_FALSE(writePng(dir / "e.png", HdrImage{}).ok());
    EXPECT_EQ(test::countEntries(dir), 0u);
}

TEST(ImageIo, ToneMapKnownValues) {
    // Expected bytes computed by hand from the formulas documented in image_io.hpp.
    ToneMap clamp{1.0f, ToneMap::Curve::Clamp};
    EXPECT_EQ(toneMapPixel({0.0f, 1.0f, 0.5f}, clamp), glm::u8vec3(0, 255, 188)); // 0.5 -> 187.52
    EXPECT_EQ(toneMapPixel({0.18f, 0.001f, -4.0f}, clamp), glm::u8vec3(118, 3, 0)); // 117.65; 3.29 (linear toe)
    EXPECT_EQ(toneMapPixel({0.25f, 7.0f, 0.0f}, ToneMap{2.0f, ToneMap::Curve::Clamp}), glm::u8vec3(188, 255, 0));
    ToneMap aces{}; // default: exposure 1, ACES fit
    // ACES fit: f(1) = 2.54/3.16 = 0.80380 -> 231.60; f(0.18) = 0.26690 -> 141.13; f(10) > 1 -> 255.
    EXPECT_EQ(toneMapPixel({1.0f, 0.18f, 10.0f}, aces), glm::u8vec3(232, 141, 255));
    EXPECT_EQ(toneMapPixel({1e30f, 0.0f, 0.0f}, ToneMap{1e30f}), glm::u8vec3(255, 0, 0)); // overflow saturates
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(toneMapPixel({nan, 0.0f, 0.0f}, aces), glm::u8vec3(255, 0, 255));
    EXPECT_EQ(toneMapPixel({0.0f, -inf, 0.0f}, aces), glm::u8vec3(255, 0, 255));
}

TEST(ImageIo, PngDecodesToToneMappedValuesAndFlagsNonFinite) {
    fs::path dir = freshDir("png");
    HdrImage img(5, 3);
    for (uint32_t y = 0; y < 3; ++y)
        for (uint32_t x = 0; x < 5; ++x)
            img.at(x, y) = {0.1f * float(x), 0.5f * float(y), 0.25f};
    img.at(1, 1) = {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f};
    img.at(4, 2) = {0.0f, std::numeric_limits<float>::infinity(), 0.0f};
    ToneMap tm{1.0f, ToneMap::Curve::Clamp};
    fs::path file = dir / "img.png";
    uint64_t bad = 99;
    ASSERT_TRUE(writePng(file, img, tm, &bad).ok());
    EXPECT_EQ(bad, 2u);
    EXPECT_EQ(test::countEntries(dir), 1u);

    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(file.c_str(), &w, &h, &n, 3);
    ASSERT_NE(data, nullptr);
    ASSERT_EQ(w, 5);
    ASSERT_EQ(h, 3);
    for (uint32_t y = 0; y < 3; ++y)
        for (uint32_t x = 0; x < 5; ++x) {
            glm::u8vec3 want = toneMapPixel(img.at(x, y), tm);
            const unsigned char* p = data + 3 * (y * 5 + x); // row 0 of the PNG = row 0 of the image
            EXPECT_EQ(p[0], want.x) << x << "," << y;
            EXPECT_EQ(p[1], want.y) << x << "," << y;
            EXPECT_EQ(p[2], want.z) << x << "," << y;
        }
    EXPECT_EQ(data[3 * (1 * 5 + 1) + 0], 255);
    EXPECT_EQ(data[3 * (1 * 5 + 1) + 1], 0);
    EXPECT_EQ(data[3 * (1 * 5 + 1) + 2], 255);
    stbi_image_free(data);
}

// Middle grey for the log-average of the lit pixels: background, NaN/Inf and an all-black image
// do not pull it.
TEST(ImageIo, AutoExposurePutsTheLogAverageAtMiddleGrey) {
    HdrImage img(4, 1);
    img.pixels = {glm::vec3(2.0f), glm::vec3(8.0f), glm::vec3(0.0f), glm::vec3(std::nanf(""))};
    // log-average of 2 and 8 is 4 (luminance of grey is the grey value): 0.18 / 4.
    EXPECT_NEAR(autoExposure(img), 0.045f, 1e-6f);
    HdrImage black(2, 2);
    EXPECT_EQ(autoExposure(black), 1.0f);
    HdrImage sun(1, 1);
    sun.pixels[0] = glm::vec3(1e30f); // clamped, not 0
    EXPECT_EQ(autoExposure(sun), 1e-9f);
}
