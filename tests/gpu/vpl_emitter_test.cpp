// Emitter VPLs (docs/vpl.md, "Emitter VPLs"): the first generation of instant radiosity on the
// emissive surfaces themselves. Their summed flux is the emitted power; their light on a floor
// under a small emissive square is the square's form-factor irradiance; and on cornell_emissive
// (lit by its emissive ceiling quad alone) the VPL frame beats the best constant against the
// path tracer.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "vkgi/gi.hpp"
#include "vkgi/image_metrics.hpp"
#include "vkgi/reference.hpp"
#include "vkgi/vpl.hpp"
#include "gi/vpl.h"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/gpu_util.hpp"
#include "support/test_scenes.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kSize = 64;
constexpr double kPi = 3.14159265358979;

// Sum of pi Le A over the scene's emitting triangle sides (both sides when double-sided), per
// channel: the power the emitters send out, in the VPLs' cd*sr.
glm::dvec3 emittedPower(const Scene& scene) {
    glm::dvec3 sum(0.0);
    for (const Instance& inst : scene.instances) {
        const Mesh& mesh = scene.meshes[inst.mesh];
        const Material& m = scene.materials[mesh.material];
        for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            glm::dvec3 p[3];
            for (int j = 0; j < 3; ++j)
                p[j] = glm::dvec3(inst.transform * glm::vec4(mesh.positions[mesh.indices[3 * t + j]], 1.0f));
            const double area = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
            sum += kPi * area * (m.doubleSided ? 2.0 : 1.0) * glm::dvec3(m.emission);
        }
    }
    return sum;
}

// A 20 m floor (albedo 0.5) under a square of side `side` at height `height`, emitting Le = 1
// nit downwards, seen from halfway up (the square stays out of view).
Scene squareOverFloor(float side, float height) {
    Scene s = test::plane(0.5f, 10.0f);
    s.name = "square_over_floor";
    Mesh m;
    const float h = 0.5f * side;
    m.positions = {{-h, height, -h}, {h, height, -h}, {h, height, h}, {-h, height, h}};
    m.normals.assign(4, glm::vec3(0, -1, 0));
    m.indices = {0, 1, 2, 0, 2, 3}; // counter-clockwise seen from below: the front faces down
    Material glow;
    glow.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    glow.emission = glm::vec3(1.0f);
    m.material = uint32_t(s.materials.size());
    s.materials.push_back(glow);
    s.meshes.push_back(m);
    Instance inst;
    inst.mesh = uint32_t(s.meshes.size() - 1);
    s.instances.push_back(inst);
    Camera c;
    c.position = {0.0f, 0.5f * height, 0.0f};
    c.forward = {0.0f, -1.0f, 0.0f};
    c.up = {0.0f, 0.0f, -1.0f};
    c.yfov = 1.0471976f;
    c.znear = 0.01f;
    c.zfar = 10.0f;
    s.camera = c;
    return s;
}

class VplEmitter : public test::GpuTest {
protected:
    // The VPL records of one frame of `scene` with `vpl`: an emissive scene without lights must
    // run the VPL passes.
    std::vector<gpu::VplRecord> records(const Scene& scene, const VplSettings& vpl) {
        GiSettings s;
        s.technique = Technique::Vpl;
        s.vpl = vpl;
        return test::vplRecords(ctx(), s, scene, kSize);
    }
};

} // namespace

// The emitter VPLs carry exactly the emitted power: one surfel per VPL, the surfels' weights sum
// to 1 per emitting side, and each carries pi Le x its share of the side's area. The only error
// is float rounding of the areas (1e-4 relative). Checked in the full and the interleaved layout,
// and with a bounced generation after the emitters' (whose records must not count).
TEST_F(VplEmitter, TotalFluxIsTheEmittedPower) {
    const Scene scene = test::builtinScene("cornell_emissive");
    ASSERT_TRUE(scene.lights.empty() && scene.hasEmission());
    const glm::dvec3 expected = emittedPower(scene);
    for (uint32_t interleave : {1u, 4u})
        for (uint32_t bounces : {1u, 2u}) {
            VplSettings v;
            v.interleave = interleave;
            v.bounces = bounces;
            v.visibility = VplVisibilityMode::Off;
            const std::vector<gpu::VplRecord> r = records(scene, v);
            ASSERT_EQ(r.size(), size_t(bounces * v.vplCount));
            glm::dvec3 sum(0.0);
            uint32_t emitterVpls = 0;
            for (uint32_t i = 0; i < r.size(); ++i) {
                // One source per generation (the emitters); generation 0 has no parent.
                if (gpu::vplParentRecord(i, interleave, 1u, bounces, v.vplCount) != ~0u)
                    continue;
                ++emitterVpls;
                EXPECT_GT(r[i].position.w, 0.0f) << "record " << i;
                EXPECT_LT(r[i].direction.y, -0.99f) << "the ceiling quad emits downwards";
                EXPECT_GT(r[i].flux.w, 0.0f) << "footprint";
                sum += glm::dvec3(r[i].flux);
            }
            EXPECT_EQ(emitterVpls, v.vplCount);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(sum[c] / expected[c], 1.0, 1e-4)
                    << "interleave " << interleave << ", bounces " << bounces << ", channel " << c;
        }
}

