// The path-traced reference against closed forms. Tolerances are stated per test with where
// they come from (Monte Carlo noise measured over seeds, or mesh faceting of the scene).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>

#include <tbb/global_control.h>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/image_metrics.hpp"
#include "vkgi/reference.hpp"
#include "support/image_stats.hpp"
#include "support/test_env.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Mean of all channels over all pixels (grey scenes: every channel carries the same value).
using test::meanRgb;

ReferenceSettings quiet(uint32_t spp, int maxBounces = -1, uint64_t seed = 1) {
    ReferenceSettings s;
    s.spp = spp;
    s.maxBounces = maxBounces;
    s.seed = seed;
    s.progress = false;
    return s;
}

// Adds a one-material quad a-b-c-d (counter-clockwise seen from its front) as its own instance.
void addQuad(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 albedo,
             glm::vec3 emission = glm::vec3(0.0f), bool doubleSided = false) {
    Material m;
    m.baseColor = glm::vec4(albedo, 1.0f);
    m.emission = emission;
    m.doubleSided = doubleSided;
    s.materials.push_back(m);
    Mesh mesh;
    mesh.positions = {a, b, c, d};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = uint32_t(s.materials.size() - 1);
    s.meshes.push_back(mesh);
    Instance inst;
    inst.mesh = uint32_t(s.meshes.size() - 1);
    s.instances.push_back(inst);
}

// A camera at `pos` looking straight down (-y), image top towards -z.
Camera downCamera(glm::vec3 pos, float yfov) {
    Camera c;
    c.position = pos;
    c.forward = {0.0f, -1.0f, 0.0f};
    c.up = {0.0f, 0.0f, -1.0f};
    c.yfov = yfov;
    return c;
}

Scene furnace(float albedo, float emission = 1.0f) {
    BuiltinSceneParams p;
    p.furnaceAlbedo = albedo;
    p.furnaceEmission = emission;
    Result<Scene> s = makeBuiltinScene("furnace", p);
    EXPECT_TRUE(s.ok()) << s.error().message;
    return s.value();
}

ReferenceImages render(const Scene& scene, const Camera& cam, uint32_t w, uint32_t h, const ReferenceSettings& s) {
    Result<ReferenceImages> r = renderReference(scene, cam, w, h, s);
    EXPECT_TRUE(r.ok()) << r.error().message;
    if (!r.ok())
        return {};
    EXPECT_EQ(countNonFinite(r->full), 0u);
    return std::move(r.value());
}

} // namespace

// Closed box, uniform emission Le and albedo p: L = Le sum_k p^k = Le / (1 - p). Unbounded
// bounces, so Russian roulette is on. The 0.5% bound is > 10 standard deviations of the image
// mean at this sample count (measured over 10 seeds: sd 0.03% at p = 0.5, 0.04% at p = 0.8).
TEST(Reference, FurnaceUnbounded) {
    for (float p : {0.5f, 0.8f}) {
        Scene s = furnace(p, 2.0f);
        ReferenceImages img = render(s, *s.camera, 16, 16, quiet(512));
        const double expected = 2.0 / (1.0 - double(p));
        EXPECT_NEAR(meanRgb(img.full), expected, 0.005 * expected) << "albedo " << p;
        // direct = emission seen + one reflection = Le (1 + p), exactly binned by path length.
        EXPECT_NEAR(meanRgb(img.direct), 2.0 * (1.0 + p), 0.005 * 2.0 * (1.0 + p)) << "albedo " << p;
    }
}

// k reflections: L = Le (1 - p^(k+1)) / (1 - p). No roulette below 4 reflections, so only the
// light-sampling noise remains; 0.5% is > 10 sigma of the mean here.
TEST(Reference, FurnaceBoundedBounces) {
    const float p = 0.5f;
    Scene s = furnace(p);
    for (int k = 0; k <= 3; ++k) {
        ReferenceImages img = render(s, *s.camera, 16, 16, quiet(64, k));
        const double expected = (1.0 - std::pow(double(p), k + 1)) / (1.0 - double(p));
        EXPECT_NEAR(meanRgb(img.full), expected, 0.005 * expected) << "k = " << k;
        if (k == 0) {
            EXPECT_EQ(meanRgb(img.full), 1.0); // emission only: no sampling at all
        }
    }
}

