#pragma once
// Whole-image statistics the tests assert on (engine/image_metrics.hpp has the error metrics).
#include <vector>

#include "engine/hdr_image.hpp"

namespace vkgi::test {

// Sum of every channel of every pixel, accumulated in double.
double sumRgb(const HdrImage& image);

// Mean of all channels over all pixels (sumRgb / (3 x pixels)); for grey images, the mean
// radiance. An empty image has no mean: NaN, so that no comparison with it passes.
double meanRgb(const HdrImage& image);

// direct + c with the per-channel constant c that minimises relMSE (epsilon `eps`) against `ref`
// over the `surface` pixels: d/dc sum w (d + c - r)^2 = 0 with w = 1 / (r^2 + eps) gives
// c = sum w (r - d) / sum w. Pixels without a surface keep `direct` (an ambient term lights
// surfaces; adding c to a black sky, weight 1 / eps, would pull c to ~0).
HdrImage bestAmbient(const HdrImage& direct, const HdrImage& ref, const std::vector<bool>& surface,
                     float eps = 0.01f);

// Pixels that show a surface: light in either image (the scenes have no sky light, so a pixel
// black in both is background, and a surface black in both adds nothing to either error).
std::vector<bool> surfacePixels(const HdrImage& a, const HdrImage& b);

} // namespace vkgi::test