// A square of side a and radiance Le, parallel to a floor at height h, gives the point below its
// centre the irradiance of four corner rectangles (the form factor of a point to a parallel
// rectangle): E = 4 Le X / sqrt(1 + X^2) atan(X / sqrt(1 + X^2)), X = a / 2h. The floor (albedo
// rho) then reflects rho / pi E. The VPLs are stratified points of the square, a 16th of its
// side apart at 256 and far from the floor, so their sum is the integral within a fraction of a
// percent; the pixels average a 4 x 4 block at the centre (within 0.6 % of the centre's value
// at a = 0.5, h = 1). Stated tolerance 2 %.
TEST_F(VplEmitter, SquareOverAFloorGivesItsFormFactorIrradiance) {
    const float side = 0.5f, height = 1.0f;
    const Scene scene = squareOverFloor(side, height);
    const double x = side / (2.0 * height), q = x / std::sqrt(1.0 + x * x);
    const double expected = 0.5 / kPi * 4.0 * q * std::atan(q);
    for (uint32_t interleave : {1u, 4u}) {
        GiSettings settings;
        settings.technique = Technique::Vpl;
        settings.vpl.interleave = interleave;
        FrameRequest request;
        request.direct = true;
        auto frame = test::renderOnce(ctx(), settings, scene, scene.cameraOrDefault(), kSize, kSize, request);
        ASSERT_TRUE(frame.ok()) << frame.error().message;
        auto indirect = subtract(frame->composite, frame->direct);
        ASSERT_TRUE(indirect.ok());
        double sum = 0.0;
        for (uint32_t y = kSize / 2 - 2; y < kSize / 2 + 2; ++y)
            for (uint32_t xx = kSize / 2 - 2; xx < kSize / 2 + 2; ++xx)
                sum += indirect->pixels[y * kSize + xx].g;
        const double got = sum / 16.0;
        std::printf("interleave %u: floor radiance under the square %.6f, closed form %.6f\n", interleave, got, expected);
        EXPECT_NEAR(got / expected, 1.0, 0.02) << "interleave " << interleave;
    }
}

// cornell_emissive at the defaults against the all-bounce path tracer (256 spp, 64^2): the VPL
// frame (the raster direct image, which shows the emitter but lights nothing with it, plus the
// VPLs: the emitter's direct light and, with bounces, more) must beat the direct image plus the
// best constant (the best for each epsilon), in the full image at both epsilons the bench reports.
TEST_F(VplEmitter, CornellEmissiveBeatsTheBestConstant) {
    const Scene scene = test::builtinScene("cornell_emissive");
    const Camera camera = scene.cameraOrDefault();
    auto ref = test::allBounceReference(scene, camera, kSize, kSize);
    ASSERT_TRUE(ref.ok()) << ref.error().message;
    GiSettings settings;
    settings.technique = Technique::Vpl;
    FrameRequest request;
    request.direct = true;
    auto frame = test::renderOnce(ctx(), settings, scene, camera, kSize, kSize, request);
    ASSERT_TRUE(frame.ok()) << frame.error().message;
    EXPECT_EQ(countNonFinite(frame->composite), 0u);
    for (float epsilon : {0.01f, 0.001f}) {
        const HdrImage ambient =
            bestAmbient(frame->direct, ref->full, surfacePixels(frame->composite, ref->full), epsilon);
        const double vpl = compareImages(frame->composite, ref->full, epsilon)->relMse;
        const double constant = compareImages(ambient, ref->full, epsilon)->relMse;
        std::printf("cornell_emissive, epsilon %g: full relMSE vpl %.4f, best constant %.4f\n", epsilon, vpl, constant);
        EXPECT_LT(vpl, constant) << "epsilon " << epsilon;
    }
}