// Albedo 0.99: L = 100 Le, paths ~100 reflections long. Must stay finite and within 2%
// (the mean's standard deviation over 10 seeds is 0.12% at this sample count).
TEST(Reference, FurnaceNearUnitAlbedo) {
    Scene s = furnace(0.99f);
    ReferenceImages img = render(s, *s.camera, 8, 8, quiet(128));
    EXPECT_EQ(countNonFinite(img.full), 0u);
    EXPECT_NEAR(meanRgb(img.full), 100.0, 2.0);
}

// Integrating sphere of radius R, point light I at the centre: E = I / R^2 on the wall, direct
// L = p E / pi, and since every reflected photon stays inside, total L = p E / (pi (1 - p)).
// The scene is an icosphere whose facets sag <= 0.12% below R (builtin_scenes.hpp), so the
// direct term holds to ~0.25% (1/d^2 and cos over a facet); 0.5% for direct, 1% for total
// (measured over 10 seeds: direct +0.15%, total +0.12% with sd 0.06%).
TEST(Reference, IntegratingSphere) {
    BuiltinSceneParams params;
    params.sphereAlbedo = 0.6f;
    params.sphereLightIntensity = 3.0f;
    Result<Scene> s = makeBuiltinScene("sphere", params);
    ASSERT_TRUE(s.ok()) << s.error().message;
    ReferenceImages img = render(*s, *s->camera, 16, 16, quiet(64));
    const double p = 0.6, e = 3.0 / (1.0 * 1.0);
    EXPECT_NEAR(meanRgb(img.direct), p * e / kPi, 0.005 * p * e / kPi);
    EXPECT_NEAR(meanRgb(img.full), p * e / (kPi * (1.0 - p)), 0.01 * p * e / (kPi * (1.0 - p)));
}

// A point light at height h over a large plane of albedo p: L(x) = p I h / (pi (h^2 + x^2)^1.5)
// at horizontal distance x from the foot point. A single plane has no interreflection and no
// randomness reaches the result (the continuation ray escapes), so it holds to float precision.
TEST(Reference, PointLightOverPlane) {
    const float p = 0.7f, h = 1.5f, I = 20.0f;
    Scene s;
    addQuad(s, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, glm::vec3(p));
    Light l;
    l.type = LightType::Point;
    l.position = {0.0f, h, 0.0f};
    l.intensity = I;
    s.lights.push_back(l);
    const uint32_t w = 32, hgt = 24;
    Camera cam = downCamera({0.3f, 4.0f, -0.2f}, 1.2f);
    ReferenceImages img = render(s, cam, w, hgt, quiet(4));
    int checked = 0;
    for (uint32_t y : {0u, 5u, 12u, 23u})
        for (uint32_t x : {0u, 9u, 16u, 31u}) {
            glm::vec3 d = cam.pixelRayDirection(x, y, w, hgt);
            glm::vec3 q = cam.position + d * (-cam.position.y / d.y); // the plane point this pixel sees
            double x2 = double(q.x) * q.x + double(q.z) * q.z;
            double expected = p * I * h / (kPi * std::pow(double(h) * h + x2, 1.5));
            EXPECT_NEAR(img.full.at(x, y).x, expected, 1e-4 * expected) << x << "," << y;
            EXPECT_EQ(img.indirect.at(x, y), glm::vec3(0.0f));
            ++checked;
        }
    EXPECT_EQ(checked, 16);
}

