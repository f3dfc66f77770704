// VCT's separate outputs through GiSystem (FrameRequest::glossy / ao): produced only when asked
// for and only by VCT, the AO a visibility in [0, 1], the glossy cone traced on request even
// without metallic materials, and asking for them changes no other image.
#include <algorithm>
#include <cmath>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/gi.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kSize = 48;

class VctOutputs : public test::GpuTest {
protected:
    FrameResult render(Technique technique, const FrameRequest& request, bool ambientOcclusion = true) {
        GiSettings settings;
        settings.technique = technique;
        settings.vct.gridResolution = 16;
        settings.vct.lowResFactor = 2;
        settings.vct.ambientOcclusion = ambientOcclusion;
        settings.lpv.gridSize = 8;
        Scene scene = test::builtinScene("cornell");
        auto frame = test::renderOnce(ctx(), settings, scene, scene.cameraOrDefault(), kSize, kSize, request);
        EXPECT_TRUE(frame.ok()) << frame.error().message;
        return frame.ok() ? std::move(*frame) : FrameResult{};
    }
};

} // namespace

TEST_F(VctOutputs, GlossyAndAmbientOcclusionOnRequest) {
    FrameRequest plain;
    plain.indirect = true;
    FrameRequest all = plain;
    all.glossy = true;
    all.ao = true;
    FrameResult a = render(Technique::Vct, plain);
    FrameResult b = render(Technique::Vct, all);
    EXPECT_TRUE(a.glossy.pixels.empty());
    EXPECT_TRUE(a.ao.pixels.empty());
    ASSERT_EQ(b.glossy.pixels.size(), size_t(kSize) * kSize);
    ASSERT_EQ(b.ao.pixels.size(), size_t(kSize) * kSize);
    ASSERT_EQ(a.indirect.pixels.size(), b.indirect.pixels.size());

    // The box has no metallic material: the glossy cone's weight is 0, so tracing it for the
    // glossy image changes neither the indirect nor the composite image (bit for bit).
    EXPECT_TRUE(a.indirect.pixels == b.indirect.pixels);
    EXPECT_TRUE(a.composite.pixels == b.composite.pixels);

    // AO: visibility in [0, 1], grey; the box's corners and the blocks' contact with the floor
    // are occluded, the open middle of the room is not.
    float minAo = 1.0f, maxAo = 0.0f;
    for (const glm::vec3& p : b.ao.pixels) {
        ASSERT_TRUE(std::isfinite(p.x)) << "AO";
        EXPECT_EQ(p.x, p.y);
        EXPECT_EQ(p.x, p.z);
        minAo = std::min(minAo, p.x);
        maxAo = std::max(maxAo, p.x);
    }
    EXPECT_GE(minAo, 0.0f);
    EXPECT_LE(maxAo, 1.0f);
    EXPECT_LT(minAo, 0.95f);
    EXPECT_GT(maxAo, 0.99f);

    // Glossy: finite, non-negative radiance, and light arrives along the mirror directions
    // inside the lit box.
    double glossySum = 0.0;
    for (const glm::vec3& p : b.glossy.pixels) {
        ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) << "glossy";
        EXPECT_GE(std::min({p.x, p.y, p.z}), 0.0f);
        glossySum += double(p.x + p.y + p.z);
    }
    EXPECT_GT(glossySum, 0.0);

    // Only the AO asked for (no composite, no indirect): the technique still runs, and the AO
    // is the same as when everything was asked for.
    FrameRequest aoOnly;
    aoOnly.composite = false;
    aoOnly.ao = true;
    FrameResult c = render(Technique::Vct, aoOnly);
    EXPECT_TRUE(c.composite.pixels.empty());
    EXPECT_TRUE(c.ao.pixels == b.ao.pixels);
}

TEST_F(VctOutputs, OtherTechniquesAndAoOffProduceNone) {
    FrameRequest all;
    all.indirect = true;
    all.glossy = true;
    all.ao = true;
    FrameResult lpv = render(Technique::Lpv, all);
    EXPECT_FALSE(lpv.indirect.pixels.empty());
    EXPECT_TRUE(lpv.glossy.pixels.empty());
    EXPECT_TRUE(lpv.ao.pixels.empty());
    FrameResult aoOff = render(Technique::Vct, all, false);
    EXPECT_FALSE(aoOff.glossy.pixels.empty());
    EXPECT_TRUE(aoOff.ao.pixels.empty());
    FrameResult none = render(Technique::None, all);
    EXPECT_FALSE(none.composite.pixels.empty());
    EXPECT_TRUE(none.glossy.pixels.empty());
    EXPECT_TRUE(none.ao.pixels.empty());
}
