// Shadow-atlas planning: which layers each light gets and the projection of every layer.
#include <algorithm>
#include <array>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "direct/cascades.hpp"
#include "direct/direct_passes.hpp"

namespace vkgi::gi {

namespace {

// Perspective near plane as a fraction of far: depth is stored linearly, so near only clips;
// 1e-4 keeps geometry 0.1 mm from a 1 m light range from leaking. Capped so a light in a large
// scene (far in hundreds of metres) does not clip what is centimetres from it.
constexpr float kNearFraction = 1e-4f;
constexpr float kMaxNear = 1e-3f;
// Far plane margin so the farthest corner of the bounds is never clipped.
constexpr float kFarMargin = 1.01f;
// Angle between a cube face's axis and its corners: a face can see a cone only if the cone
// comes within this angle of the face axis.
const float kCubeCornerAngle = std::atan(std::sqrt(2.0f));
// A directional light's RSM window replaces its own layer's RSM only when its texels are at
// most this fraction of the own layer's.
constexpr float kRsmWindowGain = 0.5f;

const std::array<glm::vec3, 6> kCubeAxes = {glm::vec3(1, 0, 0),  glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0),
                                            glm::vec3(0, -1, 0), glm::vec3(0, 0, 1),  glm::vec3(0, 0, -1)};

glm::vec3 upFor(const glm::vec3& axis) { return lightUpFor(axis); }

// What the light can reach within the scene: the farthest bounds corner, or its range when
// shorter (beyond it the light contributes nothing). Stored depth is distance / far in a 32-bit
// float, so its precision is relative to far, not to the scene's size.
float farDistance(const glm::vec3& eye, const Aabb& b, float range) {
    float far = 0.0f;
    for (const glm::vec3& c : b.corners())
        far = std::max(far, glm::distance(eye, c));
    if (range > 0.0f)
        far = std::min(far, range);
    return std::max(far * kFarMargin, 1e-3f);
}

gpu::GpuShadowView perspectiveView(const glm::vec3& eye, const glm::vec3& axis, float halfFov, float far, uint32_t n) {
    gpu::GpuShadowView v{};
    glm::mat4 view = glm::lookAtRH(eye, eye + axis, upFor(axis));
    v.viewProj = glm::perspectiveRH_ZO(2.0f * halfFov, 1.0f, std::min(far * kNearFraction, kMaxNear), far) * view;
    float texelPerMetre = 2.0f * std::tan(halfFov) / float(n);
    v.eye = glm::vec4(eye, far);
    v.axisArea = glm::vec4(axis, texelPerMetre * texelPerMetre);
    v.texel = glm::vec4(texelPerMetre, far, float(n), 0.0f);
    return v;
}

// Orthographic box around `b`, looking along `dir`, whose depth range spans `reach` (which holds
// b): the light's own layer (b = reach = the scene's bounds) or a directional light's RSM window
// (b = the window; everything between it and the sun still occludes). The own layer must see
// everything the light reaches, because the RSM (each texel's flux counted once) and the voxel
// light read it at any point of the scene; the camera's direct image reads the cascades
// (cascades.hpp), whose texels do not grow with the bounds.
gpu::GpuShadowView orthoView(const glm::vec3& dir, const Aabb& b, uint32_t n, const Aabb& reach) {
    float radius = std::max(0.5f * glm::length(b.extent()), 1e-3f);
    float reachRadius = std::max(0.5f * glm::length(reach.extent()), 1e-3f);
    // Every corner of `reach` lies at least reachRadius in front of the eye.
    glm::vec3 eye = b.centre() - dir * (2.0f * reachRadius + glm::distance(b.centre(), reach.centre()));
    glm::mat4 view = glm::lookAtRH(eye, b.centre(), upFor(dir));
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& c : b.corners()) {
        glm::vec3 v = glm::vec3(view * glm::vec4(c, 1.0f));
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
    for (const glm::vec3& c : reach.corners()) {
        float z = (view * glm::vec4(c, 1.0f)).z;
        lo.z = std::min(lo.z, z);
        hi.z = std::max(hi.z, z);
    }
    // Half a texel of margin on each side so geometry on the bounds is not clipped.
    glm::vec2 margin = 0.5f * glm::vec2(hi - lo) / float(n) + 1e-4f * radius;
    lo -= glm::vec3(margin, 0.0f);
    hi += glm::vec3(margin, 0.0f);
    float zNear = std::max(-hi.z - 1e-3f * reachRadius, 0.0f), zFar = -lo.z + 1e-3f * reachRadius;
    gpu::GpuShadowView v{};
    v.viewProj = glm::orthoRH_ZO(lo.x, hi.x, lo.y, hi.y, zNear, zFar) * view;
    glm::vec2 texel = glm::vec2(hi - lo) / float(n);
    v.eye = glm::vec4(eye, 0.0f);
    v.axisArea = glm::vec4(dir, texel.x * texel.y);
    v.texel = glm::vec4(std::max(texel.x, texel.y), zFar - zNear, float(n), 0.0f);
    return v;
}

} // namespace

