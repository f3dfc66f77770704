#pragma once
// Built-in test scenes, generated in code (no asset files): metres, +Y up, glTF conventions,
// lights in KHR_lights_punctual units. Every scene passes validateScene() and has a camera.
//
//   cornell           Cornell's published box (default); a 1.5 cd downward spot (outer 70, inner 60 deg)
//                     1 cm under the light rectangle's centre: ~1.2 nits direct floor radiance below it
//   cornell_point     the same box with a 1.5 cd point light at that spot
//   cornell_spot      the box lit by a 4 cd narrow spot (outer 30 deg) from the ceiling front to the back
//   cornell_emissive  lit only by the published light rectangle (0.1 mm under the ceiling) emitting
//                     109.9 nits, so its on-axis intensity equals the spot's 1.5 cd
//   furnace           closed 1 m cube, uniform albedo and emission: radiance = Le / (1 - albedo)
//   sphere            integrating sphere (r = 1 m, inward) with a point light at its centre
//   room              closed 6 x 3 x 5 m room of solid walls; a 10^4 lux sun 40 deg high shines
//                     through two windows onto floor patches only, the rest is lit indirectly
//   bunny_box         a closed displaced-icosphere "bunny" (5120 triangles by default) in the open Cornell box
//                     under a 1.5 cd spot
//   atrium            procedural Sponza-like atrium (~8.6k triangles): two storeys of arcades,
//                     red/green/blue banners, roofed galleries, open courtyard under a 10^4 lux sun
//   hall              16 x 6 x 10 m interior under a 1000 cd point lamp: checkered floor of 1 m tiles
//                     (albedo 0.8 / 0.04), ten thin pillars, a sphere, a vase and a ring with smooth
//                     normals (curved surfaces, thin geometry, high contrast: real-content stand-in)
//   hall_world        the hall on a 400 m ground plane among low buildings 40-180 m away (bounds ~27x
//                     the hall's, same view): techniques must not size anything by the scene bounds
//   atrium_world      the atrium in the same 400 m world, under its sun
// Reflectances of the Cornell scenes (linear sRGB): white (0.725, 0.71, 0.68), red
// (0.63, 0.065, 0.05), green (0.14, 0.45, 0.091).
#include <string>
#include <string_view>
#include <vector>

#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"

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
    // bunny_box: icosphere level of the bunny, 20 * 4^n triangles (4 -> 5120); the same displaced
    // shape at every level, so vkgi-bench --scaling grows triangles with the lit geometry fixed.
    uint32_t bunnySubdivisions = 4;
};

// Names accepted by makeBuiltinScene, the default ("cornell") first.
std::vector<std::string> builtinSceneNames();
// True when `name` is one of builtinSceneNames().
bool isBuiltinScene(std::string_view name);
// Builds a built-in scene. Unknown names or out-of-range parameters give an error that lists
// the valid choices.
Result<Scene> makeBuiltinScene(std::string_view name, const BuiltinSceneParams& p = {});

} // namespace vkgi
