// VPL visibility (vpl.visibility: each VPL's light marched through the shared voxel grid's
// occupancy) through GiSystem against the path tracer, on the built-in scenes where light
// reaches surfaces the VPLs cannot see: the sun-lit room and atrium (VPLs on the sunny ground
// outside light the inner walls through them without visibility) and the hall (pillars and a
// vase between the lamp-lit floor and the walls). 64^2, 256 spp, against the reference with
// the bounce the technique models (two reflections: light -> surface -> receiver -> eye), and
// against the best constant ambient term for that indirect image. Against the unbounded
// reference a one-bounce technique misses the light of further bounces, which in the atrium
// and the hall the leaked light happened to stand in for (docs/vpl.md).
#include <cstdio>
#include <string>
#include <vector>

#include "vkgi/image_metrics.hpp"
#include "vkgi/gi.hpp"
#include "vkgi/reference.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/image_stats.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kSize = 64;

// A quad a, b, c, d (counter-clockwise seen from the side it faces) appended to `m`.
void addQuad(Mesh& m, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    const uint32_t base = uint32_t(m.positions.size());
    for (const glm::vec3& p : {a, b, c, d}) {
        m.positions.push_back(p);
        m.normals.push_back(n);
    }
    for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u})
        m.indices.push_back(base + i);
}

// An axis-aligned box [lo, hi] seen from outside.
void addSolidBox(Mesh& m, glm::vec3 lo, glm::vec3 hi) {
    const glm::vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                            {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    addQuad(m, c[0], c[3], c[2], c[1]); // -z
    addQuad(m, c[4], c[5], c[6], c[7]); // +z
    addQuad(m, c[0], c[4], c[7], c[3]); // -x
    addQuad(m, c[1], c[2], c[6], c[5]); // +x
    addQuad(m, c[0], c[1], c[5], c[4]); // -y
    addQuad(m, c[3], c[7], c[6], c[2]); // +y
}

// Two 2 x 2 x 2 m rooms side by side (x < 0: A, x > 0: B), closed all round, separated by a
// 0.1 m wall with a 0.6 x 1.4 m doorway. A spotlight in A lights A's floor; the camera stands
// in B at the wall and looks at B's far wall (x = 2), which faces A's lit floor through the
// dividing wall: without visibility the VPLs light it through the wall, with it only what
// comes through the door remains.
Scene twoRooms() {
    Scene s;
    s.name = "two_rooms";
    Mesh m;
    const float x0 = -2.0f, x1 = 2.0f, y0 = 0.0f, y1 = 2.0f, z0 = -1.0f, z1 = 1.0f;
    addQuad(m, {x0, y0, z0}, {x0, y0, z1}, {x1, y0, z1}, {x1, y0, z0}); // floor, facing +y
    addQuad(m, {x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1}); // ceiling, facing -y
    addQuad(m, {x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0}); // z = -1, facing +z
    addQuad(m, {x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1}); // z = +1, facing -z
    addQuad(m, {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1}); // x = -2, facing +x
    addQuad(m, {x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0}); // x = +2, facing -x
    addSolidBox(m, {-0.05f, y0, z0}, {0.05f, y1, -0.3f}); // the dividing wall beside the door
    addSolidBox(m, {-0.05f, y0, 0.3f}, {0.05f, y1, z1});
    addSolidBox(m, {-0.05f, 1.4f, -0.3f}, {0.05f, y1, 0.3f}); // above the door
    s.meshes.push_back(m);
    Material mat;
    mat.baseColor = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
    s.materials.push_back(mat);
    s.instances.push_back({});
    Light spot;
    spot.name = "spot";
    spot.type = LightType::Spot;
    spot.position = {-1.0f, 1.9f, 0.0f};
    spot.direction = {0.0f, -1.0f, 0.0f};
    spot.intensity = 20.0f;
    spot.outerConeAngle = 0.7f;
    spot.innerConeAngle = 0.6f;
    s.lights.push_back(spot);
    Camera c;
    c.position = {0.15f, 1.0f, 0.0f};
    c.forward = {1.0f, 0.0f, 0.0f};
    c.up = {0.0f, 1.0f, 0.0f};
    c.yfov = 1.0471976f; // 60 degrees
    c.znear = 0.01f;
    c.zfar = 10.0f;
    s.camera = c;
    return s;
}

struct IndirectErrors {
    double off = 0.0, on = 0.0, ambient = 0.0;               // relMSE of the indirect image (eps 0.01)
    double meanOff = 0.0, meanOn = 0.0, meanReference = 0.0; // the indirect image's sum
};

class VplVisibility : public test::GpuTest {
protected:
    // The VPL indirect image (composite - direct) with visibility off and on against the path
    // tracer's own indirect (its paths of exactly two reflections), and the best constant for
    // that indirect image.
    IndirectErrors measure(const std::string& sceneName) { return measure(test::builtinScene(sceneName)); }
    IndirectErrors measure(const Scene& scene, uint32_t grid = 64) {
        const std::string& sceneName = scene.name;
        Camera camera = scene.cameraOrDefault();
        ReferenceSettings rs;
        rs.spp = 256;
        rs.maxBounces = 2;
        rs.progress = false;
        auto ref = renderReferenceCached(scene, camera, kSize, kSize, rs);
        EXPECT_TRUE(ref.ok()) << ref.error().message;
        if (!ref.ok())
            return {};
        IndirectErrors e;
        for (bool visibility : {false, true}) {
            GiSettings settings;
            settings.technique = Technique::Vpl;
            settings.vpl.visibility = visibility ? VplVisibilityMode::On : VplVisibilityMode::Off;
            settings.vpl.bounces = 1; // the one bounce the matched reference has
            settings.vpl.visibilityGrid = grid;
            FrameRequest request;
            request.direct = true;
            auto frame = test::renderOnce(ctx(), settings, scene, camera, kSize, kSize, request);
            EXPECT_TRUE(frame.ok()) << frame.error().message;
            if (!frame.ok())
                return {};
            EXPECT_EQ(countNonFinite(frame->composite), 0u) << sceneName;
            auto indirect = subtract(frame->composite, frame->direct);
            (visibility ? e.on : e.off) = compareImages(*indirect, ref->indirect)->relMse;
            (visibility ? e.meanOn : e.meanOff) = test::sumRgb(*indirect);
            if (visibility) {
                HdrImage zero = *indirect;
                for (glm::vec3& p : zero.pixels)
                    p = glm::vec3(0.0f);
                e.ambient = compareImages(bestAmbient(zero, ref->indirect, surfacePixels(frame->composite, ref->full)),
                                          ref->indirect)
                                ->relMse;
            }
        }
        e.meanReference = test::sumRgb(ref->indirect);
        std::printf("%s: indirect relMSE without visibility %.4f, with %.4f, best constant %.4f; indirect sum over "
                    "the path tracer's %.3f without, %.3f with\n",
                    sceneName.c_str(), e.off, e.on, e.ambient, e.meanOff / e.meanReference, e.meanOn / e.meanReference);
        return e;
    }
};

} // namespace

