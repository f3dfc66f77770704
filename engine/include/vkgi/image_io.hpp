#pragma once
// Image files: linear HDR images as OpenEXR (lossless float RGB, for references and error
// analysis) and tone-mapped 8-bit sRGB PNG (for looking at). Every write is atomic: the data
// goes to a temporary file in the destination folder that is renamed over the target only
// once complete, so a failed write never leaves a partial or truncated output behind.
#include <cstdint>
#include <filesystem>

#include <glm/ext/vector_uint3_sized.hpp>
#include <glm/vec3.hpp>

#include "vkgi/hdr_image.hpp"
#include "vkgi/result.hpp"

namespace vkgi {

// How linear radiance (nits) becomes a displayable 8-bit sRGB value, per channel:
//   1. v = exposure * radiance                      (a plain multiplier, no auto-exposure)
//   2. curve:  Aces  -> Narkowicz's fit of the ACES filmic curve,
//                       f(v) = v(2.51v + 0.03) / (v(2.43v + 0.59) + 0.14), clamped to [0,1]
//              Clamp -> f(v) = clamp(v, 0, 1) (identity on [0,1]; for exact checks and masks)
//   3. sRGB OETF (IEC 61966-2-1): 12.92 f for f <= 0.0031308, else 1.055 f^(1/2.4) - 0.055
//   4. round to nearest of 0..255.
// Negative values map to 0. A pixel with any NaN/Inf channel is written as magenta (255,0,255)
// so broken pixels stand out instead of silently turning black or white.
struct ToneMap {
    enum class Curve { Aces, Clamp };
    float exposure = 1.0f;
    Curve curve = Curve::Aces;
};

// The exposure that puts `image` at middle grey: 0.18 over the log-average luminance of its lit
// pixels (Reinhard's key; pixels darker than 1e-6 nits, the background, and non-finite ones are
// left out), clamped to 1e-9..1e9; 1 for an image with no lit pixel.
float autoExposure(const HdrImage& image);

// The 8-bit sRGB value that writePng stores for one linear pixel (see ToneMap).
glm::u8vec3 toneMapPixel(const glm::vec3& linear, const ToneMap& toneMap = {});

// Writes a float RGB (channels R, G, B, 32-bit float, ZIP compression) OpenEXR file.
Result<void> writeExr(const std::filesystem::path& path, const HdrImage& image);

// Reads an OpenEXR file's R, G, B channels as float (half channels are converted; a missing
// channel is an error). The data window becomes the image.
Result<HdrImage> readExr(const std::filesystem::path& path);

// Writes an 8-bit RGB PNG, tone-mapped as described by ToneMap. When `nonFinite` is given it
// receives the number of pixels that had a NaN/Inf channel (written as magenta).
Result<void> writePng(const std::filesystem::path& path, const HdrImage& image, const ToneMap& toneMap = {},
                      uint64_t* nonFinite = nullptr);

} // namespace vkgi
