#pragma once
// Error of a rendered image against a reference, on linear HDR radiance (no tone mapping):
// the figures vkgi-bench plots against run time.
#include <cstdint>
#include <vector>

#include "vkgi/hdr_image.hpp"
#include "vkgi/result.hpp"

namespace vkgi {

struct ErrorMetrics {
    // Relative MSE as in the rendering literature (e.g. Rousselle et al. 2011):
    // mean over pixels and RGB channels of (t - r)^2 / (r^2 + epsilon).
    double relMse = 0.0;
    // Root mean squared error over pixels and RGB channels, in nits: sqrt(mean (t - r)^2).
    double rmse = 0.0;
    // Test pixels with a NaN/Inf channel. When non-zero, relMse and rmse are +inf: a broken
    // pixel is an error, never silently dropped from the mean.
    uint64_t nonFinite = 0;
};

// Compares `test` against `ref`. Errors (one line) when the sizes differ, the images are
// empty, or the reference itself has a non-finite pixel (a reference must be clean).
// `epsilon` (> 0) keeps relMSE bounded where the reference is black; 0.01 is the usual choice.
Result<ErrorMetrics> compareImages(const HdrImage& test, const HdrImage& ref, float epsilon = 0.01f);

// Per-pixel a - b (e.g. indirect-only = full - direct). Errors when the sizes differ.
Result<HdrImage> subtract(const HdrImage& a, const HdrImage& b);

// Number of pixels with a NaN/Inf channel.
uint64_t countNonFinite(const HdrImage& image);

// The baseline every GI technique must beat, a constant ambient term: direct + c with the
// per-channel constant c that minimises relMSE (epsilon `eps`) against `ref` over the `surface`
// pixels: d/dc sum w (d + c - r)^2 = 0 with w = 1 / (r^2 + eps) gives
// c = sum w (r - d) / sum w. Pixels without a surface keep `direct` (an ambient term lights
// surfaces; adding c to a black sky, weight 1 / eps, would pull c to ~0).
HdrImage bestAmbient(const HdrImage& direct, const HdrImage& ref, const std::vector<bool>& surface,
                     float eps = 0.01f);

// High-frequency energy of `image` over the pixels `mask` marks (issue #15's smoothness
// measure): the mean squared discrete Laplacian of luminance at a stride of `step` pixels,
// 4 Y(p) - Y(p +- step x) - Y(p +- step y), over the mean squared luminance of the same pixels,
// so the number does not depend on the image's brightness. Pixels whose stencil leaves the
// image or the mask are skipped; 0 when none is left or the image is black there.
double laplacianEnergy(const HdrImage& image, const std::vector<bool>& mask, uint32_t step = 2);

// Pixels that show a surface: light in either image (the scenes have no sky light, so a pixel
// black in both is background, and a surface black in both adds nothing to either error).
std::vector<bool> surfacePixels(const HdrImage& a, const HdrImage& b);

} // namespace vkgi
