#pragma once
// Pinhole camera shared by the rasteriser and the path tracer. Both sample pixel centres:
// pixel (x, y) (row 0 at the top) maps to NDC ((x+0.5)/w*2-1, (y+0.5)/h*2-1) with Vulkan's
// y-down clip space and [0,1] depth, so a reference render and a rasterised frame line up.
#include <glm/glm.hpp>

namespace vkgi {

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 0.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f}; // unit view direction
    glm::vec3 up{0.0f, 1.0f, 0.0f};       // approximate up; orthonormalised on use
    float yfov = 0.6981317f;               // vertical field of view, radians (default 40 degrees)
    float znear = 0.01f;
    float zfar = 100.0f;

    glm::mat4 view() const;
    // Vulkan clip conventions: y down, depth in [0,1].
    glm::mat4 projection(float aspect) const;
    // World-space unit direction through the centre of pixel (x, y) of a w x h image.
    glm::vec3 pixelRayDirection(uint32_t x, uint32_t y, uint32_t w, uint32_t h) const;
    // Same for a sub-pixel position (px, py) in [0,w) x [0,h): (x+0.5, y+0.5) is the centre.
    glm::vec3 rayDirection(float px, float py, uint32_t w, uint32_t h) const;
};

// A camera that frames an axis-aligned box from its -z side (used when a file has no camera).
Camera framingCamera(const glm::vec3& boundsMin, const glm::vec3& boundsMax, float yfov = 0.6981317f);

} // namespace vkgi
