#pragma once
// CPU-side linear HDR image (RGB float, row 0 at the top), the common currency between
// readback, the path tracer, EXR/PNG I/O and the error metrics.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace vkgi {

struct HdrImage {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<glm::vec3> pixels; // width*height, row-major, top row first

    HdrImage() = default;
    HdrImage(uint32_t w, uint32_t h) : width(w), height(h), pixels(size_t(w) * h, glm::vec3(0.0f)) {}
    glm::vec3& at(uint32_t x, uint32_t y) { return pixels[size_t(y) * width + x]; }
    const glm::vec3& at(uint32_t x, uint32_t y) const { return pixels[size_t(y) * width + x]; }
    bool empty() const { return pixels.empty(); }
};

} // namespace vkgi
