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

} // namespace vkgi::test
