#pragma once
// What the command line may add to a loaded scene: a camera (--camera) and lights (--light), for
// glTF files that have none (most asset packs ship neither). Parsed when the options are (a bad
// value is a bad argument), applied once the scene's bounds are known.
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "cli.hpp"
#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"

namespace vkgi::apps {

// --camera EX,EY,EZ:TX,TY,TZ[:FOV]: eye, target and vertical field of view in degrees (default 60).
struct CameraSpec {
    glm::vec3 eye{0.0f};
    std::optional<glm::vec3> target; // none: the centre of the scene's bounds
    float yfovDegrees = 60.0f;
};
Result<CameraSpec> parseCameraSpec(const std::string& flag, const std::string& text);

// The camera of `spec` for a scene with `bounds`: +Y up (+Z when looking straight up or down),
// clip planes from the scene's size and the eye's distance to it, as for the default camera.
Camera makeCamera(const CameraSpec& spec, const Aabb& bounds);

// --light, one of
//   point:X,Y,Z:CD                 a point light of CD candela
//   spot:X,Y,Z:DX,DY,DZ:CD:DEG     a spot along (DX,DY,DZ), outer cone half-angle DEG (inner 0.9 DEG)
//   sun:DX,DY,DZ:LUX               a directional light shining along (DX,DY,DZ)
// White, unbounded range. Positions and directions finite, directions not zero, intensities > 0.
Result<Light> parseLightSpec(const std::string& flag, const std::string& text);

// The --camera option (sets `to`) and the repeatable --light option (appends to `to`).
Option cameraOption(std::optional<CameraSpec>& to);
Option lightOption(std::vector<Light>& to);

} // namespace vkgi::apps
