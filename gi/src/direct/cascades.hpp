#pragma once
// Cascaded shadow maps for directional lights (docs/direct.md): the camera's view depth, limited
// to where the scene is, is split into slices; each slice gets an orthographic shadow layer
// fitted to its bounding sphere (rotation-invariant size) with its origin on whole texels (no
// shimmer when the camera moves). Pure CPU math, private to gi/.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "vkgi/camera.hpp"
#include "vkgi/scene.hpp"
#include "gi/direct_types.h"

namespace vkgi::gi {

// Weight of the logarithmic split against the uniform one (the "practical" scheme): log splits
// keep the texel-to-pixel ratio constant with depth, the uniform share keeps the near slices from
// collapsing to centimetres when znear is tiny.
constexpr float kCascadeSplitLambda = 0.75f;

// The camera frustum the cascades cover.
struct CascadeFrustum {
    glm::vec3 position{0.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f}; // unit
    glm::vec3 right{1.0f, 0.0f, 0.0f};    // unit
    glm::vec3 up{0.0f, 1.0f, 0.0f};       // unit
    float tanHalfY = 0.0f;                // tan(yfov / 2)
    float aspect = 1.0f;                  // width / height
    float znear = 0.01f;
    float zfar = 100.0f;
};
CascadeFrustum cascadeFrustum(const Camera& camera, float aspect);

// The view-depth range [near, far] of the frustum that can hold scene geometry: the camera's
// range limited to the depths of the bounds' corners. False when the bounds are not in front.
bool sceneDepthRange(const CascadeFrustum& f, const Aabb& bounds, float& near, float& far);

// count + 1 split depths from near to far (practical scheme with kCascadeSplitLambda),
// strictly increasing.
std::vector<float> cascadeSplits(float near, float far, uint32_t count, float lambda = kCascadeSplitLambda);

// The 8 world-space corners of the frustum between view depths d0 and d1.
std::array<glm::vec3, 8> sliceCorners(const CascadeFrustum& f, float d0, float d1);

// Smallest sphere centred on the view axis that holds the slice [d0, d1]: its radius depends
// only on d0, d1, the fov and the aspect, not on the camera's orientation.
struct Sphere {
    glm::vec3 centre{0.0f};
    float radius = 0.0f;
};
Sphere sliceSphere(const CascadeFrustum& f, float d0, float d1);

// Orthographic layer looking along `lightDir` whose square box holds `sphere` with
// `marginTexels` texels to spare on each side, origin snapped to whole texels; its depth range
// spans the bounds along the light (casters outside the slice still cast) up to the sphere's far
// side. The light's view has no translation, so the snapped box is a lattice of texels fixed in
// the world.
gpu::GpuShadowView cascadeView(const glm::vec3& lightDir, const Sphere& sphere, const Aabb& bounds, uint32_t resolution,
                               float marginTexels);

// Orthographic layer looking along `lightDir` whose square box holds the projection of `box`
// along the light with `marginTexels` texels to spare on each side, origin snapped to whole
// texels of the light's rotation frame as for a cascade (a box moved by any step keeps its texel
// size and the world's texel lattice; an unmoved box gives a bitwise equal view). Its depth range
// spans from the nearest point of `bounds` or `box` toward the light (every caster between the
// box and the light) to the box's far side. A shadow window (planShadows).
gpu::GpuShadowView windowView(const glm::vec3& lightDir, const Aabb& box, const Aabb& bounds, uint32_t resolution,
                              float marginTexels);

struct CascadeSet {
    std::vector<float> splits;              // count + 1 view depths
    std::vector<gpu::GpuShadowView> views;  // one per slice, finest first
};
// Empty when the bounds are invalid or not in front of the camera.
CascadeSet planCascades(const CascadeFrustum& f, const glm::vec3& lightDir, const Aabb& bounds, uint32_t count,
                        uint32_t resolution, float marginTexels);

// Up vector of a light view along `axis` (shared by every shadow layer).
glm::vec3 lightUpFor(const glm::vec3& axis);

} // namespace vkgi::gi
