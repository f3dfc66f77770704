// VCT through GiSystem against the path tracer with the same bounce count, on built-in scenes
// at 64^2: relMSE of the full image and of the indirect part (composite - direct against
// reference - direct), compared with the best constant ambient term added to the direct image.
#include <cmath>
#include <cstdio>

#include "engine/builtin_scenes.hpp"
#include "engine/image_metrics.hpp"
#include "gi/gi.hpp"
#include "gi/reference.hpp"
#include "support/gpu_fixture.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kSize = 64;

// direct + c with the per-channel constant c that minimises relMSE against `ref`:
// d/dc sum w (d + c - r)^2 = 0 with w = 1 / (r^2 + eps) gives c = sum w (r - d) / sum w.
HdrImage bestAmbient(const HdrImage& direct, const HdrImage& ref, float eps = 0.01f) {
    glm::dvec3 num(0.0), den(0.0);
    for (size_t i = 0; i < ref.pixels.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            double r = ref.pixels[i][k];
            double w = 1.0 / (r * r + eps);
            num[k] += w * (r - direct.pixels[i][k]);
            den[k] += w;
        }
    HdrImage out = direct;
    for (glm::vec3& p : out.pixels)
        p += glm::vec3(num / den);
    return out;
}

struct Errors {
    double full, indirect, ambientFull, ambientIndirect;
};

class VctReference : public test::GpuTest {
protected:
    Errors measure(const char* sceneName, const VctSettings& vct) {
        auto scene = makeBuiltinScene(sceneName);
        EXPECT_TRUE(scene.ok()) << scene.error().message;
        if (!scene.ok())
            return {};
        GiSettings settings;
        settings.technique = Technique::Vct;
        settings.vct = vct;
        auto gi = GiSystem::create(ctx(), settings);
        EXPECT_TRUE(gi.ok()) << gi.error().message;
        auto set = (*gi)->setScene(*scene);
        EXPECT_TRUE(set.ok()) << set.error().message;
        Camera camera = scene->cameraOrDefault();
        FrameRequest request;
        request.direct = true;
        auto frame = (*gi)->renderFrame(camera, kSize, kSize, request);
        EXPECT_TRUE(frame.ok()) << frame.error().message;
        if (!frame.ok())
            return {};
        ReferenceSettings rs;
        rs.spp = 256; // reference noise (relMSE ~1e-3 on these scenes) well below the errors compared
        rs.maxBounces = int(vct.bounces) + 1; // the light reaches voxels after one reflection
        rs.progress = false;
        auto ref = renderReferenceCached(*scene, camera, kSize, kSize, rs);
        EXPECT_TRUE(ref.ok()) << ref.error().message;
        if (!ref.ok())
            return {};
        auto full = compareImages(frame->composite, ref->full);
        auto testIndirect = subtract(frame->composite, frame->direct);
        auto refIndirect = subtract(ref->full, frame->direct);
        auto indirect = compareImages(*testIndirect, *refIndirect);
        auto ambient = compareImages(bestAmbient(frame->direct, ref->full), ref->full);
        HdrImage zero = *refIndirect;
        for (glm::vec3& p : zero.pixels)
            p = glm::vec3(0.0f);
        auto ambientIndirect = compareImages(bestAmbient(zero, *refIndirect), *refIndirect);
        Errors e{full->relMse, indirect->relMse, ambient->relMse, ambientIndirect->relMse};
        double meanTest = 0.0, meanRef = 0.0;
        for (size_t i = 0; i < testIndirect->pixels.size(); ++i) {
            meanTest += double(testIndirect->pixels[i].x + testIndirect->pixels[i].y + testIndirect->pixels[i].z);
            meanRef += double(refIndirect->pixels[i].x + refIndirect->pixels[i].y + refIndirect->pixels[i].z);
        }
        m_lastMeanRatio = meanTest / meanRef;
        EXPECT_EQ(countNonFinite(frame->composite), 0u) << sceneName;
        double ms = 0.0, lightMs = 0.0;
        for (const auto& p : frame->passes) {
            if (p.name.rfind("gi.v", 0) == 0)
                ms += p.ms;
            if (p.name == "gi.vct.light")
                lightMs = p.ms;
        }
        std::printf("%s: relMSE full %.4f (best ambient %.4f), indirect %.4f (best constant %.4f); VCT passes %.1f ms (voxel light %.1f)\n",
                    sceneName, e.full, e.ambientFull, e.indirect, e.ambientIndirect, ms, lightMs);
        return e;
    }
    // Mean indirect of the last measure() over the reference's (rgb summed over the pixels).
    double m_lastMeanRatio = 0.0;
};

} // namespace

