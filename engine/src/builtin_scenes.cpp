#include "vkgi/builtin_scenes.hpp"

#include <array>
#include <cmath>
#include <functional>
#include <vector>

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

Light sunLight(std::string name, const glm::vec3& dir, float lux) {
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


// ---- Room lit through two windows (Gaitatzes et al.'s hard case) ----------------------------

// Interior 6 (x) x 3 (y) x 5 (z) m; every wall, the floor and the ceiling are solid 0.2 m boxes
// (outward faces), so the room is light-tight for shadow maps and rays except at the windows.
constexpr float kRoomW = 6.0f, kRoomH = 3.0f, kRoomD = 5.0f, kRoomWall = 0.2f;
// Windows in the x = 0 wall: z 1..2 and 3..4, sill 1.0 m, lintel 2.2 m.
constexpr float kSill = 1.0f, kLintel = 2.2f;
const std::array<glm::vec2, 2> kWindowsZ = {glm::vec2(1.0f, 2.0f), glm::vec2(3.0f, 4.0f)};
// Sun 40 degrees above the horizon, 15 degrees off the window normal: rays through the window
// land on the floor 1.15..2.5 m from the window wall, so only floor patches are lit directly.
const glm::vec3 kRoomSunDir = glm::normalize(glm::vec3(std::cos(40 * kDeg) * std::cos(15 * kDeg), -std::sin(40 * kDeg),
                                                       std::cos(40 * kDeg) * std::sin(15 * kDeg)));
// 10^4 lux (overcast-bright daylight; full sun is ~10^5): the lit wooden floor reaches
// 0.6 * 10^4 * sin 40 / pi = 1.2e3 nits, the indirectly lit room tens of nits, all well inside
// half-float range.
constexpr float kRoomSunLux = 1.0e4f;

Scene makeRoom() {
    Scene s;
    s.name = "room";
    const float t = kRoomWall;
    uint32_t floorMat = addMaterial(s, "room_wood_floor", {0.60f, 0.42f, 0.25f});
    uint32_t ceilMat = addMaterial(s, "room_ceiling", {0.80f, 0.80f, 0.78f});
    uint32_t windowWallMat = addMaterial(s, "room_window_wall", {0.75f, 0.75f, 0.72f});
    uint32_t blueMat = addMaterial(s, "room_blue_wall", {0.30f, 0.45f, 0.70f});
    uint32_t terracottaMat = addMaterial(s, "room_terracotta_wall", {0.75f, 0.35f, 0.25f});
    uint32_t greenMat = addMaterial(s, "room_green_wall", {0.45f, 0.65f, 0.40f});
    MeshBuilder b;
    b.addBox({-t, -t, -t}, {kRoomW + t, 0.0f, kRoomD + t});
    addMeshInstance(s, b, "room_floor", floorMat);
    b.addBox({-t, kRoomH, -t}, {kRoomW + t, kRoomH + t, kRoomD + t});
    addMeshInstance(s, b, "room_ceiling", ceilMat);
    b.addBox({kRoomW, 0.0f, 0.0f}, {kRoomW + t, kRoomH, kRoomD}); // opposite the windows
    addMeshInstance(s, b, "room_blue_wall", blueMat);
    b.addBox({0.0f, 0.0f, kRoomD}, {kRoomW, kRoomH, kRoomD + t});
    addMeshInstance(s, b, "room_terracotta_wall", terracottaMat);
    b.addBox({0.0f, 0.0f, -t}, {kRoomW, kRoomH, 0.0f});
    addMeshInstance(s, b, "room_green_wall", greenMat);
    // Window wall (x in [-t, 0]): below the sills, above the lintels, and the piers between.
    b.addBox({-t, 0.0f, 0.0f}, {0.0f, kSill, kRoomD});
    b.addBox({-t, kLintel, 0.0f}, {0.0f, kRoomH, kRoomD});
    float z = 0.0f;
    for (const glm::vec2& w : kWindowsZ) {
        b.addBox({-t, kSill, z}, {0.0f, kLintel, w.x});
        z = w.y;
    }
    b.addBox({-t, kSill, z}, {0.0f, kLintel, kRoomD});
    addMeshInstance(s, b, "room_window_wall", windowWallMat);
    s.lights.push_back(sunLight("room_sun", kRoomSunDir, kRoomSunLux));
    s.camera = lookAt({5.7f, 1.6f, 0.3f}, {1.5f, 0.4f, 3.2f}, 60.0f, 0.02f, 50.0f);
    return s;
}

// ---- A procedural "bunny" in an open box under a spot (after Cochran & Steele) -------------

// Star-shaped radius: an ellipsoid with low-frequency bumps and two "ear" lobes. Radial
// displacement of a sphere cannot self-intersect, so the mesh stays a closed 2-manifold.
float bunnyRadius(const glm::vec3& d) {
    const glm::vec3 semi(0.11f, 0.13f, 0.09f); // ellipsoid semi-axes, metres
    float r = 1.0f / glm::length(d / semi);
    float bumps = 0.08f * std::sin(5.0f * d.x + 1.0f) * std::sin(4.0f * d.y) * std::sin(3.0f * d.z + 0.5f);
    float ears = 0.0f;
    for (const glm::vec3& ear : {glm::vec3(0.35f, 0.9f, 0.2f), glm::vec3(-0.35f, 0.9f, 0.2f)})
        ears += 0.9f * std::pow(std::max(0.0f, glm::dot(d, glm::normalize(ear))), 24.0f);
    return r * (1.0f + bumps + ears);
}

Scene makeBunnyBox(const BuiltinSceneParams& p) {
    Scene s;
    s.name = "bunny_box";
    addCornellWalls(s);
    uint32_t clay = addMaterial(s, "bunny_clay", {0.80f, 0.60f, 0.45f});
    MeshBuilder b;
    b.addIcosphere(glm::vec3(0.0f), p.bunnySubdivisions, bunnyRadius); // 20 * 4^n triangles (4: 5120)
    Aabb bb = b.bounds();
    b.translate(glm::vec3(0.278f, 0.0f, 0.30f) - glm::vec3(bb.centre().x, bb.min.y, bb.centre().z)); // on the floor
    addMeshInstance(s, b, "bunny", clay);
    // From the ceiling front onto the bunny: 1.5 cd at ~0.5 m lights the floor around it at
    // ~1.5 nits (0.71 * 1.5 * cos / (d^2 pi)), like the cornell scenes.
    glm::vec3 from = mm(278, 520, 40), to = mm(278, 120, 300);
    s.lights.push_back(spotLight("bunny_spot", from, to - from, 1.5f, 28.0f, 35.0f));
    s.camera = cornellCamera();
    return s;
}

// ---- Procedural Sponza-like atrium ------------------------------------------------------

// Courtyard x in [-7, 7], z in [-14, 14]; colonnades on x = +-4 with columns every 3 m; two
// storeys of round arches; galleries roofed, courtyard open to the sky.
constexpr float kAtriumX = 7.0f, kAtriumZ = 14.0f, kColX = 4.0f, kColStep = 3.0f;
constexpr float kGroundColH = 3.6f, kGalleryY = 5.1f, kSlab = 0.3f, kUpperColH = 2.2f, kArchR = 1.5f;
constexpr float kWallTop = 9.6f;
// Sun ~55 degrees high: floods most of the courtyard floor, leaves the galleries in shadow.
const glm::vec3 kAtriumSunDir = glm::normalize(glm::vec3(0.35f, -1.0f, 0.5f));
// Same 10^4 lux as the room (documented there).
constexpr float kAtriumSunLux = 1.0e4f;

// A round arch in the plane x = xc spanning z in [zc - R, zc + R], springing at y = ys, with
// its spandrels filled as in a masonry arcade: `segments` hexahedra, each from a piece of the
// intrados (radius R - 0.3) straight up to y = ys + R, the underside of the slab above. Depth
// 0.6 m. (A bare ring of outer radius R left two thin wedges between its extrados and the slab
// at every crown, sub-voxel crevices of ~1 nit that a 128^2 image's relMSE was mostly made of,
// and with its crown flush against the slab the two faces were coplanar: the path tracer met
// the ring's top face from behind on pixels where the rasterizer saw the slab.)
void addArch(MeshBuilder& b, float xc, float zc, float ys, uint32_t segments) {
    const float rin = kArchR - 0.3f, top = ys + kArchR, half = 0.3f;
    auto at = [&](float theta, float x) { return glm::vec3(x, ys + rin * std::sin(theta), zc - rin * std::cos(theta)); };
    auto above = [&](float theta, float x) { return glm::vec3(x, top, zc - rin * std::cos(theta)); };
    for (uint32_t i = 0; i < segments; ++i) {
        float a0 = kPi * float(i) / float(segments), a1 = kPi * float(i + 1) / float(segments);
        std::array<glm::vec3, 8> c = {at(a0, xc - half),    at(a1, xc - half),    above(a0, xc - half),
                                      above(a1, xc - half), at(a0, xc + half),    at(a1, xc + half),
                                      above(a0, xc + half), above(a1, xc + half)};
        b.addHexahedron(c);
    }
}

Scene makeAtrium() {
    Scene s;
    s.name = "atrium";
    uint32_t stone = addMaterial(s, "atrium_floor", {0.55f, 0.50f, 0.42f});
    uint32_t sandstone = addMaterial(s, "atrium_walls", {0.70f, 0.60f, 0.45f});
    uint32_t columnMat = addMaterial(s, "atrium_columns", {0.75f, 0.70f, 0.60f});
    uint32_t roofMat = addMaterial(s, "atrium_roof", {0.50f, 0.45f, 0.40f});
    const glm::vec3 bannerColours[3] = {{0.70f, 0.08f, 0.06f}, {0.10f, 0.55f, 0.12f}, {0.08f, 0.15f, 0.65f}};
    uint32_t bannerMats[3];
    for (int i = 0; i < 3; ++i)
        bannerMats[i] = addMaterial(s, std::string("atrium_banner_") + "rgb"[i], bannerColours[i], glm::vec3(0.0f), true);

    MeshBuilder floor, walls, columns, roof;
    const float t = 0.3f;
    floor.addBox({-kAtriumX - t, -0.2f, -kAtriumZ - t}, {kAtriumX + t, 0.0f, kAtriumZ + t}, Facing::Outward, 8);
    walls.addBox({kAtriumX, 0.0f, -kAtriumZ}, {kAtriumX + t, kWallTop, kAtriumZ});
    walls.addBox({-kAtriumX - t, 0.0f, -kAtriumZ}, {-kAtriumX, kWallTop, kAtriumZ});
    walls.addBox({-kAtriumX - t, 0.0f, kAtriumZ}, {kAtriumX + t, kWallTop, kAtriumZ + t});
    walls.addBox({-kAtriumX - t, 0.0f, -kAtriumZ - t}, {kAtriumX + t, kWallTop, -kAtriumZ});
    const float upperY = kGalleryY + kSlab;           // upper gallery floor level
    const float upperSpring = upperY + kUpperColH;     // upper arches spring here
    const float roofY = upperSpring + kArchR;          // roof slab bottom
    for (float side : {-1.0f, 1.0f}) {
        float xc = side * kColX;
        // Gallery floor and roof, from just inside the column line to the outer wall.
        float inner = xc - side * 0.3f, outer = side * kAtriumX;
        glm::vec3 lo(std::min(inner, outer), 0.0f, -kAtriumZ), hi(std::max(inner, outer), 0.0f, kAtriumZ);
        roof.addBox({lo.x, kGalleryY, lo.z}, {hi.x, upperY, hi.z});
        roof.addBox({lo.x, roofY, lo.z}, {hi.x, roofY + kSlab, hi.z});
        for (float z = -kAtriumZ + 2.0f; z <= kAtriumZ - 2.0f + 1e-3f; z += kColStep) {
            columns.addCylinder({xc, 0.0f, z}, 0.3f, kGroundColH, 12);
            columns.addCylinder({xc, upperY, z}, 0.25f, kUpperColH, 12);
            // Piers over the capitals, between the arches' feet (z +- (R - 0.3) from their centres).
            const float pier = kColStep * 0.5f - (kArchR - 0.3f);
            columns.addBox({xc - 0.3f, kGroundColH, z - pier}, {xc + 0.3f, kGalleryY, z + pier});
            columns.addBox({xc - 0.3f, upperSpring, z - pier}, {xc + 0.3f, roofY, z + pier});
            if (z + kColStep <= kAtriumZ - 2.0f + 1e-3f) {
                addArch(columns, xc, z + 0.5f * kColStep, kGroundColH, 16);
                addArch(columns, xc, z + 0.5f * kColStep, upperSpring, 16);
            }
        }
    }
    addMeshInstance(s, floor, "atrium_floor", stone);
    addMeshInstance(s, walls, "atrium_walls", sandstone);
    addMeshInstance(s, columns, "atrium_colonnades", columnMat);
    addMeshInstance(s, roof, "atrium_gallery_slabs", roofMat);
    // Banners hang on the courtyard side of each colonnade, below the gallery slab.
    int k = 0;
    for (float side : {-1.0f, 1.0f})
        for (float z : {-7.0f, -1.0f, 5.0f}) {
            MeshBuilder banner;
            float x = side * (kColX - 0.6f);
            glm::vec3 a(x, 2.4f, z - 0.6f), c(x, kGalleryY - 0.1f, z + 0.6f);
            if (side < 0) // front faces the courtyard centre (banners are double-sided anyway)
                banner.addQuad({x, a.y, c.z}, {x, a.y, a.z}, {x, c.y, a.z}, {x, c.y, c.z});
            else
                banner.addQuad(a, {x, a.y, c.z}, c, {x, c.y, a.z});
            addMeshInstance(s, banner, "atrium_banner_" + std::to_string(k), bannerMats[k % 3]);
            ++k;
        }
    s.lights.push_back(sunLight("atrium_sun", kAtriumSunDir, kAtriumSunLux));
    s.camera = lookAt({0.0f, 1.7f, -12.5f}, {0.0f, 3.5f, 6.0f}, 60.0f, 0.05f, 100.0f);
    return s;
}

// ---- hall: a large interior with what game assets have ----------------------------------
// A 16 x 6 x 10 m hall lit by one point lamp: a checkered floor of 1 m tiles (albedo 0.8 / 0.04,
// the high contrast that shows blotches and light bleeding), ten thin pillars (r = 0.18 m) and a
// sphere, a vase and a torus-like ring with smooth normals (curved surfaces, where coarse-grid
// cone sampling shows), on the floor between them.
constexpr float kHallX = 8.0f, kHallY = 6.0f, kHallZ = 5.0f;

void addHallFloor(Scene& s) {
    uint32_t light = addMaterial(s, "hall_tile_light", {0.80f, 0.78f, 0.74f});
    uint32_t dark = addMaterial(s, "hall_tile_dark", {0.04f, 0.04f, 0.045f});
    MeshBuilder tiles[2];
    for (int x = int(-kHallX); x < int(kHallX); ++x)
        for (int z = int(-kHallZ); z < int(kHallZ); ++z) {
            const float x0 = float(x), z0 = float(z);
            tiles[(x + z) & 1].addQuad({x0, 0, z0 + 1}, {x0 + 1, 0, z0 + 1}, {x0 + 1, 0, z0}, {x0, 0, z0});
        }
    addMeshInstance(s, tiles[0], "hall_floor_light", light);
    addMeshInstance(s, tiles[1], "hall_floor_dark", dark);
}

void addHallObjects(Scene& s) {
    uint32_t stone = addMaterial(s, "hall_pillars", {0.70f, 0.68f, 0.62f});
    uint32_t red = addMaterial(s, "hall_sphere", {0.70f, 0.16f, 0.10f});
    uint32_t blue = addMaterial(s, "hall_vase", {0.15f, 0.25f, 0.65f});
    uint32_t gold = addMaterial(s, "hall_ring", {0.75f, 0.60f, 0.25f});
    MeshBuilder pillars;
    // Base flare, shaft, capital: smooth along the shaft, split at the flat ends.
    const std::vector<glm::vec2> pillar = {{0.0f, 0.0f},   {0.30f, 0.0f}, {0.30f, 0.12f}, {0.18f, 0.35f},
                                           {0.18f, 5.50f}, {0.28f, 5.80f}, {0.28f, kHallY}, {0.0f, kHallY}};
    for (float z : {-2.5f, 2.5f})
        for (float x : {-6.0f, -3.0f, 0.0f, 3.0f, 6.0f})
            pillars.addLathe({x, 0.0f, z}, pillar, 24);
    addMeshInstance(s, pillars, "hall_pillars", stone);
    MeshBuilder sphere;
    sphere.addIcosphere({-3.0f, 0.7f, 0.2f}, 3, [](const glm::vec3&) { return 0.7f; });
    addMeshInstance(s, sphere, "hall_sphere", red);
    // A vase: a bulging body, a narrow neck and a lip (a stand-in for a teapot-like curved body).
    std::vector<glm::vec2> vase = {{0.0f, 0.0f}};
    for (int i = 0; i <= 16; ++i) {
        float t = float(i) / 16.0f;
        float r = 0.22f + 0.38f * std::sin(kPi * std::min(1.0f, t * 1.15f)) * (1.0f - 0.55f * t);
        vase.emplace_back(r, 1.4f * t);
    }
    vase.emplace_back(0.0f, 1.4f);
    MeshBuilder vaseMesh;
    vaseMesh.addLathe({2.4f, 0.0f, 0.6f}, vase, 32);
    addMeshInstance(s, vaseMesh, "hall_vase", blue);
    // A thick ring lying on the floor (a torus as a lathe of a circle, closed in itself).
    std::vector<glm::vec2> ring;
    for (int i = 0; i <= 20; ++i) {
        float a = 2.0f * kPi * float(i) / 20.0f;
        ring.emplace_back(0.55f + 0.2f * std::cos(a), 0.2f + 0.2f * std::sin(a));
    }
    MeshBuilder ringMesh;
    ringMesh.addLathe({0.0f, 0.0f, -0.6f}, ring, 32);
    addMeshInstance(s, ringMesh, "hall_ring", gold);
}

Scene makeHall() {
    Scene s;
    s.name = "hall";
    uint32_t walls = addMaterial(s, "hall_walls", {0.62f, 0.58f, 0.52f});
    uint32_t ceiling = addMaterial(s, "hall_ceiling", {0.70f, 0.70f, 0.70f});
    MeshBuilder w, c;
    // Walls face into the hall; the floor is the tiles, the ceiling its own material.
    w.addGridQuad({-kHallX, 0, -kHallZ}, {kHallX, 0, -kHallZ}, {kHallX, kHallY, -kHallZ}, {-kHallX, kHallY, -kHallZ}, 4);
    w.addGridQuad({kHallX, 0, kHallZ}, {-kHallX, 0, kHallZ}, {-kHallX, kHallY, kHallZ}, {kHallX, kHallY, kHallZ}, 4);
    w.addGridQuad({-kHallX, 0, kHallZ}, {-kHallX, 0, -kHallZ}, {-kHallX, kHallY, -kHallZ}, {-kHallX, kHallY, kHallZ}, 4);
    w.addGridQuad({kHallX, 0, -kHallZ}, {kHallX, 0, kHallZ}, {kHallX, kHallY, kHallZ}, {kHallX, kHallY, -kHallZ}, 4);
    c.addGridQuad({-kHallX, kHallY, -kHallZ}, {kHallX, kHallY, -kHallZ}, {kHallX, kHallY, kHallZ}, {-kHallX, kHallY, kHallZ}, 4);
    addMeshInstance(s, w, "hall_walls", walls);
    addMeshInstance(s, c, "hall_ceiling", ceiling);
    addHallFloor(s);
    addHallObjects(s);
    // 1000 cd at 4.5 m: 0.8 x 1000 / (pi 4.5^2) = 12.6 nits on the light tiles below it.
    s.lights.push_back(pointLight("hall_lamp", {0.0f, 4.5f, 0.0f}, 1000.0f));
    s.camera = lookAt({-7.4f, 1.9f, 1.2f}, {1.0f, 0.6f, -0.4f}, 55.0f, 0.05f, 60.0f);
    return s;
}

// ---- the same interiors inside a large world ------------------------------------------
// A 400 m square ground plane under the interior and a ring of low buildings 40-180 m away: the
// scene's bounds grow ~27x while what the camera sees does not (closed hall walls; the atrium's
// walls hide buildings that low), so a technique's error should not change either. Techniques
// that size their volumes or constants by the scene's bounds do worse here (issue #16).
constexpr float kWorldHalf = 200.0f, kBuildingMaxH = 8.0f;

void addWorldAround(Scene& s, const std::string& prefix, float groundY) {
    uint32_t ground = addMaterial(s, prefix + "_ground", {0.30f, 0.28f, 0.25f});
    uint32_t building = addMaterial(s, prefix + "_buildings", {0.50f, 0.48f, 0.45f});
    MeshBuilder g, b;
    g.addGridQuad({-kWorldHalf, groundY, kWorldHalf}, {kWorldHalf, groundY, kWorldHalf},
                  {kWorldHalf, groundY, -kWorldHalf}, {-kWorldHalf, groundY, -kWorldHalf}, 16);
    // Deterministic placement: 24 buildings on rings, sizes from a fixed sequence.
    for (int i = 0; i < 24; ++i) {
        float angle = 2.0f * kPi * (float(i) + 0.37f * float(i % 3)) / 24.0f;
        float radius = 40.0f + 140.0f * float((i * 7) % 24) / 23.0f;
        float w = 6.0f + float((i * 5) % 7), d = 5.0f + float((i * 3) % 5);
        float h = 3.0f + (kBuildingMaxH - 3.0f) * float((i * 11) % 13) / 12.0f;
        glm::vec3 c(radius * std::cos(angle), groundY, radius * std::sin(angle));
        b.addBox({c.x - 0.5f * w, groundY, c.z - 0.5f * d}, {c.x + 0.5f * w, groundY + h, c.z + 0.5f * d});
    }
    addMeshInstance(s, g, prefix + "_ground", ground);
    addMeshInstance(s, b, prefix + "_buildings", building);
}

Scene makeHallWorld() {
    Scene s = makeHall();
    s.name = "hall_world";
    addWorldAround(s, "hall_world", -0.05f); // just under the floor tiles
    return s;
}

Scene makeAtriumWorld() {
    Scene s = makeAtrium();
    s.name = "atrium_world";
    addWorldAround(s, "atrium_world", -0.25f); // just under the floor slab
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
        {"room", [](const BuiltinSceneParams&) { return makeRoom(); }},
        {"bunny_box", makeBunnyBox},
        {"atrium", [](const BuiltinSceneParams&) { return makeAtrium(); }},
        {"hall", [](const BuiltinSceneParams&) { return makeHall(); }},
        {"hall_world", [](const BuiltinSceneParams&) { return makeHallWorld(); }},
        {"atrium_world", [](const BuiltinSceneParams&) { return makeAtriumWorld(); }},
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
    if (p.bunnySubdivisions > 7)
        return makeError("builtin scene parameter bunnySubdivisions = " + std::to_string(p.bunnySubdivisions) +
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
