// VCT through GiSystem against the path tracer with the same bounce count, on built-in scenes
// at 64^2: relMSE of the full image and of the indirect part (composite - direct against
// reference - direct), compared with the best constant ambient term added to the direct image.
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
    double full, indirect, ambientFull;
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
        Errors e{full->relMse, indirect->relMse, ambient->relMse};
        EXPECT_EQ(countNonFinite(frame->composite), 0u) << sceneName;
        double ms = 0.0;
        for (const auto& p : frame->passes)
            if (p.name.rfind("gi.v", 0) == 0)
                ms += p.ms;
        std::printf("%s: relMSE full %.4f, indirect %.4f, best ambient %.4f; VCT passes %.1f ms\n", sceneName,
                    e.full, e.indirect, e.ambientFull, ms);
        return e;
    }
};

} // namespace

// Measured on lavapipe (Mesa 22.3.6), 32^3 grid, 6 cones of 30 degrees, 2 bounces, 64^2 pixels
// (relMSE with epsilon 0.01; the reference has 3 reflections, as VCT: direct, voxel, bounce):
//   cornell           full 0.209  indirect 0.423   best constant ambient 0.256
//   cornell_point     full 0.617  indirect 4.10    best constant ambient 0.267
//   cornell_emissive  full 2.09   indirect 3.40    best constant ambient 0.494
// Both renderers are deterministic, so the bounds only allow for driver/compiler changes: 20%
// above the measurement. Only the spot-lit box beats the ambient baseline; near a point light
// under the ceiling and with the small emitter sharing voxels with the ceiling (its emission is
// averaged with the ceiling's zero), VCT at 32^3 is worse than a constant (docs/vct.md).
TEST_F(VctReference, CornellBoxes) {
    VctSettings s;
    s.gridResolution = 32;
    Errors spot = measure("cornell", s);
    EXPECT_LT(spot.full, 0.25);
    EXPECT_LT(spot.indirect, 0.51);
    EXPECT_LT(spot.full, spot.ambientFull);
    Errors point = measure("cornell_point", s);
    EXPECT_LT(point.full, 0.74);
    EXPECT_LT(point.indirect, 4.9);
    Errors emissive = measure("cornell_emissive", s);
    EXPECT_LT(emissive.full, 2.5);
    EXPECT_LT(emissive.indirect, 4.1);
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
