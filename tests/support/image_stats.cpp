#include "support/image_stats.hpp"

#include <limits>

namespace vkgi::test {

double sumRgb(const HdrImage& image) {
    double s = 0.0;
    for (const glm::vec3& p : image.pixels)
        s += double(p.x) + double(p.y) + double(p.z);
    return s;
}

double meanRgb(const HdrImage& image) {
    if (image.pixels.empty())
        return std::numeric_limits<double>::quiet_NaN();
    return sumRgb(image) / (3.0 * double(image.pixels.size()));
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

std::vector<bool> surfacePixels(const HdrImage& a, const HdrImage& b) {
    std::vector<bool> surface(a.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i)
        surface[i] = a.pixels[i] != glm::vec3(0.0f) || b.pixels[i] != glm::vec3(0.0f);
    return surface;
}

} // namespace vkgi::test