std::vector<gpu::GpuShadowView> cubeShadowViews(const glm::vec3& eye, const Aabb& bounds, uint32_t resolution) {
    std::vector<gpu::GpuShadowView> views;
    const float far = farDistance(eye, bounds, 0.0f);
    for (const glm::vec3& axis : kCubeAxes)
        views.push_back(perspectiveView(eye, axis, 0.25f * 3.14159265f, far, resolution));
    return views;
}

ShadowLayout planShadows(const Scene& scene, const Aabb& bounds, uint32_t resolution, uint32_t maxLayers,
                         const CascadeRequest& cascades, const Aabb& rsmWindow,
                         const std::vector<Aabb>& shadowWindows) {
    ShadowLayout layout;
    layout.resolution = resolution;
    for (uint32_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        LightShadowPlan plan;
        plan.light = i;
        bool single = l.type == LightType::Directional ||
                      (l.type == LightType::Spot && l.outerConeAngle <= kMaxSpotFrustumHalfAngle);
        uint32_t count = single ? 1 : 6;
        if (!bounds.valid() || layout.views.size() + count > maxLayers) {
            layout.lights.push_back(plan); // unshadowed
            continue;
        }
        plan.kind = single ? GI_SHADOW_SINGLE : GI_SHADOW_CUBE;
        plan.firstLayer = uint32_t(layout.views.size());
        plan.layerCount = count;
        glm::vec3 dir = glm::normalize(l.direction);
        if (l.type == LightType::Directional) {
            layout.views.push_back(orthoView(dir, bounds, resolution, bounds));
            plan.faceMask = 1;
            Aabb window;
            window.min = glm::max(rsmWindow.min, bounds.min);
            window.max = glm::min(rsmWindow.max, bounds.max);
            if (rsmWindow.valid() && window.valid()) {
                gpu::GpuShadowView w = orthoView(dir, window, resolution, bounds);
                // Only a window at least twice as fine as the own layer is worth its extra pass.
                if (w.texel.x <= kRsmWindowGain * layout.views.back().texel.x) {
                    plan.rsmWindowed = true;
                    plan.rsmView = w;
                }
            }
        } else if (single) {
            layout.views.push_back(perspectiveView(l.position, dir, l.outerConeAngle, farDistance(l.position, bounds, l.range),
                                                   resolution));
            plan.faceMask = 1;
        } else {
            float far = farDistance(l.position, bounds, l.range);
            for (uint32_t f = 0; f < 6; ++f) {
                layout.views.push_back(perspectiveView(l.position, kCubeAxes[f], 0.25f * 3.14159265f, far, resolution));
                float angle = std::acos(std::clamp(glm::dot(kCubeAxes[f], dir), -1.0f, 1.0f));
                bool sees = l.type == LightType::Point || angle - kCubeCornerAngle < l.outerConeAngle;
                plan.faceMask |= sees ? (1u << f) : 0u;
            }
        }
        for (uint32_t k = 0; k < count; ++k)
            layout.layers.push_back({i, single ? 0 : k, layout.views[plan.firstLayer + k].viewProj});
        layout.lights.push_back(plan);
    }
    const CascadeFrustum frustum = cascadeFrustum(cascades.camera, cascades.aspect);
    for (LightShadowPlan& plan : layout.lights) {
        const Light& l = scene.lights[plan.light];
        if (cascades.count == 0 || l.type != LightType::Directional || plan.kind == GI_SHADOW_NONE ||
            layout.views.size() + cascades.count > maxLayers)
            continue;
        CascadeSet set = planCascades(frustum, glm::normalize(l.direction), bounds, cascades.count, resolution,
                                      cascades.marginTexels);
        const float wholeTexel = layout.views[plan.firstLayer].texel.x;
        uint32_t finer = 0;
        while (finer < set.views.size() && set.views[finer].texel.x < wholeTexel)
            ++finer;
        if (finer == 0)
            continue;
        plan.cascadeFirst = uint32_t(layout.views.size());
        plan.cascadeCount = finer;
        layout.views.insert(layout.views.end(), set.views.begin(), set.views.begin() + finer);
    }
    // Shadow windows after every cascade, so that the cascades' and the RSM's layers do not
    // depend on whether a technique asks for windows.
    for (LightShadowPlan& plan : layout.lights) {
        const Light& l = scene.lights[plan.light];
        if (l.type != LightType::Directional || plan.kind == GI_SHADOW_NONE)
            continue;
        const float wholeTexel = layout.views[plan.firstLayer].texel.x;
        plan.windowFirst = uint32_t(layout.views.size());
        for (const Aabb& w : shadowWindows) {
            if (!w.valid() || plan.windowCount == kMaxShadowWindows || layout.views.size() >= maxLayers)
                break;
            // Only the part inside the bounds holds geometry; a box outside them keeps its own
            // extent (nothing to draw, but window k stays layer windowFirst + k).
            Aabb box;
            box.min = glm::max(w.min, bounds.min);
            box.max = glm::min(w.max, bounds.max);
            gpu::GpuShadowView v = windowView(glm::normalize(l.direction), box.valid() ? box : w, bounds, resolution,
                                              cascades.marginTexels);
            if (!(v.texel.x < wholeTexel))
                break;
            layout.views.push_back(v);
            ++plan.windowCount;
        }
        if (plan.windowCount == 0)
            plan.windowFirst = 0;
    }
    return layout;
}

} // namespace vkgi::gi