// Measured at 64^2 (256 spp): room 18.4 -> 15.3 (best constant 0.56), atrium 1053 -> 4.98
// (0.86), hall 1.25 -> 0.134 (0.64). The room's and atrium's relMSE is dominated by a few
// pixels the reference has black (seen through the window openings) that the VPLs still light:
// visibility does not beat the constant there (docs/vpl.md, known limits).
TEST_F(VplVisibility, SunLitRoomLosesTheLightThroughItsWalls) {
    IndirectErrors e = measure("room");
    EXPECT_LT(e.on, 0.9 * e.off);
}

TEST_F(VplVisibility, SunLitAtriumLosesTheLightThroughItsWalls) {
    IndirectErrors e = measure("atrium");
    EXPECT_LT(e.on, 0.05 * e.off);
}

// The hall's lamp lights the floor; pillars and the vase stand between floor VPLs and the walls.
TEST_F(VplVisibility, HallBeatsTheBestConstant) {
    IndirectErrors e = measure("hall");
    EXPECT_LT(e.on, e.ambient);
    EXPECT_LT(e.on, 0.25 * e.off);
}

// The two-room test: the far wall of room B, which faces the lit floor of room A
// through the dividing wall, gets only what comes through the door. The grid's conservative
// voxels narrow the 0.6 m doorway by about a voxel on each side (6 cm at 64^3 over the 4 m
// scene), so the light through it approaches the path tracer's as the grid refines (measured
// 0.72, 0.83, 0.89 of it at 32^3, 64^3, 128^3; without visibility 2.2). At 128^3 a doorway
// narrowed by a 3 cm voxel on each side passes 0.9 of the light. (Before the march sampled
// every segment inside the grid every 0.75 voxel, a segment longer than 48 voxels got 64
// samples spread over it, which at 128^3 skipped voxels of the door's jambs and let 0.97
// through.) Within 15 % at 128^3.
TEST_F(VplVisibility, TwoRoomsLightOnlyThroughTheDoor) {
    std::vector<double> ratio;
    for (uint32_t grid : {32u, 64u, 128u}) {
        IndirectErrors e = measure(twoRooms(), grid);
        ratio.push_back(e.meanOn / e.meanReference);
        EXPECT_GT(e.meanOff / e.meanReference, 1.5) << "without visibility the light comes through the wall";
        EXPECT_LT(e.on, e.ambient) << grid;
    }
    EXPECT_LT(ratio[0], ratio[1]);
    EXPECT_LT(ratio[1], ratio[2]);
    EXPECT_NEAR(ratio[2], 1.0, 0.15);
}
