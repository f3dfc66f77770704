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
    const bool ok = (parts.size() == 2 || parts.size() == 3) && vec3(parts[0], spec.eye) &&
                    vec3(parts[1], spec.target) && (parts.size() == 2 || number(parts[2], spec.yfovDegrees));
    if (!ok)
        return badValue(flag, "EX,EY,EZ:TX,TY,TZ[:FOV] with finite numbers", text);
    if (glm::length(spec.target - spec.eye) < 1e-6f)
        return badValue(flag, "a target apart from the eye", text);
    if (!(spec.yfovDegrees > 0.0f && spec.yfovDegrees < 179.0f))
        return badValue(flag, "a field of view in (0, 179) degrees", text);
    return spec;
}

Camera makeCamera(const CameraSpec& spec, const Aabb& bounds) {
    Camera c;
    c.position = spec.eye;
    c.forward = glm::normalize(spec.target - spec.eye);
    c.up = std::abs(c.forward.y) > 0.999f ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    c.yfov = glm::radians(spec.yfovDegrees);
    const float diag = bounds.valid() ? glm::length(bounds.extent()) : 1.0f;
    const float away = bounds.valid() ? glm::length(spec.eye - 0.5f * (bounds.min + bounds.max)) : 0.0f;
    c.znear = std::max(1e-4f, 1e-3f * diag);
    c.zfar = std::max(2.0f * (away + diag), 10.0f * c.znear);
    return c;
}

Result<Light> parseLightSpec(const std::string& flag, const std::string& text) {
    const std::vector<std::string> parts = split(text, ':');
    Light light;
    bool ok = false;
    if (!parts.empty() && parts[0] == "point" && parts.size() == 3) {
        light.type = LightType::Point;
        ok = vec3(parts[1], light.position) && number(parts[2], light.intensity);
    } else if (!parts.empty() && parts[0] == "spot" && parts.size() == 5) {
        light.type = LightType::Spot;
        float degrees = 0.0f;
        ok = vec3(parts[1], light.position) && vec3(parts[2], light.direction) && number(parts[3], light.intensity) &&
             number(parts[4], degrees) && degrees > 0.0f && degrees < 90.0f;
        light.outerConeAngle = glm::radians(degrees);
        light.innerConeAngle = 0.9f * light.outerConeAngle;
    } else if (!parts.empty() && parts[0] == "sun" && parts.size() == 3) {
        light.type = LightType::Directional;
        ok = vec3(parts[1], light.direction) && number(parts[2], light.intensity);
    }
    if (!ok)
        return badValue(flag, "point:X,Y,Z:CD, spot:X,Y,Z:DX,DY,DZ:CD:DEG (0 < DEG < 90) or sun:DX,DY,DZ:LUX", text);
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
            "EX,EY,EZ:TX,TY,TZ[:FOV]: view from the eye towards the target, vertical field of\n"
            "view in degrees (default 60); replaces the scene's camera",
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
            "add a light (repeatable): point:X,Y,Z:CD, spot:X,Y,Z:DX,DY,DZ:CD:DEG (outer cone\n"
            "half-angle), or sun:DX,DY,DZ:LUX",
            [&to](const std::string& v) -> Result<void> {
                auto light = parseLightSpec("--light", v);
                if (!light)
                    return light.error();
                to.push_back(*light);
                return {};
            }};
}

} // namespace vkgi::apps
