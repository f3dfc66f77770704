// Cascade planning for directional lights (see cascades.hpp and docs/direct.md).
#include "direct/cascades.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace vkgi::gi {

glm::vec3 lightUpFor(const glm::vec3& axis) {
    return std::abs(axis.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
}

CascadeFrustum cascadeFrustum(const Camera& camera, float aspect) {
    CascadeFrustum f;
    f.position = camera.position;
    f.forward = glm::normalize(camera.forward);
    glm::vec3 up = std::abs(glm::dot(f.forward, glm::normalize(camera.up))) < 0.999f ? camera.up : lightUpFor(f.forward);
    f.right = glm::normalize(glm::cross(f.forward, up));
    f.up = glm::cross(f.right, f.forward);
    f.tanHalfY = std::tan(0.5f * camera.yfov);
    f.aspect = aspect;
    f.znear = camera.znear;
    f.zfar = camera.zfar;
    return f;
}

bool sceneDepthRange(const CascadeFrustum& f, const Aabb& bounds, float& near, float& far) {
    if (!bounds.valid())
        return false;
    float lo = 1e30f, hi = -1e30f;
    for (const glm::vec3& c : bounds.corners()) {
        float d = glm::dot(c - f.position, f.forward);
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    near = std::max(f.znear, lo);
    far = std::min(f.zfar, hi);
    return far > near;
}

std::vector<float> cascadeSplits(float near, float far, uint32_t count, float lambda) {
    std::vector<float> d(count + 1);
    for (uint32_t i = 0; i <= count; ++i) {
        float s = float(i) / float(count);
        float logSplit = near * std::pow(far / near, s);
        float uniform = near + (far - near) * s;
        d[i] = lambda * logSplit + (1.0f - lambda) * uniform;
    }
    d.front() = near;
    d.back() = far;
    return d;
}

std::array<glm::vec3, 8> sliceCorners(const CascadeFrustum& f, float d0, float d1) {
    std::array<glm::vec3, 8> c;
    for (int i = 0; i < 8; ++i) {
        float d = (i & 4) ? d1 : d0;
        float x = ((i & 1) ? 1.0f : -1.0f) * d * f.tanHalfY * f.aspect;
        float y = ((i & 2) ? 1.0f : -1.0f) * d * f.tanHalfY;
        c[i] = f.position + f.forward * d + f.right * x + f.up * y;
    }
    return c;
}

Sphere sliceSphere(const CascadeFrustum& f, float d0, float d1) {
    // Corners at depth d lie d * k from the axis; the centre depth z equalises the distance to
    // the near and the far corners, unless that lies beyond d1 (wide slices), where the far
    // rectangle's circumcircle already holds the near corners.
    float k2 = f.tanHalfY * f.tanHalfY * (1.0f + f.aspect * f.aspect);
    float z = 0.5f * (d0 + d1) * (1.0f + k2);
    float radius;
    if (z >= d1) {
        z = d1;
        radius = d1 * std::sqrt(k2);
    } else {
        radius = std::sqrt((d1 - z) * (d1 - z) + d1 * d1 * k2);
    }
    return {f.position + f.forward * z, radius};
}

namespace {

// The orthographic layer of the light's rotation `view` whose square box of half size `half` is
// centred on `centre` (light frame, on the texel lattice) and spans [zNear, zFar] along `dir`,
// padded so that geometry on either end is not clipped.
gpu::GpuShadowView latticeView(const glm::mat4& view, const glm::vec3& dir, glm::vec2 centre, float half, float zNear,
                               float zFar, uint32_t resolution) {
    const float n = float(resolution);
    const float texel = 2.0f * half / n;
    float pad = 1e-3f * (zFar - zNear) + 1e-4f * half;
    zNear -= pad;
    zFar += pad;
    gpu::GpuShadowView v{};
    v.viewProj = glm::orthoRH_ZO(centre.x - half, centre.x + half, centre.y - half, centre.y + half, zNear, zFar) * view;
    glm::mat3 toWorld = glm::transpose(glm::mat3(view));
    v.eye = glm::vec4(toWorld * glm::vec3(centre, -zNear), 0.0f);
    v.axisArea = glm::vec4(dir, texel * texel);
    v.texel = glm::vec4(texel, zFar - zNear, n, 0.0f);
    return v;
}

} // namespace

gpu::GpuShadowView cascadeView(const glm::vec3& lightDir, const Sphere& sphere, const Aabb& bounds, uint32_t resolution,
                               float marginTexels) {
    const glm::vec3 dir = glm::normalize(lightDir);
    const float n = float(resolution);
    // Half size h = radius + (margin + 1) texels of size 2h / n: the margin keeps the deferred
    // pass's PCF footprint inside the box, the extra texel absorbs the snapping of the origin.
    float frac = std::min(2.0f * (marginTexels + 1.0f) / n, 0.5f);
    float half = sphere.radius / (1.0f - frac);
    float texel = 2.0f * half / n;
    // The light's view is a pure rotation (eye at the world origin): the texel lattice is fixed in
    // the world, and snapping the box's centre to it keeps every texel on the same world squares.
    glm::mat4 view = glm::lookAtRH(glm::vec3(0.0f), dir, lightUpFor(dir));
    glm::vec3 c = glm::vec3(view * glm::vec4(sphere.centre, 1.0f));
    glm::vec2 centre = glm::round(glm::vec2(c) / texel) * texel;
    // Depth along the light: from the bounds' nearest point to the light (every caster) to the
    // box's far side or the bounds' far end, whichever is nearer (no receiver beyond).
    float lo = 1e30f, hi = -1e30f;
    for (const glm::vec3& b : bounds.corners()) {
        float d = glm::dot(b, dir);
        lo = std::min(lo, d);
        hi = std::max(hi, d);
    }
    // The far side is rounded up to whole box half-sizes: it follows the unsnapped centre, and a
    // continuous value would change the matrix (and re-render the cascade) on every camera move.
    float zNear = lo, zFar = std::min(hi, std::ceil((-c.z + half) / half) * half);
    if (zFar <= zNear)
        zFar = zNear + half;
    return latticeView(view, dir, centre, half, zNear, zFar, resolution);
}

gpu::GpuShadowView windowView(const glm::vec3& lightDir, const Aabb& box, const Aabb& bounds, uint32_t resolution,
                              float marginTexels) {
    const glm::vec3 dir = glm::normalize(lightDir);
    const float n = float(resolution);
    glm::mat4 view = glm::lookAtRH(glm::vec3(0.0f), dir, lightUpFor(dir));
    // Half extents of the box's projection in the light's frame (x, y) and along it (z), from
    // the box's size alone: a moved box of the same size gets bitwise the same texel size.
    const glm::vec3 halfSize = 0.5f * (box.max - box.min);
    const glm::mat3 rotation(view);
    const glm::vec3 extent =
        glm::abs(rotation[0] * halfSize.x) + glm::abs(rotation[1] * halfSize.y) + glm::abs(rotation[2] * halfSize.z);
    // Square box: half size h = radius + (margin + 1) texels of size 2h / n, as for a cascade.
    const float radius = std::max(std::max(extent.x, extent.y), 1e-3f);
    float frac = std::min(2.0f * (marginTexels + 1.0f) / n, 0.5f);
    float half = radius / (1.0f - frac);
    float texel = 2.0f * half / n;
    glm::vec3 c = glm::vec3(view * glm::vec4(0.5f * (box.min + box.max), 1.0f));
    glm::vec2 centre = glm::round(glm::vec2(c) / texel) * texel;
    // Depth along the light (-z): from the bounds' (or the box's) point nearest the light, so
    // every caster between the box and the light is in front, to the box's far side (no
    // receiver beyond).
    float zNear = -c.z - extent.z, zFar = -c.z + extent.z;
    for (const glm::vec3& b : bounds.corners())
        zNear = std::min(zNear, glm::dot(b, dir));
    if (zFar <= zNear)
        zFar = zNear + half;
    return latticeView(view, dir, centre, half, zNear, zFar, resolution);
}

CascadeSet planCascades(const CascadeFrustum& f, const glm::vec3& lightDir, const Aabb& bounds, uint32_t count,
                        uint32_t resolution, float marginTexels) {
    CascadeSet set;
    float near = 0.0f, far = 0.0f;
    if (count == 0 || !sceneDepthRange(f, bounds, near, far))
        return set;
    set.splits = cascadeSplits(near, far, count);
    for (uint32_t i = 0; i < count; ++i)
        set.views.push_back(
            cascadeView(lightDir, sliceSphere(f, set.splits[i], set.splits[i + 1]), bounds, resolution, marginTexels));
    return set;
}

} // namespace vkgi::gi