// Measured on lavapipe (Mesa 22.3.6), 32^3 grid, 6 cones of 30 degrees, 2 bounces, cones at
// half resolution with the discontinuity refine, 64^2 pixels (relMSE with epsilon 0.01; the
// reference has 3 reflections, as VCT: direct, voxel, bounce). "constant" is the best
// constant colour: added to the direct image (full) or alone (indirect only).
//   scene             full    constant   indirect  constant  (before the cone fixes of 2026-11-23)
//   cornell           0.0579  0.251      0.0842    0.356     (0.192 / 0.287)
//   cornell_point     0.147   0.267      0.542     0.579     (0.669 / 2.14)
//   cornell_emissive  0.324   0.494      0.325     0.498     (1.10 / 1.37)
//   room              941     9.05       929       0.944     (945 / 936)
//   atrium            2.61    1.18       14.3      0.868     (2.07 / 8.99)
// Both renderers are deterministic, so the bounds only allow for driver/compiler changes: 20%
// above the measurement. The three Cornell boxes beat the constant baselines (the point-lit
// box's indirect part only just). In the sun-lit room and atrium the lit outer faces of roofs
// and walls one or two voxels thick leak into the interior through the side views of the
// anisotropic mips (docs/vct.md); the atrium got worse with the extinction-weighted views.
TEST_F(VctReference, BuiltinScenesAgainstThePathTracer) {
    struct Case {
        const char* scene;
        double full, indirect;
        bool beatsConstant;
    } cases[] = {{"cornell", 0.0579, 0.0842, true},
                 {"cornell_point", 0.147, 0.542, true},
                 {"cornell_emissive", 0.324, 0.325, true},
                 {"room", 941.0, 929.0, false},
                 {"atrium", 2.61, 14.3, false}};
    VctSettings s;
    s.gridResolution = 32;
    for (const Case& c : cases) {
        Errors e = measure(c.scene, s);
        EXPECT_LT(e.full, 1.2 * c.full) << c.scene;
        EXPECT_LT(e.indirect, 1.2 * c.indirect) << c.scene;
        if (c.beatsConstant) {
            EXPECT_LT(e.full, e.ambientFull) << c.scene;
            EXPECT_LT(e.indirect, e.ambientIndirect) << c.scene;
        }
    }
}

// Full-resolution cones (lowResFactor 1) against the default half resolution on the spot-lit
// box: the upsample with its discontinuity refine changes the error by under 5% (measured:
// full 0.0579 at half vs 0.0601 at full resolution, indirect 0.0842 vs 0.0873).
TEST_F(VctReference, HalfResolutionConesMatchFullResolution) {
    VctSettings s;
    s.gridResolution = 32;
    Errors half = measure("cornell", s);
    s.lowResFactor = 1;
    Errors full = measure("cornell", s);
    EXPECT_LT(std::abs(half.full - full.full), 0.05 * full.full);
    EXPECT_LT(std::abs(half.indirect - full.indirect), 0.05 * full.indirect);
}

// Voxel light occluded by the direct-light shadow atlas instead of the hard occupancy march, on
// the spot-lit box. Measured: full 0.0571 (march 0.0579), indirect 0.0866 (march 0.0842); the
// constants are 0.251 and 0.356. Bounds: the measurements + 20%, as above, and both parts
// still beat the best constant.
TEST_F(VctReference, ShadowMapOcclusionAgainstThePathTracer) {
    VctSettings s;
    s.gridResolution = 32;
    s.occlusion = VctOcclusion::ShadowMap;
    Errors e = measure("cornell", s);
    EXPECT_LT(e.full, 1.2 * 0.0571);
    EXPECT_LT(e.indirect, 1.2 * 0.0866);
    EXPECT_LT(e.full, e.ambientFull);
    EXPECT_LT(e.indirect, e.ambientIndirect);
}

