#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "vkgi/image_metrics.hpp"

using namespace vkgi;

TEST(ImageMetrics, HandComputedExample) {
    // 2x1 images; per channel differences and reference values:
    //   pixel 0: t = (1, 2, 3),  r = (1, 1, 1)   -> d = (0, 1, 2)
    //   pixel 1: t = (0, 0, 0),  r = (0, 2, 0.5) -> d = (0, -2, -0.5)
    // sum d^2 = 0 + 1 + 4 + 0 + 4 + 0.25 = 9.25 -> RMSE = sqrt(9.25 / 6)
    // relMSE (eps 0.01) = [0 + 1/1.01 + 4/1.01 + 0 + 4/4.01 + 0.25/0.26] / 6
    HdrImage t(2, 1), r(2, 1);
    t.at(0, 0) = {1, 2, 3};
    r.at(0, 0) = {1, 1, 1};
    t.at(1, 0) = {0, 0, 0};
    r.at(1, 0) = {0, 2, 0.5f};
    Result<ErrorMetrics> m = compareImages(t, r);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_DOUBLE_EQ(m->rmse, std::sqrt(9.25 / 6.0));
    const double eps = double(0.01f); // the float default, widened exactly as the code does
    EXPECT_NEAR(m->relMse, (1.0 / (1 + eps) + 4.0 / (1 + eps) + 4.0 / (4 + eps) + 0.25 / (0.25 + eps)) / 6.0, 1e-15);
    EXPECT_EQ(m->nonFinite, 0u);

    EXPECT_FALSE(compareImages(t, r, 0.0f).ok()); // 0/0 on the black reference channel
}

TEST(ImageMetrics, IdenticalImagesHaveZeroError) {
    HdrImage a(3, 3);
    for (size_t i = 0; i < a.pixels.size(); ++i)
        a.pixels[i] = glm::vec3(float(i), 0.5f * float(i), 1e6f);
    Result<ErrorMetrics> m = compareImages(a, a);
    ASSERT_TRUE(m.ok());
    EXPECT_EQ(m->relMse, 0.0);
    EXPECT_EQ(m->rmse, 0.0);
}

TEST(ImageMetrics, RelativeErrorIsScaleInvariantWhereEpsilonIsNegligible) {
    // 10% error everywhere on a bright reference: relMSE ~= 0.01 whatever the brightness.
    HdrImage r(4, 4), t(4, 4);
    for (auto& p : r.pixels)
        p = glm::vec3(1000.0f);
    for (auto& p : t.pixels)
        p = glm::vec3(1100.0f);
    Result<ErrorMetrics> m = compareImages(t, r);
    ASSERT_TRUE(m.ok());
    EXPECT_NEAR(m->relMse, 0.01, 1e-8); // eps/r^2 = 1e-8 relative change
    EXPECT_NEAR(m->rmse, 100.0, 1e-9);
}

TEST(ImageMetrics, NonFiniteTestPixelsAreCountedAndPoisonTheMetrics) {
    HdrImage r(3, 2), t(3, 2);
    t.at(0, 0).x = std::numeric_limits<float>::quiet_NaN();
    t.at(2, 1).z = std::numeric_limits<float>::infinity();
    t.at(1, 1) = {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::infinity(), 0};
    Result<ErrorMetrics> m = compareImages(t, r);
    ASSERT_TRUE(m.ok()) << m.error().message;
    EXPECT_EQ(m->nonFinite, 3u);
    EXPECT_TRUE(std::isinf(m->relMse) && m->relMse > 0);
    EXPECT_TRUE(std::isinf(m->rmse) && m->rmse > 0);
    EXPECT_EQ(countNonFinite(t), 3u);
}

TEST(ImageMetrics, BadInputsAreErrors) {
    HdrImage a(2, 2), b(2, 3);
    EXPECT_FALSE(compareImages(a, b).ok());
    EXPECT_FALSE(compareImages(HdrImage{}, HdrImage{}).ok());
    HdrImage badRef(2, 2);
    badRef.at(1, 1).y = std::numeric_limits<float>::quiet_NaN();
    Result<ErrorMetrics> m = compareImages(a, badRef);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find("reference"), std::string::npos);
    EXPECT_FALSE(subtract(a, b).ok());
}

