#pragma once
// Small synthetic scenes shared by GPU tests whose closed forms need a simple geometry.
#include "vkgi/scene.hpp"

namespace vkgi::test {

// The box with corners lo and hi.
inline Aabb box(glm::vec3 lo, glm::vec3 hi) {
    Aabb b;
    b.extend(lo);
    b.extend(hi);
    return b;
}

// A square plane of half-side `halfSize` at y = 0 (normal +Y, uniform grey `albedo`), one
// instance, no light and no camera.
Scene plane(float albedo, float halfSize);

// A 20 m plane (plane(albedo, 10)) lit by `light`, seen from 3 m above looking straight down
// (60 degree vertical field of view, depth 0.01..10 m).
Scene planeScene(float albedo, const Light& light);

} // namespace vkgi::test