// The same plane under a spot (glTF cone falloff from lights.h, recomputed here from the spec
// formula) and under a sun (E = lux cos(theta)).
TEST(Reference, SpotAndDirectionalOverPlane) {
    const float p = 0.5f, h = 2.0f, I = 10.0f, inner = 0.3f, outer = 0.6f;
    Scene s;
    addQuad(s, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, glm::vec3(p));
    Light spot;
    spot.type = LightType::Spot;
    spot.position = {0.0f, h, 0.0f};
    spot.direction = {0.0f, -1.0f, 0.0f};
    spot.intensity = I;
    spot.innerConeAngle = inner;
    spot.outerConeAngle = outer;
    s.lights.push_back(spot);
    const uint32_t w = 32, hgt = 32;
    Camera cam = downCamera({0.0f, 5.0f, 0.0f}, 1.0f);
    ReferenceImages img = render(s, cam, w, hgt, quiet(2));
    bool sawDark = false, sawFull = false, sawRamp = false;
    for (uint32_t y = 0; y < hgt; y += 3)
        for (uint32_t x = 0; x < w; x += 3) {
            glm::vec3 d = cam.pixelRayDirection(x, y, w, hgt);
            glm::vec3 q = cam.position + d * (-cam.position.y / d.y);
            double r2 = double(q.x) * q.x + double(q.z) * q.z;
            double dist = std::sqrt(r2 + double(h) * h);
            double cosA = h / dist; // angle off the spot axis; also the cosine at the plane
            double t = std::clamp((cosA - std::cos(outer)) / (std::cos(inner) - std::cos(outer)), 0.0, 1.0);
            double expected = p / kPi * I * t * t / (dist * dist) * cosA;
            EXPECT_NEAR(img.full.at(x, y).x, expected, 1e-4 * expected + 1e-7) << x << "," << y;
            sawDark |= t == 0.0;
            sawFull |= t == 1.0;
            sawRamp |= t > 0.0 && t < 1.0;
        }
    EXPECT_TRUE(sawDark && sawFull && sawRamp); // the view covers all three regions of the cone

    s.lights.clear();
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f)); // 45 degrees
    sun.intensity = 1000.0f;
    s.lights.push_back(sun);
    img = render(s, cam, 8, 8, quiet(1));
    for (const glm::vec3& px : img.full.pixels)
        EXPECT_NEAR(px.y, p / kPi * 1000.0 * std::sqrt(0.5), 1e-4 * 1000.0);
}

// Two parallel unit squares at distance 1: form factor F = 0.199825. An emitter of radiance Le
// facing a receiver of albedo 1: by reciprocity (equal areas) the receiver's mean irradiance is
// pi Le F, so its mean radiance is p Le F. The camera looks straight down at the receiver,
// which exactly fills the frame: a pinhole perpendicular to a plane gives every pixel the
// same area, so the pixel mean is the area mean (midpoint rule, O(1/n^2) = ~1e-4 here).
// 1% bound: Monte Carlo sigma of the mean is ~0.1% at this sample count.
TEST(Reference, ParallelSquaresFormFactor) {
    const float le = 5.0f;
    Scene s;
    addQuad(s, {-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}, {0.5f, 0, -0.5f}, {-0.5f, 0, -0.5f}, glm::vec3(1.0f)); // up
    addQuad(s, {-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0.5f, 1, 0.5f}, {-0.5f, 1, 0.5f}, glm::vec3(0.0f),
            glm::vec3(le)); // faces down
    const float camH = 0.5f;
    Camera cam = downCamera({0.0f, camH, 0.0f}, 2.0f * std::atan(0.5f / camH));
    ReferenceImages img = render(s, cam, 32, 32, quiet(64, 1));
    EXPECT_NEAR(meanRgb(img.full), le * 0.199825, 0.01 * le * 0.199825);
    EXPECT_EQ(meanRgb(img.indirect), 0.0);
    // Unbounded gives the same image here: the emitter is black, so nothing bounces back.
    ReferenceImages unbounded = render(s, cam, 32, 32, quiet(64));
    EXPECT_EQ(meanRgb(unbounded.full), meanRgb(img.full));
}

// Emission is one-sided unless the material is doubleSided (reference.hpp).
TEST(Reference, EmissionSidedness) {
    for (bool doubleSided : {false, true}) {
        Scene s;
        addQuad(s, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, glm::vec3(0.5f), glm::vec3(3.0f), doubleSided);
        ReferenceImages top = render(s, downCamera({0, 1, 0}, 0.5f), 4, 4, quiet(1));
        Camera below = downCamera({0, -1, 0}, 0.5f);
        below.forward = {0, 1, 0};
        ReferenceImages bottom = render(s, below, 4, 4, quiet(1));
        EXPECT_EQ(meanRgb(top.full), 3.0);                        // front: Le, no other light
        EXPECT_EQ(meanRgb(bottom.full), doubleSided ? 3.0 : 0.0); // back
    }
}