// A consistent discretisation converges: on the spot-lit box the indirect error must not grow
// when the grid is refined. Before the fixes of 2026-11-23 it doubled from 32^3 to 64^3
// (indirect relMSE 0.287 -> 0.578, 128^3: 1.06): wide cones read their own surface through the
// trilinear footprint of coarse levels, and the hard shadow march stopped at the light's own
// voxel, which the ceiling 1 cm above the light occupies at 32^3 (mean indirect 0.56 of the
// reference at 32^3, 1.12 at 128^3). Measured now (2 bounces, full-resolution cones, the
// reference's mean indirect in brackets): 32^3 0.0873 (mean 1.055x), 64^3 0.0842 (1.048x),
// 128^3 0.104 (0.78x; not run here: tests keep grids small). 5% above the 32^3 error allows
// for driver changes; the mean must be within 10% of the reference at both grids.
TEST_F(VctReference, IndirectErrorDoesNotGrowWithTheGrid) {
    VctSettings s;
    s.lowResFactor = 1;
    s.gridResolution = 32;
    Errors coarse = measure("cornell", s);
    double coarseMean = m_lastMeanRatio;
    s.gridResolution = 64;
    Errors fine = measure("cornell", s);
    double fineMean = m_lastMeanRatio;
    EXPECT_LE(fine.indirect, 1.05 * coarse.indirect);
    EXPECT_LT(coarse.indirect, 0.1);
    EXPECT_NEAR(coarseMean, 1.0, 0.1);
    EXPECT_NEAR(fineMean, 1.0, 0.1);
}

TEST_F(VctReference, TechniqueIsRegisteredAndBadSettingsAreErrors) {
    auto parsed = parseTechnique("vct");
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    EXPECT_EQ(*parsed, Technique::Vct);
    GiSettings settings;
    settings.technique = Technique::Vct;
    settings.vct.gridResolution = 48;
    auto gi = GiSystem::create(ctx(), settings);
    ASSERT_FALSE(gi.ok());
    EXPECT_NE(gi.error().message.find("gridResolution 48"), std::string::npos) << gi.error().message;
    settings.vct = {};
    settings.vct.diffuseCones = 0;
    gi = GiSystem::create(ctx(), settings);
    ASSERT_FALSE(gi.ok());
    EXPECT_NE(gi.error().message.find("diffuseCones"), std::string::npos) << gi.error().message;
}

// A scene lit only by an emissive surface still gets indirect light from it, finite everywhere.
TEST_F(VctReference, EmissiveOnlySceneGetsIndirectLight) {
    auto scene = makeBuiltinScene("cornell_emissive");
    ASSERT_TRUE(scene.ok());
    ASSERT_TRUE(scene->lights.empty());
    GiSettings settings;
    settings.technique = Technique::Vct;
    settings.vct.gridResolution = 32;
    auto gi = GiSystem::create(ctx(), settings);
    ASSERT_TRUE(gi.ok()) << gi.error().message;
    ASSERT_TRUE((*gi)->setScene(*scene).ok());
    FrameRequest request;
    request.direct = true;
    auto frame = (*gi)->renderFrame(scene->cameraOrDefault(), 32, 32, request);
    ASSERT_TRUE(frame.ok()) << frame.error().message;
    double indirect = 0.0;
    for (size_t i = 0; i < frame->composite.pixels.size(); ++i) {
        glm::vec3 d = frame->composite.pixels[i] - frame->direct.pixels[i];
        indirect += d.x + d.y + d.z;
    }
    EXPECT_EQ(countNonFinite(frame->composite), 0u);
    EXPECT_GT(indirect / frame->composite.pixels.size(), 0.1); // measured 1.1 per pixel (sum of rgb)
}