TEST(ImageMetrics, SubtractIsPerPixel) {
    HdrImage a(2, 1), b(2, 1);
    a.at(0, 0) = {5, 6, 7};
    b.at(0, 0) = {1, 2, 3};
    a.at(1, 0) = {0.5f, 0, -1};
    b.at(1, 0) = {0.25f, 1, -1};
    Result<HdrImage> d = subtract(a, b);
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(d->at(0, 0), glm::vec3(4, 4, 4));
    EXPECT_EQ(d->at(1, 0), glm::vec3(0.25f, -1, 0));
}

// The constant-ambient baseline: on the surface pixels the relMSE-optimal constant, per channel,
// in closed form; background pixels keep the direct image and do not pull the constant.
TEST(ImageMetrics, BestAmbientIsTheRelMseOptimalConstant) {
    HdrImage direct(3, 1), ref(3, 1);
    direct.pixels = {glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(0.0f)};
    ref.pixels = {glm::vec3(2.0f), glm::vec3(4.0f), glm::vec3(0.0f)};
    std::vector<bool> surface = surfacePixels(direct, ref);
    ASSERT_EQ(surface, (std::vector<bool>{true, true, false}));
    HdrImage a = bestAmbient(direct, ref, surface, 0.01f);
    // c = sum w (r - d) / sum w, w = 1 / (r^2 + eps): (1/4.01 * 1 + 1/16.01 * 3) / (1/4.01 + 1/16.01).
    const double w1 = 1.0 / 4.01, w2 = 1.0 / 16.01, c = (w1 * 1.0 + w2 * 3.0) / (w1 + w2);
    EXPECT_NEAR(a.pixels[0].x, 1.0 + c, 1e-5);
    EXPECT_NEAR(a.pixels[1].y, 1.0 + c, 1e-5);
    EXPECT_EQ(a.pixels[2], glm::vec3(0.0f));
    // Optimal: a nudge either way raises relMSE.
    auto at = [&](double shift) {
        HdrImage t = a;
        for (int i = 0; i < 2; ++i)
            t.pixels[i] += glm::vec3(float(shift));
        return compareImages(t, ref)->relMse;
    };
    EXPECT_LT(at(0.0), at(0.01));
    EXPECT_LT(at(0.0), at(-0.01));
}

// The smoothness measure: zero for any linear ramp (the discrete Laplacian of a plane is 0),
// exactly 8 for stripes 2 pixels wide at stride 2 (every stencil sees the opposite value at
// +-2 in x: |L| = 2 on every pixel, luminance^2 = 1 on half of them), independent of brightness,
// and blind to pixels outside the mask.
TEST(ImageMetrics, LaplacianEnergyOfRampsStripesAndMasks) {
    HdrImage ramp(20, 12);
    for (uint32_t y = 0; y < ramp.height; ++y)
        for (uint32_t x = 0; x < ramp.width; ++x)
            ramp.at(x, y) = glm::vec3(1.0f + 0.25f * float(x) + 0.5f * float(y));
    EXPECT_NEAR(laplacianEnergy(ramp, {}), 0.0, 1e-12);

    HdrImage stripes(20, 12);
    for (uint32_t y = 0; y < stripes.height; ++y)
        for (uint32_t x = 0; x < stripes.width; ++x)
            stripes.at(x, y) = glm::vec3((x / 2) % 2 == 0 ? 1.0f : 0.0f);
    EXPECT_NEAR(laplacianEnergy(stripes, {}), 8.0, 1e-9);
    HdrImage bright = stripes;
    for (glm::vec3& p : bright.pixels)
        p *= 1000.0f;
    EXPECT_NEAR(laplacianEnergy(bright, {}), 8.0, 1e-9);

    // The stripes kept only in the right half, which the mask leaves out; the left half is
    // constant, so every stencil inside the mask gives 0.
    HdrImage half = stripes;
    std::vector<bool> mask(half.pixels.size(), false);
    for (uint32_t y = 0; y < half.height; ++y)
        for (uint32_t x = 0; x < half.width; ++x) {
            mask[size_t(y) * half.width + x] = x < 10;
            if (x < 10)
                half.at(x, y) = glm::vec3(2.0f);
        }
    EXPECT_NEAR(laplacianEnergy(half, mask), 0.0, 1e-12);
    EXPECT_GT(laplacianEnergy(half, {}), 0.0); // without the mask the stripes count
    EXPECT_EQ(laplacianEnergy(HdrImage(20, 12), {}), 0.0); // black: no energy to compare with
}