// Albedo = baseColor factor x texture (sRGB-decoded unless the texture is linear), shading
// normals from the mesh, and glTF's mirrored-transform winding rule, under a sun straight
// down (E = lux): L = albedo E cos(n_shading, up) / pi.
TEST(Reference, TextureShadingNormalsAndMirroring) {
    const float lux = 100.0f;
    for (bool srgb : {true, false}) {
        Scene s;
        addQuad(s, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, glm::vec3(0.5f, 0.5f, 1.0f));
        s.meshes[0].uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        const float tilt = 1.0471976f; // 60 degrees: cos = 0.5
        s.meshes[0].normals.assign(4, glm::vec3(std::sin(tilt), std::cos(tilt), 0.0f));
        Texture t;
        t.width = t.height = 1;
        t.srgb = srgb;
        t.rgba8 = {128, 255, 0, 255};
        s.textures.push_back(t);
        s.materials[0].baseColorTexture = 0;
        Light sun;
        sun.type = LightType::Directional;
        sun.direction = {0.0f, -1.0f, 0.0f};
        sun.intensity = lux;
        s.lights.push_back(sun);
        ReferenceImages img = render(s, downCamera({0, 1, 0}, 0.5f), 4, 4, quiet(1));
        // sRGB 128 -> ((128/255 + 0.055) / 1.055)^2.4 = 0.2158605
        const double r = srgb ? 0.2158605 : 128.0 / 255.0;
        const glm::vec3 want = glm::vec3(glm::dvec3(0.5 * r, 0.5, 0.0) * (lux * 0.5 / kPi));
        for (const glm::vec3& px : img.full.pixels) {
            EXPECT_NEAR(px.x, want.x, 1e-4f * want.x) << "srgb " << srgb;
            EXPECT_NEAR(px.y, want.y, 1e-4f * want.y);
            EXPECT_EQ(px.z, 0.0f);
        }
    }
    // A one-sided emitter facing up in object space, mirrored in x: glTF flips the winding
    // rule for negative determinants, so it must still emit upwards only.
    Scene m;
    addQuad(m, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, glm::vec3(0.0f), glm::vec3(2.0f));
    m.instances[0].transform = glm::mat4(glm::vec4(-1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0),
                                         glm::vec4(0, 0, 0, 1));
    Camera below = downCamera({0, -1, 0}, 0.5f);
    below.forward = {0, 1, 0};
    EXPECT_EQ(meanRgb(render(m, downCamera({0, 1, 0}, 0.5f), 4, 4, quiet(1)).full), 2.0);
    EXPECT_EQ(meanRgb(render(m, below, 4, 4, quiet(1)).full), 0.0);
}

