// VCT's geometry-aware filter of the incoming diffuse light (VctSettings::filter, vct_filter.comp,
// docs/vct.md "Filter"): on synthetic G-buffers its closed forms (a constant field is kept, a
// field alternating between the tent's residue classes becomes its mean, a bright surface does
// not leak onto a perpendicular dark one), and on a smooth indirect field (a sphere and a torus
// in a closed room under a point light) the high-frequency energy against the path tracer.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/gtc/packing.hpp>

#include "mesh_builder.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/gpu_util.hpp"
#include "vct/vct_passes.hpp"
#include "vkgi/gi.hpp"
#include "vkgi/image_metrics.hpp"
#include "vkgi/pipeline.hpp"
#include "vkgi/reference.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kW = 32, kH = 32;
constexpr uint32_t kSeam = 16; // columns x < kSeam: floor; x >= kSeam: wall

// A synthetic G-buffer: a floor (y = 0, normal +Y) in the left half meeting a wall (x = 1.6,
// normal -X) in the right half at their common edge, 0.1 m per pixel, seen from a camera 2 m away.
struct SyntheticGBuffer {
    std::vector<glm::vec4> position, normal, albedo;
};

SyntheticGBuffer cornerGBuffer() {
    SyntheticGBuffer g;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const float v = 0.1f * float(y);
            if (x < kSeam) {
                g.position.emplace_back(0.1f * float(x), 0.0f, v, 1.0f);
                g.normal.emplace_back(0.0f, 1.0f, 0.0f, 1.0f);
            } else {
                g.position.emplace_back(1.6f, 0.1f * float(x - kSeam), v, 1.0f);
                g.normal.emplace_back(-1.0f, 0.0f, 0.0f, 1.0f);
            }
            g.albedo.emplace_back(1.0f, 1.0f, 1.0f, 0.0f); // white, not metallic: radiance = E
        }
    return g;
}

class VctFilterSynthetic : public test::GpuTest {
protected:
    Image upload(const std::vector<glm::vec4>& texels, VkFormat format, const char* name) {
        ImageDesc d;
        d.format = format;
        d.width = kW;
        d.height = kH;
        d.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        Image img = createImage(ctx(), d, name);
        if (format == VK_FORMAT_R16G16B16A16_SFLOAT) {
            std::vector<uint64_t> half;
            for (const glm::vec4& t : texels)
                half.push_back(glm::packHalf4x16(t));
            uploadImage(ctx(), img, half.data(), half.size() * sizeof(uint64_t), VK_IMAGE_LAYOUT_GENERAL);
        } else {
            uploadImage(ctx(), img, texels.data(), texels.size() * sizeof(glm::vec4), VK_IMAGE_LAYOUT_GENERAL);
        }
        m_images.push_back(img);
        return img;
    }
    void TearDown() override {
        if (m_ctx) {
            vkDeviceWaitIdle(ctx().device());
            for (Image& i : m_images)
                destroyImage(ctx(), i);
            destroyPipeline(ctx(), m_pipeline);
        }
        GpuTest::TearDown();
    }
    // The filter of side `side` at f = 1 over the incoming light `light` (a = AO) of the corner
    // G-buffer: the indirect radiance, which with white albedo is the filtered light.
    std::vector<glm::vec4> filter(const std::vector<glm::vec4>& light, uint32_t side) {
        if (!m_ctx) {
            m_ctx = &ctx();
            auto p = createComputePipeline(ctx(), {"gi/vct/vct_filter.comp", {}});
            EXPECT_TRUE(p) << p.error().message;
            if (!p)
                return {};
            m_pipeline = std::move(*p);
        }
        SyntheticGBuffer gb = cornerGBuffer();
        Image pos = upload(gb.position, VK_FORMAT_R32G32B32A32_SFLOAT, "g.position");
        Image nrm = upload(gb.normal, VK_FORMAT_R16G16B16A16_SFLOAT, "g.normal");
        Image alb = upload(gb.albedo, VK_FORMAT_R16G16B16A16_SFLOAT, "g.albedo");
        Image in = upload(light, VK_FORMAT_R32G32B32A32_SFLOAT, "light");
        Image glossy =
            upload(std::vector<glm::vec4>(kW * kH, glm::vec4(0.0f)), VK_FORMAT_R32G32B32A32_SFLOAT, "glossy");
        rg::RenderGraph graph;
        const rg::Access read = rg::Access::ComputeStorageRead;
        VctGBufferHandles g;
        g.position = graph.importImage("g.position", pos, read);
        g.normal = graph.importImage("g.normal", nrm, read);
        g.albedo = graph.importImage("g.albedo", alb, read);
        g.width = kW;
        g.height = kH;
        g.eye = glm::vec3(0.4f, 1.2f, 1.6f) + 2.0f * glm::normalize(glm::vec3(-1.0f, 1.0f, 0.0f));
        rg::ImageHandle out = addVctFilterPasses(graph, m_pipeline, g, graph.importImage("light", in, read),
                                                 graph.importImage("glossy", glossy, read), 1u, side);
        return test::asArray<glm::vec4>(
            test::runAndReadImage(ctx(), graph, out, VkDeviceSize(kW) * kH * sizeof(glm::vec4)));
    }

private:
    Context* m_ctx = nullptr;
    Pipeline m_pipeline;
    std::vector<Image> m_images;
};

