#include "scene_overrides.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "args.hpp"

namespace vkgi::apps {

namespace {

std::vector<std::string> split(const std::string& text, char by) {
    std::vector<std::string> parts;
    size_t start = 0;
    for (size_t i = 0; i <= text.size(); ++i)
        if (i == text.size() || text[i] == by) {
            parts.push_back(text.substr(start, i - start));
            start = i + 1;
        }
    return parts;
}

bool number(const std::string& text, float& v) {
    char* end = nullptr;
    const double d = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(d) || std::abs(d) > 1e12)
        return false;
    v = float(d);
    return true;
}

bool vec3(const std::string& text, glm::vec3& v) {
    const std::vector<std::string> c = split(text, ',');
    return c.size() == 3 && number(c[0], v.x) && number(c[1], v.y) && number(c[2], v.z);
}

} // namespace

Result<CameraSpec> parseCameraSpec(const std::string& flag, const std::string& text) {
    const std::vector<std::string> parts = split(text, ':');
    CameraSpec spec;
    glm::vec3 target{0.0f};
    const bool ok = parts.size() <= 3 && vec3(parts[0], spec.eye) &&
                    (parts.size() < 2 || vec3(parts[1], target)) &&
                    (parts.size() < 3 || number(parts[2], spec.yfovDegrees));
    if (!ok)
        return badValue(flag, "EX,EY,EZ[:TX,TY,TZ[:FOV]] with finite numbers", text);
    if (parts.size() >= 2) {
        if (glm::length(target - spec.eye) < 1e-6f)
            return badValue(flag, "a target apart from the eye", text);
        spec.target = target;
    }
    if (!(spec.yfovDegrees > 0.0f && spec.yfovDegrees < 179.0f))
        return badValue(flag, "a field of view in (0, 179) degrees", text);
    return spec;
}

Camera makeCamera(const CameraSpec& spec, const Aabb& bounds) {
    Camera c;
    c.position = spec.eye;
    const glm::vec3 centre = bounds.valid() ? bounds.centre() : glm::vec3(0.0f);
    glm::vec3 target = spec.target.value_or(centre);
    if (glm::length(target - spec.eye) < 1e-6f) // the eye at the centre of the bounds: look along +z
        target = spec.eye + glm::vec3(0.0f, 0.0f, 1.0f);
    c.forward = glm::normalize(target - spec.eye);
    c.up = std::abs(c.forward.y) > 0.999f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    c.yfov = glm::radians(spec.yfovDegrees);
    const float diag = bounds.valid() ? glm::length(bounds.extent()) : 1.0f;
    const float away = bounds.valid() ? glm::length(spec.eye - centre) : 0.0f;
    c.znear = std::max(1e-4f, 1e-3f * diag);
    c.zfar = std::max(2.0f * (away + diag), 10.0f * c.znear);
    return c;
}

namespace {

// Optional light colour "R,G,B": linear, finite, non-negative and not black.
bool colour(const std::vector<std::string>& parts, size_t index, glm::vec3& out) {
    if (parts.size() <= index)
        return true;
    return vec3(parts[index], out) && out.r >= 0.0f && out.g >= 0.0f && out.b >= 0.0f &&
           out.r + out.g + out.b > 0.0f;
}

} // namespace

Result<Light> parseLightSpec(const std::string& flag, const std::string& text) {
    const std::vector<std::string> parts = split(text, ':');
    Light light;
    bool ok = false;
    if (!parts.empty() && parts[0] == "point" && (parts.size() == 3 || parts.size() == 4)) {
        light.type = LightType::Point;
        ok = vec3(parts[1], light.position) && number(parts[2], light.intensity) && colour(parts, 3, light.color);
    } else if (!parts.empty() && parts[0] == "spot" && (parts.size() == 5 || parts.size() == 6)) {
        light.type = LightType::Spot;
        float outer = 0.0f, inner = -1.0f;
        ok = vec3(parts[1], light.position) && vec3(parts[2], light.direction) && number(parts[3], light.intensity) &&
             number(parts[4], outer) && outer > 0.0f && outer < 90.0f &&
             (parts.size() == 5 || (number(parts[5], inner) && inner >= 0.0f && inner < outer));
        light.outerConeAngle = glm::radians(outer);
        light.innerConeAngle = inner >= 0.0f ? glm::radians(inner) : 0.9f * light.outerConeAngle;
    } else if (!parts.empty() && parts[0] == "sun" && (parts.size() == 3 || parts.size() == 4)) {
        light.type = LightType::Directional;
        ok = vec3(parts[1], light.direction) && number(parts[2], light.intensity) && colour(parts, 3, light.color);
    }
    if (!ok)
        return badValue(flag,
                        "point:X,Y,Z:CD[:R,G,B], spot:X,Y,Z:DX,DY,DZ:CD:OUTER[:INNER] (degrees, 0 <= INNER < "
                        "OUTER < 90) or sun:DX,DY,DZ:LUX[:R,G,B] (colour linear, not black)",
                        text);
    if (light.type != LightType::Point) {
        if (glm::length(light.direction) < 1e-6f)
            return badValue(flag, "a direction that is not zero", text);
        light.direction = glm::normalize(light.direction);
    }
    if (!(light.intensity > 0.0f))
        return badValue(flag, "an intensity above 0", text);
    light.name = "--light " + text;
    return light;
}

Option cameraOption(std::optional<CameraSpec>& to) {
    return {"--camera", "SPEC",
            "EX,EY,EZ[:TX,TY,TZ[:FOV]]: view from the eye towards the target (default: the\n"
            "centre of the scene), vertical field of view in degrees (default 60); replaces the\n"
            "scene's camera",
            [&to](const std::string& v) -> Result<void> {
                auto spec = parseCameraSpec("--camera", v);
                if (!spec)
                    return spec.error();
                to = *spec;
                return {};
            }};
}

Option lightOption(std::vector<Light>& to) {
    return {"--light", "SPEC",
            "add a light (repeatable): point:X,Y,Z:CD[:R,G,B], spot:X,Y,Z:DX,DY,DZ:CD:OUTER[:INNER]\n"
            "(cone half-angles in degrees; inner default 0.9 outer), or sun:DX,DY,DZ:LUX[:R,G,B]",
            [&to](const std::string& v) -> Result<void> {
                auto light = parseLightSpec("--light", v);
                if (!light)
                    return light.error();
                to.push_back(*light);
                return {};
            }};
}

} // namespace vkgi::apps
