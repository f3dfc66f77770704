// The camera a scene without one gets (Scene::cameraOrDefault). Outside views suit objects and
// open scenes; an interior (a hall, a room, a building entered through its door) seen from
// outside shows its outer walls and nothing of its light. A scene counts as an interior when
// nearly every ray from the centre of its bounds that is not aimed at the sky meets the front
// side of a surface (walls facing inwards; a courtyard open to the sky counts); the camera then stands inside, backed off along the longest horizontal axis towards
// one end, looking along that axis. A closed object (a statue) seen from its centre shows back
// faces, so it keeps the outside view.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "vkgi/scene.hpp"

namespace vkgi {

namespace {

// Of the probe rays, the share that must meet a front face for the scene to be an interior:
// a door or a window may let a few escape.
constexpr float kInteriorShare = 0.9f;
constexpr uint32_t kProbeRays = 64;
constexpr float kSkyElevation = 0.5f; // sin(30 degrees)
constexpr float kInteriorFov = 1.0471976f; // 60 degrees: a room fits, perspective stays mild

struct Hit {
    float t = std::numeric_limits<float>::infinity();
    bool front = false;
};

// Nearest hit of every ray from `origin` (Moller-Trumbore, both sides; `front` when the
// triangle's winding faces the origin).
std::vector<Hit> castRays(const Scene& scene, const glm::vec3& origin, const std::vector<glm::vec3>& dirs) {
    std::vector<Hit> hits(dirs.size());
    for (const Instance& inst : scene.instances) {
        if (inst.mesh >= scene.meshes.size())
            continue;
        const Mesh& mesh = scene.meshes[inst.mesh];
        // A mirroring transform flips the winding.
        bool mirrored = glm::determinant(glm::mat3(inst.transform)) < 0.0f;
        for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
            glm::vec3 p[3];
            for (int k = 0; k < 3; ++k)
                p[k] = glm::vec3(inst.transform * glm::vec4(mesh.positions[mesh.indices[i + size_t(k)]], 1.0f));
            glm::vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
            glm::vec3 n = glm::cross(e1, e2);
            glm::vec3 s = origin - p[0];
            for (size_t r = 0; r < dirs.size(); ++r) {
                glm::vec3 q = glm::cross(dirs[r], e2);
                float det = glm::dot(e1, q);
                if (std::abs(det) < 1e-12f)
                    continue;
                float inv = 1.0f / det;
                float u = glm::dot(s, q) * inv;
                if (u < 0.0f || u > 1.0f)
                    continue;
                glm::vec3 w = glm::cross(s, e1);
                float v = glm::dot(dirs[r], w) * inv;
                if (v < 0.0f || u + v > 1.0f)
                    continue;
                float t = glm::dot(e2, w) * inv;
                if (t > 0.0f && t < hits[r].t)
                    hits[r] = {t, (glm::dot(n, dirs[r]) < 0.0f) != mirrored};
            }
        }
    }
    return hits;
}

std::vector<glm::vec3> sphereDirections(uint32_t n) {
    std::vector<glm::vec3> dirs;
    const float golden = 2.39996323f;
    for (uint32_t i = 0; i < n; ++i) {
        float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
        float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        float phi = golden * float(i);
        dirs.emplace_back(r * std::cos(phi), z, r * std::sin(phi));
    }
    return dirs;
}

} // namespace

std::optional<Camera> interiorCamera(const Scene& scene) {
    Aabb b = scene.bounds();
    if (!b.valid())
        return std::nullopt;
    glm::vec3 centre = b.centre();
    // Rays steeper than kSkyElevation upwards do not count: a courtyard or an atrium open to
    // the sky is an interior too.
    std::vector<glm::vec3> dirs;
    for (const glm::vec3& d : sphereDirections(kProbeRays))
        if (d.y <= kSkyElevation)
            dirs.push_back(d);
    std::vector<Hit> hits = castRays(scene, centre, dirs);
    uint32_t front = 0;
    for (const Hit& h : hits)
        front += h.front ? 1u : 0u;
    if (float(front) < kInteriorShare * float(dirs.size()))
        return std::nullopt;

    glm::vec3 ext = b.extent();
    glm::vec3 axis = ext.x >= ext.z ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    float length = ext.x >= ext.z ? ext.x : ext.z;
    // Back off towards one end, but stay well clear of whatever stands behind the centre.
    Hit behind = castRays(scene, centre, {-axis})[0];
    float back = std::min(0.35f * length, 0.8f * behind.t);
    Camera c;
    c.position = centre - axis * back;
    c.forward = axis;
    c.yfov = kInteriorFov;
    float diag = glm::length(ext);
    c.znear = std::max(1e-4f, 1e-3f * diag);
    c.zfar = std::max(4.0f * diag, c.znear * 10.0f);
    return c;
}

} // namespace vkgi