// A constant field is kept: every residue class's weights sum to 1 (gi/surface_filter.h), so
// the filter returns the constant, up to the rounding of the weighted sum, at every window size
// the seams and the image border leave (AO in alpha too).
TEST_F(VctFilterSynthetic, ConstantFieldIsKept) {
    const glm::vec4 c(3.7f, 0.42f, 1234.5f, 0.8f);
    for (uint32_t side = 2; side <= kVctMaxFilter; ++side) {
        std::vector<glm::vec4> out = filter(std::vector<glm::vec4>(kW * kH, c), side);
        ASSERT_EQ(out.size(), size_t(kW) * kH);
        for (size_t i = 0; i < out.size(); ++i)
            for (int k = 0; k < 4; ++k)
                ASSERT_NEAR(out[i][k], c[k], 1e-6f * c[k]) << "side " << side << ", pixel " << i << ", channel " << k;
    }
}

// Every estimate of a tent's residue classes weighs the same: a field alternating with period
// `side` along x and y (an interleaved pattern of side x side estimates) becomes its mean exactly
// where the window is whole, and stays within its range everywhere.
TEST_F(VctFilterSynthetic, InterleavedPatternBecomesItsMean) {
    for (uint32_t side : {2u, 4u}) {
        std::vector<glm::vec4> light;
        double mean = 0.0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                const float v = 1.0f + float((x % side) + side * (y % side)); // the class index + 1
                light.emplace_back(v, v, v, 1.0f);
            }
        for (uint32_t s = 0; s < side * side; ++s)
            mean += (1.0 + s) / double(side * side);
        std::vector<glm::vec4> out = filter(light, side);
        ASSERT_EQ(out.size(), size_t(kW) * kH);
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                const float v = out[y * kW + x].g;
                const bool whole =
                    y >= side - 1 && y + side - 1 < kH &&
                    ((x >= side - 1 && x + side - 1 < kSeam) || (x >= kSeam + side - 1 && x + side - 1 < kW));
                if (whole) {
                    EXPECT_NEAR(v, mean, 1e-5 * mean) << "side " << side << " at " << x << ", " << y;
                }
                EXPECT_GE(v, 1.0f - 1e-5f);
                EXPECT_LE(v, float(side * side) + 1e-4f);
            }
    }
}

// A floor receiving 100x the wall's light meets the wall at a right angle: filtered at the
// largest side, no wall pixel takes any of the floor's light and no floor pixel the wall's.
// Each keeps its own value within 1e-6, where a floor pixel inside a wall pixel's window would
// add at least 100 / 64^2 (the smallest row weight times the smallest column weight at n = 8).
TEST_F(VctFilterSynthetic, LightDoesNotBleedAcrossSurfaces) {
    const float floorLight = 100.0f, wallLight = 1.0f;
    std::vector<glm::vec4> light;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const float v = x < kSeam ? floorLight : wallLight;
            light.emplace_back(v, v, v, 1.0f);
        }
    std::vector<glm::vec4> out = filter(light, kVctMaxFilter);
    ASSERT_EQ(out.size(), size_t(kW) * kH);
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            const float expected = x < kSeam ? floorLight : wallLight;
            EXPECT_NEAR(out[y * kW + x].r, expected, 1e-6f * expected) << x << ", " << y;
        }
}

// ---- a smooth indirect field against the path tracer --------------------------------------

constexpr uint32_t kSize = 64;

