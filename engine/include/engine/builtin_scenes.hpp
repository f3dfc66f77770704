#pragma once
// Built-in test scenes, generated in code (no asset files): metres, +Y up, glTF conventions,
// lights in KHR_lights_punctual units. Every scene passes validateScene() and has a camera.
//
//   cornell           Cornell's published box (default); a wide downward spot under the light rectangle
//   cornell_point     the same box with a point light at that spot
//   cornell_spot      the box lit by a narrow spot from the front of the ceiling toward the back
//   cornell_emissive  the box lit only by the published light rectangle as an emissive quad
//   furnace           closed 1 m cube, uniform albedo and emission: radiance = Le / (1 - albedo)
//   sphere            integrating sphere (r = 1 m) with a point light at its centre
//   room              closed 6 x 3 x 5 m room, sun through two windows (mostly indirect lighting)
//   bunny_box         a displaced-icosphere "bunny" in an open box under a spot light
//   atrium            procedural Sponza-like two-storey atrium under a sun
#include <string>
#include <string_view>
#include <vector>

#include "engine/result.hpp"
#include "engine/scene.hpp"

namespace vkgi {

struct BuiltinSceneParams {
    // furnace: albedo of every face (grey); closed form needs 0 <= albedo < 1.
    float furnaceAlbedo = 0.5f;
    // furnace: emitted radiance of every face, nits.
    float furnaceEmission = 1.0f;
    // sphere: albedo of the inner surface (grey).
    float sphereAlbedo = 0.5f;
    // sphere: intensity of the central point light, cd. Inner-wall radiance (exact sphere) is
    // albedo * I / (pi r^2 (1 - albedo)); with the defaults 1/pi nits.
    float sphereLightIntensity = 1.0f;
    // sphere: icosphere subdivision level; 4 -> 5120 triangles whose flat facets sag at most 0.12% of r
    // below the true sphere (facet centroids at >= 0.99886 r), so closed forms hold to ~0.1%.
    uint32_t sphereSubdivisions = 4;
};

// Names accepted by makeBuiltinScene, the default ("cornell") first.
std::vector<std::string> builtinSceneNames();
// True when `name` is one of builtinSceneNames().
bool isBuiltinScene(std::string_view name);
// Builds a built-in scene. Unknown names or out-of-range parameters give an error that lists
// the valid choices.
Result<Scene> makeBuiltinScene(std::string_view name, const BuiltinSceneParams& p = {});

} // namespace vkgi
