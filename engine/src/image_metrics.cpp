#include "vkgi/image_metrics.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace vkgi {

namespace {

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

std::string sizeText(const HdrImage& img) { return std::to_string(img.width) + "x" + std::to_string(img.height); }

bool consistent(const HdrImage& img) { return img.pixels.size() == size_t(img.width) * img.height; }

} // namespace

uint64_t countNonFinite(const HdrImage& image) {
    uint64_t n = 0;
    for (const glm::vec3& p : image.pixels)
        n += finite(p) ? 0 : 1;
    return n;
}

Result<ErrorMetrics> compareImages(const HdrImage& test, const HdrImage& ref, float epsilon) {
    if (test.width != ref.width || test.height != ref.height)
        return makeError("compareImages: size mismatch, test " + sizeText(test) + " vs reference " + sizeText(ref));
    if (ref.empty() || !consistent(test) || !consistent(ref))
        return makeError("compareImages: empty or inconsistent image (" + sizeText(ref) + ")");
    if (!(epsilon > 0.0f) || !std::isfinite(epsilon)) // 0 would divide 0 by 0 on black reference pixels
        return makeError("compareImages: epsilon must be finite and > 0");
    if (uint64_t bad = countNonFinite(ref); bad > 0)
        return makeError("compareImages: reference has " + std::to_string(bad) + " non-finite pixels");

    ErrorMetrics m;
    // Double accumulation: 2^28 float terms summed in float would lose the small errors.
    double sumSq = 0.0, sumRel = 0.0;
    for (size_t i = 0; i < ref.pixels.size(); ++i) {
        const glm::vec3& t = test.pixels[i];
        const glm::vec3& r = ref.pixels[i];
        if (!finite(t)) {
            ++m.nonFinite;
            continue;
        }
        for (int c = 0; c < 3; ++c) {
            double d = double(t[c]) - double(r[c]);
            sumSq += d * d;
            sumRel += d * d / (double(r[c]) * double(r[c]) + double(epsilon));
        }
    }
    if (m.nonFinite > 0) {
        m.relMse = m.rmse = std::numeric_limits<double>::infinity();
        return m;
    }
    const double n = 3.0 * double(ref.pixels.size());
    m.relMse = sumRel / n;
    m.rmse = std::sqrt(sumSq / n);
    return m;
}

Result<HdrImage> subtract(const HdrImage& a, const HdrImage& b) {
    if (a.width != b.width || a.height != b.height || !consistent(a) || !consistent(b))
        return makeError("subtract: size mismatch, " + sizeText(a) + " vs " + sizeText(b));
    HdrImage out(a.width, a.height);
    for (size_t i = 0; i < a.pixels.size(); ++i)
        out.pixels[i] = a.pixels[i] - b.pixels[i];
    return out;
}

HdrImage bestAmbient(const HdrImage& direct, const HdrImage& ref, const std::vector<bool>& surface, float eps) {
    glm::dvec3 num(0.0), den(0.0);
    for (size_t i = 0; i < ref.pixels.size(); ++i)
        for (int k = 0; k < 3 && surface[i]; ++k) {
            double r = ref.pixels[i][k];
            double w = 1.0 / (r * r + eps);
            num[k] += w * (r - direct.pixels[i][k]);
            den[k] += w;
        }
    HdrImage out = direct;
    for (size_t i = 0; i < out.pixels.size(); ++i)
        if (surface[i])
            out.pixels[i] += glm::vec3(num / den);
    return out;
}

double laplacianEnergy(const HdrImage& image, const std::vector<bool>& mask, uint32_t step) {
    auto lum = [&](uint32_t x, uint32_t y) {
        const glm::vec3& c = image.at(x, y);
        return 0.2126 * double(c.r) + 0.7152 * double(c.g) + 0.0722 * double(c.b);
    };
    auto inMask = [&](uint32_t x, uint32_t y) { return mask.size() != image.pixels.size() || mask[size_t(y) * image.width + x]; };
    double laplacian = 0.0, energy = 0.0;
    for (uint32_t y = step; y + step < image.height; ++y)
        for (uint32_t x = step; x + step < image.width; ++x) {
            if (!inMask(x, y) || !inMask(x - step, y) || !inMask(x + step, y) || !inMask(x, y - step) ||
                !inMask(x, y + step))
                continue;
            const double c = lum(x, y);
            const double l = 4.0 * c - lum(x - step, y) - lum(x + step, y) - lum(x, y - step) - lum(x, y + step);
            laplacian += l * l;
            energy += c * c;
        }
    return energy > 0.0 ? laplacian / energy : 0.0;
}

std::vector<bool> surfacePixels(const HdrImage& a, const HdrImage& b) {
    std::vector<bool> surface(a.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i)
        surface[i] = a.pixels[i] != glm::vec3(0.0f) || b.pixels[i] != glm::vec3(0.0f);
    return surface;
}

} // namespace vkgi