// A closed 4 x 3 x 4 m grey room under a 100 cd point light, with a sphere and a torus (smooth
// normals) on the floor: the indirect light on the curved objects varies slowly, so what the
// coarse voxels' cones add in high frequencies shows against the path tracer's.
Scene smoothFieldScene() {
    Scene s;
    s.name = "vct_filter_smooth";
    const uint32_t grey = addMaterial(s, "room", {0.6f, 0.6f, 0.6f});
    const uint32_t objects = addMaterial(s, "objects", {0.7f, 0.7f, 0.7f});
    MeshBuilder room;
    room.addBox({-2.0f, 0.0f, -2.0f}, {2.0f, 3.0f, 2.0f}, Facing::Inward, 4);
    addMeshInstance(s, room, "room", grey);
    MeshBuilder sphere;
    sphere.addIcosphere({-0.8f, 0.5f, -0.2f}, 3, [](const glm::vec3&) { return 0.5f; });
    addMeshInstance(s, sphere, "sphere", objects);
    std::vector<glm::vec2> ring;
    for (int i = 0; i <= 24; ++i) {
        const float a = 2.0f * 3.14159265f * float(i) / 24.0f;
        ring.emplace_back(0.45f + 0.22f * std::cos(a), 0.22f + 0.22f * std::sin(a));
    }
    MeshBuilder torus;
    torus.addLathe({0.8f, 0.0f, -0.4f}, ring, 32);
    addMeshInstance(s, torus, "torus", objects);
    Light l;
    l.name = "lamp";
    l.type = LightType::Point;
    l.position = glm::vec3(0.0f, 2.6f, 0.3f);
    l.intensity = 100.0f;
    s.lights.push_back(l);
    Camera c;
    c.position = glm::vec3(0.0f, 1.5f, 1.9f);
    c.forward = glm::normalize(glm::vec3(0.0f, 0.35f, -0.4f) - c.position);
    c.yfov = 1.0f;
    c.znear = 0.05f;
    c.zfar = 20.0f;
    s.camera = c;
    return s;
}

struct SmoothFieldErrors {
    double hfRatio = 0.0, relMse = 0.0, relMseDark = 0.0;
};

class VctFilterReference : public test::GpuTest {
protected:
    SmoothFieldErrors measure(const Scene& scene, const ReferenceImages& ref, uint32_t filterSide,
                              uint32_t lowResFactor = 2) { // 64^2 test images: f = 4 traces 16^2 (docs/vct.md)
        GiSettings settings;
        settings.technique = Technique::Vct;
        settings.vct.lowResFactor = lowResFactor;
        settings.vct.filter = filterSide;
        FrameRequest request;
        request.direct = true;
        auto frame = test::renderOnce(ctx(), settings, scene, *scene.camera, kSize, kSize, request);
        EXPECT_TRUE(frame.ok()) << frame.error().message;
        if (!frame.ok())
            return {};
        auto indirect = subtract(frame->composite, frame->direct);
        const std::vector<bool> surface = surfacePixels(frame->composite, ref.full);
        SmoothFieldErrors e;
        e.hfRatio = laplacianEnergy(*indirect, surface) / laplacianEnergy(ref.indirect, surface);
        e.relMse = compareImages(*indirect, ref.indirect)->relMse;
        e.relMseDark = compareImages(*indirect, ref.indirect, 0.001f)->relMse;
        std::printf("f %u, filter %u: HF ratio %.3f, indirect relMSE %.4f (eps 1e-3: %.4f)\n", lowResFactor,
                    filterSide, e.hfRatio, e.relMse, e.relMseDark);
        return e;
    }
};

// With the default filter the VCT indirect image's HF energy relative to the path tracer's falls
// to at most 0.6x the unfiltered one's, and its error against the path tracer's indirect (both
// epsilons) does not rise (the measured values: the commits that added the test and the rotated
// cone sets). The filter averages the rotated cone sets (docs/vct.md "Rotated cone sets"): at the
// default settings (f = 4) the HF ratio is within issue #15's 1.5x. At f = 2, the resolution the
// other tests use at 64^2, it stays above 1.5 (1.61 measured, bound 1.65): what remains lies
// along the silhouettes and contact edges, where VCT's indirect light steps from one surface to
// the next by more than the path tracer's (an error of the light's level on either side), and
// the filter never crosses an edge (docs/vct.md "Filter", "Known limits").
TEST_F(VctFilterReference, SmoothFieldHfEnergyFallsAndErrorDoesNot) {
    const Scene scene = smoothFieldScene();
    ASSERT_TRUE(validateScene(scene).ok());
    ReferenceSettings rs;
    rs.spp = 4096; // the reference's own noise adds to its HF energy: keep it far below the field's
    rs.maxBounces = 3;
    rs.progress = false;
    auto ref = renderReferenceCached(scene, *scene.camera, kSize, kSize, rs);
    ASSERT_TRUE(ref.ok()) << ref.error().message;
    const SmoothFieldErrors off = measure(scene, *ref, 1);
    const SmoothFieldErrors on = measure(scene, *ref, VctSettings{}.filter);
    EXPECT_GT(VctSettings{}.filter, 1u);
    EXPECT_LE(on.hfRatio, 0.6 * off.hfRatio);
    EXPECT_LE(on.hfRatio, 1.65);
    EXPECT_LE(on.relMse, off.relMse);
    EXPECT_LE(on.relMseDark, off.relMseDark);
    const SmoothFieldErrors defaults = measure(scene, *ref, VctSettings{}.filter, VctSettings{}.lowResFactor);
    EXPECT_LE(defaults.hfRatio, 1.5); // issue #15
    EXPECT_LE(defaults.relMse, off.relMse);
}

} // namespace
