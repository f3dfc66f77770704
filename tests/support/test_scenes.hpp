#pragma once
// Small synthetic scenes shared by GPU tests whose closed forms need a simple geometry.
#include "engine/scene.hpp"

namespace vkgi::test {

// A 20 m plane at y = 0 (normal +Y, uniform grey `albedo`) lit by `light`, seen from 3 m above
// looking straight down (60 degree vertical field of view, depth 0.01..10 m).
Scene planeScene(float albedo, const Light& light);

} // namespace vkgi::test
