#pragma once
// Whole-image statistics the tests assert on (vkgi/image_metrics.hpp has the error metrics).
#include "vkgi/hdr_image.hpp"

namespace vkgi::test {

// Sum of every channel of every pixel, accumulated in double.
double sumRgb(const HdrImage& image);

// Mean of all channels over all pixels (sumRgb / (3 x pixels)); for grey images, the mean
// radiance. An empty image has no mean: NaN, so that no comparison with it passes.
double meanRgb(const HdrImage& image);

} // namespace vkgi::test
