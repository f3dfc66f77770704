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

#include "engine/image_metrics.hpp"
#include "gi/gi.hpp"
#include "gi/reference.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/image_stats.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kSize = 64;

struct IndirectErrors {
    double off = 0.0, on = 0.0, ambient = 0.0; // relMSE of the indirect image (eps 0.01)
};

class VplVisibility : public test::GpuTest {
protected:
    // The VPL indirect image (composite - direct) with visibility off and on against the path
    // tracer's own indirect (its paths of exactly two reflections), and the best constant for
    // that indirect image.
    IndirectErrors measure(const std::string& sceneName) {
        Scene scene = test::builtinScene(sceneName);
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
            settings.vpl.visibility = visibility;
            FrameRequest request;
            request.direct = true;
            auto frame = test::renderOnce(ctx(), settings, scene, camera, kSize, kSize, request);
            EXPECT_TRUE(frame.ok()) << frame.error().message;
            if (!frame.ok())
                return {};
            EXPECT_EQ(countNonFinite(frame->composite), 0u) << sceneName;
            auto indirect = subtract(frame->composite, frame->direct);
            (visibility ? e.on : e.off) = compareImages(*indirect, ref->indirect)->relMse;
            if (visibility) {
                HdrImage zero = *indirect;
                for (glm::vec3& p : zero.pixels)
                    p = glm::vec3(0.0f);
                e.ambient = compareImages(test::bestAmbient(zero, ref->indirect, test::surfacePixels(frame->composite, ref->full)),
                                          ref->indirect)
                                ->relMse;
            }
        }
        std::printf("%s: indirect relMSE without visibility %.4f, with %.4f, best constant %.4f\n", sceneName.c_str(),
                    e.off, e.on, e.ambient);
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
