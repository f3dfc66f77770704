#include "engine/builtin_scenes.hpp"

#include <array>
#include <cmath>
#include <functional>

#include "mesh_builder.hpp"

namespace vkgi {

namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kDeg = kPi / 180.0f;

glm::vec3 mm(float x, float y, float z) { return glm::vec3(x, y, z) * 0.001f; }

Camera lookAt(const glm::vec3& from, const glm::vec3& to, float yfovDeg, float znear, float zfar) {
    Camera c;
    c.position = from;
    c.forward = glm::normalize(to - from);
    c.up = glm::vec3(0.0f, 1.0f, 0.0f);
    c.yfov = yfovDeg * kDeg;
    c.znear = znear;
    c.zfar = zfar;
    return c;
}

Light spotLight(std::string name, const glm::vec3& pos, const glm::vec3& dir, float cd, float innerDeg, float outerDeg) {
    Light l;
    l.name = std::move(name);
    l.type = LightType::Spot;
    l.position = pos;
    l.direction = glm::normalize(dir);
    l.intensity = cd;
    l.innerConeAngle = innerDeg * kDeg;
    l.outerConeAngle = outerDeg * kDeg;
    return l;
}

Light pointLight(std::string name, const glm::vec3& pos, float cd) {
    Light l;
    l.name = std::move(name);
    l.type = LightType::Point;
    l.position = pos;
    l.intensity = cd;
    return l;
}

[[maybe_unused]] Light sunLight(std::string name, const glm::vec3& dir, float lux) {
    Light l;
    l.name = std::move(name);
    l.type = LightType::Directional;
    l.direction = glm::normalize(dir);
    l.intensity = lux;
    return l;
}

// ---- Cornell box (published data, /work/shared/data/cornell_box.md), mm -> m ----------------

// Common RGB approximations of the published reflectance spectra (linear sRGB).
const glm::vec3 kCornellWhite(0.725f, 0.71f, 0.68f);
const glm::vec3 kCornellRed(0.63f, 0.065f, 0.05f);
const glm::vec3 kCornellGreen(0.14f, 0.45f, 0.091f);

// Centre of the published light rectangle x 213..343, z 227..332 mm, on the ceiling y = 548.8 mm.
const glm::vec3 kCornellLightCentre = mm(278.0f, 548.8f, 279.5f);
// The punctual stand-in sits 1 cm below the ceiling so shadow-map/RSM near planes clear it.
const glm::vec3 kCornellPunctualPos = kCornellLightCentre - glm::vec3(0.0f, 0.01f, 0.0f);
// 1.5 cd straight down over 0.539 m onto the white floor gives direct radiance
// 0.71 * 1.5 / (0.539^2 * pi) = 1.17 nits under the light: "order 1 nit", as asked of the scene.
constexpr float kCornellLightCd = 1.5f;
// Published light rectangle: 130 x 105 mm.
constexpr float kCornellLightArea = 0.130f * 0.105f;
// Emissive variant: a Lambertian rectangle of radiance L has on-axis intensity L * A, so
// L = 1.5 cd / A = 109.9 nits matches the spot's straight-down intensity (flux pi*L*A = 4.7 lm
// against the 70/60-degree spot's ~5.4 lm).
constexpr float kCornellEmission = kCornellLightCd / kCornellLightArea;

void addCornellWalls(Scene& s, bool ceiling = true) {
    uint32_t white = addMaterial(s, "cornell_white", kCornellWhite);
    uint32_t red = addMaterial(s, "cornell_red", kCornellRed);
    uint32_t green = addMaterial(s, "cornell_green", kCornellGreen);
    MeshBuilder w, r, g;
    // Published vertex order, which is already counter-clockwise seen from inside the box.
    w.addQuad(mm(552.8f, 0, 0), mm(0, 0, 0), mm(0, 0, 559.2f), mm(549.6f, 0, 559.2f)); // floor
    if (ceiling)
        w.addQuad(mm(556, 548.8f, 0), mm(556, 548.8f, 559.2f), mm(0, 548.8f, 559.2f), mm(0, 548.8f, 0));
    w.addQuad(mm(549.6f, 0, 559.2f), mm(0, 0, 559.2f), mm(0, 548.8f, 559.2f), mm(556, 548.8f, 559.2f)); // back
    r.addQuad(mm(552.8f, 0, 0), mm(549.6f, 0, 559.2f), mm(556, 548.8f, 559.2f), mm(556, 548.8f, 0));    // left
    g.addQuad(mm(0, 0, 559.2f), mm(0, 0, 0), mm(0, 548.8f, 0), mm(0, 548.8f, 559.2f));                 // right
    addMeshInstance(s, w, "cornell_white_walls", white);
    addMeshInstance(s, r, "cornell_red_wall", red);
    addMeshInstance(s, g, "cornell_green_wall", green);
}

void addCornellBlocks(Scene& s) {
    uint32_t white = addMaterial(s, "cornell_block_white", kCornellWhite);
    const std::array<glm::vec2, 4> shortBlock = {glm::vec2(130, 65), glm::vec2(82, 225), glm::vec2(240, 272),
                                                 glm::vec2(290, 114)};
    const std::array<glm::vec2, 4> tallBlock = {glm::vec2(423, 247), glm::vec2(265, 296), glm::vec2(314, 456),
                                                glm::vec2(472, 406)};
    MeshBuilder b;
    std::array<glm::vec2, 4> fp;
    for (size_t i = 0; i < 4; ++i)
        fp[i] = shortBlock[i] * 0.001f;
    b.addPrism(fp, 0.0f, 0.165f);
    addMeshInstance(s, b, "cornell_short_block", white);
    for (size_t i = 0; i < 4; ++i)
        fp[i] = tallBlock[i] * 0.001f;
    b.addPrism(fp, 0.0f, 0.330f);
    addMeshInstance(s, b, "cornell_tall_block", white);
}

Camera cornellCamera() {
    // Published: 35 mm lens, 25 mm film -> vfov 2 atan(12.5/35) = 39.31 degrees.
    Camera c = lookAt(mm(278, 273, -800), mm(278, 273, 0), 2.0f * std::atan(12.5f / 35.0f) / kDeg, 0.01f, 10.0f);
    return c;
}

Scene makeCornellBase(std::string name) {
    Scene s;
    s.name = std::move(name);
    addCornellWalls(s);
    addCornellBlocks(s);
    s.camera = cornellCamera();
    return s;
}

Scene makeCornell() {
    Scene s = makeCornellBase("cornell");
    s.lights.push_back(spotLight("cornell_ceiling_spot", kCornellPunctualPos, {0, -1, 0}, kCornellLightCd, 60.0f, 70.0f));
    return s;
}

Scene makeCornellPoint() {
    Scene s = makeCornellBase("cornell_point");
    // Same candela as the spot: the floor under the light gets the same direct radiance.
    s.lights.push_back(pointLight("cornell_ceiling_point", kCornellPunctualPos, kCornellLightCd));
    return s;
}

Scene makeCornellSpot() {
    Scene s = makeCornellBase("cornell_spot");
    // From the front of the ceiling toward the back of the floor. 4 cd at ~0.64 m and ~39 degrees
    // incidence gives ~1.7 nits direct floor radiance at the beam centre (0.71 * 4 * 0.78 / (0.41 pi)).
    glm::vec3 from = mm(278, 520, 50);
    glm::vec3 to = mm(278, 0, 450);
    s.lights.push_back(spotLight("cornell_narrow_spot", from, to - from, 4.0f, 25.0f, 30.0f));
    return s;
}

Scene makeCornellEmissive() {
    Scene s = makeCornellBase("cornell_emissive");
    uint32_t lightMat = addMaterial(s, "cornell_light", glm::vec3(0.78f), glm::vec3(kCornellEmission));
    MeshBuilder q;
    const float y = 548.7f; // 0.1 mm below the ceiling so the two never z-fight
    q.addQuad(mm(343, y, 227), mm(343, y, 332), mm(213, y, 332), mm(213, y, 227)); // published order: faces down
    addMeshInstance(s, q, "cornell_light_quad", lightMat);
    return s;
}

// ---- Analytic scenes ---------------------------------------------------------------------

Scene makeFurnace(const BuiltinSceneParams& p) {
    Scene s;
    s.name = "furnace";
    uint32_t m = addMaterial(s, "furnace_wall", glm::vec3(p.furnaceAlbedo), glm::vec3(p.furnaceEmission));
    MeshBuilder b;
    b.addBox(glm::vec3(-0.5f), glm::vec3(0.5f), Facing::Inward);
    addMeshInstance(s, b, "furnace_box", m);
    s.camera = lookAt({0.0f, 0.0f, -0.25f}, {0.0f, 0.0f, 0.5f}, 60.0f, 0.01f, 10.0f);
    return s;
}

Scene makeSphere(const BuiltinSceneParams& p) {
    Scene s;
    s.name = "sphere";
    uint32_t m = addMaterial(s, "sphere_wall", glm::vec3(p.sphereAlbedo));
    MeshBuilder b;
    b.addIcosphere(glm::vec3(0.0f), p.sphereSubdivisions, [](const glm::vec3&) { return 1.0f; }, Facing::Inward);
    addMeshInstance(s, b, "integrating_sphere", m);
    s.lights.push_back(pointLight("sphere_centre_point", glm::vec3(0.0f), p.sphereLightIntensity));
    s.camera = lookAt({0.0f, 0.0f, -0.5f}, {0.0f, 0.0f, 1.0f}, 60.0f, 0.01f, 10.0f);
    return s;
}

struct Entry {
    const char* name;
    std::function<Scene(const BuiltinSceneParams&)> make;
};

const std::vector<Entry>& registry() {
    static const std::vector<Entry> entries = {
        {"cornell", [](const BuiltinSceneParams&) { return makeCornell(); }},
        {"cornell_point", [](const BuiltinSceneParams&) { return makeCornellPoint(); }},
        {"cornell_spot", [](const BuiltinSceneParams&) { return makeCornellSpot(); }},
        {"cornell_emissive", [](const BuiltinSceneParams&) { return makeCornellEmissive(); }},
        {"furnace", makeFurnace},
        {"sphere", makeSphere},
    };
    return entries;
}

std::string joinedNames() {
    std::string out;
    for (const std::string& n : builtinSceneNames())
        out += (out.empty() ? "" : ", ") + n;
    return out;
}

Result<void> checkParams(const BuiltinSceneParams& p) {
    auto unitInterval = [](float v) { return std::isfinite(v) && v >= 0.0f && v < 1.0f; };
    auto nonNegative = [](float v) { return std::isfinite(v) && v >= 0.0f; };
    if (!unitInterval(p.furnaceAlbedo))
        return makeError("builtin scene parameter furnaceAlbedo = " + std::to_string(p.furnaceAlbedo) +
                         " is outside [0, 1)");
    if (!nonNegative(p.furnaceEmission))
        return makeError("builtin scene parameter furnaceEmission = " + std::to_string(p.furnaceEmission) +
                         " must be finite and >= 0");
    if (!unitInterval(p.sphereAlbedo))
        return makeError("builtin scene parameter sphereAlbedo = " + std::to_string(p.sphereAlbedo) +
                         " is outside [0, 1)");
    if (!nonNegative(p.sphereLightIntensity))
        return makeError("builtin scene parameter sphereLightIntensity = " + std::to_string(p.sphereLightIntensity) +
                         " must be finite and >= 0");
    if (p.sphereSubdivisions > 7) // 7 levels = 327680 triangles, already far more than any test needs
        return makeError("builtin scene parameter sphereSubdivisions = " + std::to_string(p.sphereSubdivisions) +
                         " is outside [0, 7]");
    return {};
}

} // namespace

std::vector<std::string> builtinSceneNames() {
    std::vector<std::string> names;
    for (const Entry& e : registry())
        names.emplace_back(e.name);
    return names;
}

bool isBuiltinScene(std::string_view name) {
    for (const Entry& e : registry())
        if (name == e.name)
            return true;
    return false;
}

Result<Scene> makeBuiltinScene(std::string_view name, const BuiltinSceneParams& p) {
    for (const Entry& e : registry()) {
        if (name != e.name)
            continue;
        if (Result<void> ok = checkParams(p); !ok)
            return ok.error();
        Scene s = e.make(p);
        if (Result<void> valid = validateScene(s); !valid)
            return makeError("builtin scene '" + std::string(name) + "' is invalid (bug): " + valid.error().message);
        return s;
    }
    return makeError("unknown built-in scene '" + std::string(name) + "'; valid names: " + joinedNames());
}

} // namespace vkgi