// DESIGN.md "Numerical stability": millimetre to kilometre scenes and extreme intensities.
// A furnace scaled by 1e-3 or 1e3 keeps L = Le (1 - p^3) / (1 - p) at k = 2 (ray offsets scale
// with the coordinates); radiance is linear in intensity from 1e-6 to 1e9 cd; degenerate
// triangles and zero normals in a mesh leave the image finite and unchanged elsewhere.
TEST(Reference, ScaleIntensityAndDegenerateGeometry) {
    for (float scale : {1e-3f, 1e3f}) {
        Scene s = furnace(0.5f);
        s.instances[0].transform = glm::mat4(scale);
        s.instances[0].transform[3][3] = 1.0f;
        Camera cam = *s.camera;
        cam.position *= scale;
        ReferenceImages img = render(s, cam, 16, 16, quiet(32, 2));
        EXPECT_NEAR(meanRgb(img.full), 1.75, 0.005 * 1.75) << "scale " << scale;
    }

    Scene plane;
    addQuad(plane, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50}, glm::vec3(0.5f));
    Light l;
    l.type = LightType::Point;
    l.position = {0.0f, 1.0f, 0.0f};
    l.intensity = 1.0f;
    plane.lights.push_back(l);
    Camera cam = downCamera({0.0f, 3.0f, 0.0f}, 1.0f);
    const ReferenceImages unit = render(plane, cam, 8, 8, quiet(1));
    for (float intensity : {1e-6f, 1e9f}) {
        plane.lights[0].intensity = intensity;
        ReferenceImages img = render(plane, cam, 8, 8, quiet(1));
        for (size_t i = 0; i < img.full.pixels.size(); ++i)
            EXPECT_NEAR(img.full.pixels[i].x / intensity, unit.full.pixels[i].x, 1e-5f * unit.full.pixels[i].x);
    }

    // Append a zero-area triangle, a sliver and zero-length normals to the plane's mesh.
    plane.lights[0].intensity = 1.0f;
    Mesh& m = plane.meshes[0];
    m.normals.assign(4, glm::vec3(0.0f, 1.0f, 0.0f));
    const uint32_t base = uint32_t(m.positions.size());
    for (glm::vec3 p : {glm::vec3(0, 0.5f, 0), glm::vec3(0, 0.5f, 0), glm::vec3(1, 0.5f, 0), glm::vec3(2, 0.5f, 0),
                        glm::vec3(2, 0.5f, 1e-9f), glm::vec3(3, 0.5f, 0)}) {
        m.positions.push_back(p);
        m.normals.push_back(glm::vec3(0.0f));
    }
    for (uint32_t i = 0; i < 6; ++i)
        m.indices.push_back(base + i);
    ReferenceImages img = render(plane, cam, 8, 8, quiet(2));
    EXPECT_EQ(countNonFinite(img.full), 0u);
    EXPECT_EQ(img.full.pixels, unit.full.pixels); // the degenerate triangles hide nothing here
}

// Inside a closed cube whose six faces all emit Le and reflect with albedo p, the radiance is
// Le / (1 - p) at every point, edges and corners included. A view into a corner puts many pixel
// centres within a hair of the three concave edges, where a path whose rays start behind an
// adjacent face loses light (and one whose MIS weights measure distances from the offset origin
// is biased near edges: with the old 32-ulp-of-the-largest-coordinate origin offset the image
// mean 800 m from the origin was 0.16% low, 15 sigma). 0.5% per pixel: the per-pixel standard
// deviation is 0.24% at 2048 spp (measured), ~0.1% at this sample count: 5 sigma per pixel.
TEST(Reference, CubeCornerFurnaceEveryPixel) {
    const float le = 1.0f, p = 0.5f;
    for (glm::vec3 offset : {glm::vec3(0.0f), glm::vec3(310.0f, 47.0f, -730.0f)}) {
        Scene s;
        const glm::vec3 o = offset;
        auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
            addQuad(s, o + a, o + d, o + c, o + b, glm::vec3(p), glm::vec3(le));
        };
        // Listed clockwise seen from inside the unit cube; quad() reverses them to face inwards.
        quad({0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}); // floor, faces +y
        quad({0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}); // ceiling, faces -y
        quad({0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}); // x = 0, faces +x
        quad({1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}); // x = 1, faces -x
        quad({0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}); // z = 0, faces +z
        quad({0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}); // z = 1, faces -z
        Camera cam;
        cam.position = o + glm::vec3(0.55f, 0.6f, 0.45f);
        cam.forward = glm::normalize(glm::vec3(-1.0f, -1.0f, 1.0f)); // the corner (0, 0, 1)
        cam.up = {0.0f, 1.0f, 0.0f};
        cam.yfov = 1.3f;
        const uint32_t n = 16;
        ReferenceImages img = render(s, cam, n, n, quiet(12288));
        const double expected = le / (1.0 - p);
        int bad = 0;
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const double v = img.full.at(x, y).x;
                if (std::abs(v - expected) > 0.005 * expected && bad++ < 5)
                    ADD_FAILURE() << "offset " << o.x << ": pixel " << x << "," << y << " = " << v;
            }
        EXPECT_EQ(bad, 0) << "offset " << o.x;
    }
}

