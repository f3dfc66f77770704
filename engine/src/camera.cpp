#include "vkgi/camera.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace vkgi {

namespace {
struct Basis {
    glm::vec3 right, up, forward;
};
Basis basis(const Camera& c) {
    glm::vec3 f = glm::normalize(c.forward);
    glm::vec3 r = glm::cross(f, c.up);
    if (glm::dot(r, r) < 1e-12f) // forward parallel to up: pick any perpendicular
        r = glm::cross(f, std::abs(f.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1));
    r = glm::normalize(r);
    return {r, glm::cross(r, f), f};
}
} // namespace

glm::mat4 Camera::view() const {
    Basis b = basis(*this);
    return glm::lookAtRH(position, position + b.forward, b.up);
}

glm::mat4 Camera::projection(float aspect) const {
    glm::mat4 p = glm::perspectiveRH_ZO(yfov, aspect, znear, zfar);
    p[1][1] *= -1.0f; // Vulkan clip space: +y points down the image
    return p;
}

glm::vec3 Camera::rayDirection(float px, float py, uint32_t w, uint32_t h) const {
    Basis b = basis(*this);
    float tanHalf = std::tan(0.5f * yfov);
    float aspect = float(w) / float(h);
    float sx = (2.0f * px / float(w) - 1.0f) * tanHalf * aspect;
    float sy = (1.0f - 2.0f * py / float(h)) * tanHalf; // row 0 is the top of the image
    return glm::normalize(b.forward + sx * b.right + sy * b.up);
}

glm::vec3 Camera::pixelRayDirection(uint32_t x, uint32_t y, uint32_t w, uint32_t h) const {
    return rayDirection(float(x) + 0.5f, float(y) + 0.5f, w, h);
}

Camera framingCamera(const glm::vec3& bmin, const glm::vec3& bmax, float yfov) {
    Camera c;
    glm::vec3 centre = 0.5f * (bmin + bmax);
    glm::vec3 ext = bmax - bmin;
    float radius = 0.5f * std::max({ext.x, ext.y, 1e-3f});
    float dist = radius / std::tan(0.5f * yfov) + 0.5f * ext.z;
    c.position = centre - glm::vec3(0.0f, 0.0f, dist); // dist is measured from the centre
    c.forward = glm::vec3(0.0f, 0.0f, 1.0f);
    c.yfov = yfov;
    float diag = glm::length(ext);
    c.znear = std::max(1e-4f, 1e-3f * diag);
    c.zfar = std::max(4.0f * (dist + diag), c.znear * 10.0f);
    return c;
}

} // namespace vkgi