// Two planes meeting at an edge, lit by a point light inside the wedge they form: the wedge
// is convex, so every point of both faces sees the light and the one-reflection image is
// L = p I cos / (pi d^2) per pixel, up to the edge. The camera looks along the edge at a slant,
// so pixel centres land at every distance from it. Right and acute (25 degree) wedges, near the
// origin and 800 m from it: a ray origin offset by a multiple of the coordinates' size (not of
// their float error along the normal) starts behind the adjacent face of an acute wedge, and
// those pixels go black (with the old offset 800 m out: pixels 0.4-6.2 mm from the edge). Pixels within the float resolution of the scene's coordinates
// (4 ulp) of the edge are ambiguous to any float renderer and are not judged; the test
// requires that they are few.
TEST(Reference, WedgeEdgeDirectLightEveryPixel) {
    constexpr double kDeg = kPi / 180.0;
    const float p = 0.6f, I = 5.0f;
    for (double alphaDeg : {90.0, 25.0})
        for (glm::vec3 offset : {glm::vec3(0.0f), glm::vec3(310.0f, 47.0f, -730.0f)}) {
            const float ca = float(std::cos(alphaDeg * kDeg)), sa = float(std::sin(alphaDeg * kDeg));
            const glm::vec3 o = offset;
            Scene s;
            // Floor y = 0 (x >= 0) faces +y; the other face rises from the edge x = y = 0 at
            // angle alpha and faces into the wedge.
            const float len = 3.0f, zr = 3.0f;
            addQuad(s, o + glm::vec3(0, 0, zr), o + glm::vec3(len, 0, zr), o + glm::vec3(len, 0, -zr),
                    o + glm::vec3(0, 0, -zr), glm::vec3(p));
            const glm::vec3 up(len * ca, len * sa, 0.0f);
            addQuad(s, o + glm::vec3(0, 0, -zr), o + up + glm::vec3(0, 0, -zr), o + up + glm::vec3(0, 0, zr),
                    o + glm::vec3(0, 0, zr), glm::vec3(p));
            const glm::vec3 nFloor(0, 1, 0), nWall(sa, -ca, 0);
            const float half = float(alphaDeg * kDeg / 2.0);
            Light l;
            l.type = LightType::Point;
            l.position = o + 1.2f * glm::vec3(std::cos(half), std::sin(half), 0.0f) + glm::vec3(0, 0, 0.4f);
            l.intensity = I;
            s.lights.push_back(l);

            Camera cam;
            const glm::vec3 bis(std::cos(half), std::sin(half), 0.0f);
            cam.position = o + 0.6f * bis + glm::vec3(0, 0, -0.9f);
            const glm::vec3 target = o + glm::vec3(0, 0, 0.2f);
            cam.forward = glm::normalize(target - cam.position);
            cam.up = glm::normalize(glm::vec3(-bis.y, bis.x, 0.0f) + glm::vec3(0.0f, 0.0f, 0.3f));
            cam.yfov = 0.7f;
            const uint32_t w = 64, h = 64;
            ReferenceImages img = render(s, cam, w, h, quiet(1, 1));

            // The float resolution of the coordinates: 4 ulp of the largest one.
            const double res = 4.0 * std::ldexp(1.0, std::ilogb(std::max({std::abs(o.x), std::abs(o.z), 1.0f})) - 23);
            int judged = 0, ambiguous = 0, bad = 0, edgeNear = 0;
            for (uint32_t y = 0; y < h; ++y)
                for (uint32_t x = 0; x < w; ++x) {
                    const glm::dvec3 dir(cam.pixelRayDirection(x, y, w, h));
                    const glm::dvec3 c = glm::dvec3(cam.position) - glm::dvec3(o);
                    // Ray against each face's plane; both planes contain the origin (the edge).
                    double best = std::numeric_limits<double>::infinity();
                    glm::dvec3 q(0.0), n(0.0);
                    for (int f = 0; f < 2; ++f) {
                        const glm::dvec3 nf = glm::dvec3(f == 0 ? nFloor : nWall);
                        const double t = -glm::dot(nf, c) / glm::dot(nf, dir);
                        const glm::dvec3 hit = c + t * dir;
                        const glm::dvec3 along = f == 0 ? glm::dvec3(1, 0, 0) : glm::dvec3(ca, sa, 0);
                        const double u = glm::dot(hit, along);
                        if (t > 0.0 && t < best && u >= 0.0 && u <= len && std::abs(hit.z) <= zr) {
                            best = t;
                            q = hit;
                            n = nf;
                        }
                    }
                    if (!std::isfinite(best))
                        continue;
                    const glm::dvec3 edgeDir(0, 0, 1);
                    const double distToEdge = glm::length(q - edgeDir * q.z);
                    if (distToEdge < res) {
                        ++ambiguous;
                        continue;
                    }
                    if (distToEdge < 0.01)
                        ++edgeNear;
                    const glm::dvec3 d = glm::dvec3(l.position) - glm::dvec3(o) - q;
                    const double dist = glm::length(d);
                    const double expected = p / kPi * I * std::max(0.0, glm::dot(n, d) / dist) / (dist * dist);
                    const double v = img.direct.at(x, y).x;
                    ++judged;
                    if (std::abs(v - expected) > 1e-3 * expected && bad++ < 5)
                        ADD_FAILURE() << "wedge " << alphaDeg << " deg, offset " << o.x << ": pixel " << x << ","
                                      << y << " at " << distToEdge * 1e3 << " mm from the edge = " << v
                                      << ", expected " << expected;
                }
            EXPECT_EQ(bad, 0) << "wedge " << alphaDeg << " deg, offset " << o.x;
            EXPECT_GT(judged, int(w * h) * 9 / 10);
            EXPECT_LE(ambiguous, judged / 100);
            EXPECT_GE(edgeNear, 8) << "the view must put pixel centres within 1 cm of the edge";
        }
}

// A bounce image = the direct part of the unbounded one, to the bit: the same random streams,
// the same path prefix, the same summation order.
TEST(Reference, DirectMatchesOneBounceRenderAndFullIsTheSum) {
    Result<Scene> s = makeBuiltinScene("cornell_emissive");
    ASSERT_TRUE(s.ok()) << s.error().message;
    ReferenceImages all = render(*s, *s->camera, 16, 16, quiet(4));
    ReferenceImages one = render(*s, *s->camera, 16, 16, quiet(4, 1));
    ASSERT_EQ(all.direct.pixels.size(), one.full.pixels.size());
    for (size_t i = 0; i < all.direct.pixels.size(); ++i) {
        EXPECT_EQ(all.direct.pixels[i], one.full.pixels[i]) << i;
        glm::vec3 sum = all.direct.pixels[i] + all.indirect.pixels[i];
        EXPECT_NEAR(all.full.pixels[i].x, sum.x, 1e-5f * (1.0f + sum.x)); // float rounding of the split
    }
    EXPECT_GT(meanRgb(all.indirect), 0.0);
    EXPECT_GT(all.rays, 16u * 16u * 4u);
}

TEST(Reference, DeterministicAcrossRunsAndThreadCounts) {
    Result<Scene> s = makeBuiltinScene("cornell");
    ASSERT_TRUE(s.ok()) << s.error().message;
    ReferenceImages a = render(*s, *s->camera, 16, 12, quiet(4));
    ReferenceImages b = render(*s, *s->camera, 16, 12, quiet(4));
    ReferenceImages c;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        c = render(*s, *s->camera, 16, 12, quiet(4));
    }
    ReferenceImages d = render(*s, *s->camera, 16, 12, quiet(4, -1, 2));
    ASSERT_EQ(a.full.pixels.size(), 16u * 12u);
    EXPECT_EQ(a.full.pixels, b.full.pixels);
    EXPECT_EQ(a.indirect.pixels, b.indirect.pixels);
    EXPECT_EQ(a.full.pixels, c.full.pixels);
    EXPECT_EQ(a.rays, c.rays);
    EXPECT_NE(a.full.pixels, d.full.pixels); // the seed matters
}

TEST(Reference, BadInputIsAOneLineError) {
    Scene s = furnace(0.5f);
    Camera cam = *s.camera;
    auto expectError = [](const Result<ReferenceImages>& r, const char* what) {
        ASSERT_FALSE(r.ok()) << what;
        EXPECT_FALSE(r.error().message.empty());
        EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
    };
    expectError(renderReference(Scene{}, cam, 8, 8, quiet(1)), "empty scene");
    expectError(renderReference(s, cam, 0, 8, quiet(1)), "width 0");
    expectError(renderReference(s, cam, 8, 0, quiet(1)), "height 0");
    expectError(renderReference(s, cam, 16385, 8, quiet(1)), "width > 16384");
    expectError(renderReference(s, cam, 8, 8, quiet(0)), "spp 0");
    expectError(renderReference(s, cam, 8, 8, quiet(1, -2)), "maxBounces -2");
    Scene nanLight = s;
    Light l;
    l.name = "broken";
    l.intensity = std::numeric_limits<float>::quiet_NaN();
    nanLight.lights.push_back(l);
    Result<ReferenceImages> r = renderReference(nanLight, cam, 8, 8, quiet(1));
    expectError(r, "NaN light");
    if (!r.ok()) {
        EXPECT_NE(r.error().message.find("broken"), std::string::npos) << r.error().message;
    }
    Scene nanVertex = s;
    nanVertex.meshes[0].positions[0].y = std::numeric_limits<float>::infinity();
    expectError(renderReference(nanVertex, cam, 8, 8, quiet(1)), "Inf vertex");
    Scene badIndex = s;
    badIndex.meshes[0].indices[0] = 1u << 30;
    expectError(renderReference(badIndex, cam, 8, 8, quiet(1)), "index out of range");
}

TEST(Reference, CacheStoresAndReloads) {
    namespace fs = std::filesystem;
    const fs::path dir = test::outputDir() / "reference_cache";
    fs::remove_all(dir);
    ASSERT_EQ(setenv("VKGI_CACHE_DIR", dir.c_str(), 1), 0);
    Scene s = furnace(0.5f);
    const ReferenceSettings st = quiet(2);
    const fs::path file = referenceCacheFile(s, *s.camera, 8, 8, st);
    EXPECT_EQ(file.parent_path(), dir);

    bool cached = true;
    Result<ReferenceImages> first = renderReferenceCached(s, *s.camera, 8, 8, st, &cached);
    ASSERT_TRUE(first.ok()) << first.error().message;
    EXPECT_FALSE(cached);
    EXPECT_TRUE(fs::exists(file));
    Result<ReferenceImages> second = renderReferenceCached(s, *s.camera, 8, 8, st, &cached);
    ASSERT_TRUE(second.ok()) << second.error().message;
    EXPECT_TRUE(cached);
    EXPECT_EQ(first->full.pixels, second->full.pixels);
    EXPECT_EQ(first->direct.pixels, second->direct.pixels);
    EXPECT_EQ(first->indirect.pixels, second->indirect.pixels);
    EXPECT_EQ(first->rays, second->rays);

    // The key follows what changes the image, and only that.
    ReferenceSettings noisy = st;
    noisy.progress = !st.progress;
    EXPECT_EQ(referenceCacheFile(s, *s.camera, 8, 8, noisy), file);
    Scene renamed = s;
    renamed.name = "other name";
    EXPECT_EQ(referenceCacheFile(renamed, *s.camera, 8, 8, st), file);
    EXPECT_NE(referenceCacheFile(s, *s.camera, 8, 8, quiet(3)), file);
    EXPECT_NE(referenceCacheFile(s, *s.camera, 8, 9, st), file);
    Scene brighter = furnace(0.5f, 1.5f);
    EXPECT_NE(referenceCacheFile(brighter, *s.camera, 8, 8, st), file);
    Camera moved = *s.camera;
    moved.position.x += 1e-3f;
    EXPECT_NE(referenceCacheFile(s, moved, 8, 8, st), file);

    // A damaged entry is a miss, not an error: it is rendered again.
    fs::resize_file(file, 10);
    Result<ReferenceImages> third = renderReferenceCached(s, *s.camera, 8, 8, st, &cached);
    ASSERT_TRUE(third.ok()) << third.error().message;
    EXPECT_FALSE(cached);
    EXPECT_EQ(first->full.pixels, third->full.pixels);
    unsetenv("VKGI_CACHE_DIR");
}
