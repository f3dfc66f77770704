// LPV injection from a synthetic RSM and the per-pixel lookup, through the render graph:
// cell choice with the half-cell normal offset, run merging across invocations, bad texels
// ignored, the normalisation by the largest texel flux M (scale invariance from 1e-6 to 1e9),
// and the lookup's irradiance and damping against closed forms.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include <glm/gtc/packing.hpp>

#include "vkgi/rg/transient_pool.hpp"
#include "gi/direct_types.h"
#include "gi/lpv_passes.h"
#include "lpv/lpv_cpu.hpp"
#include "lpv/lpv_inject.hpp"
#include "support/gpu_fixture.hpp"
#include "support/gpu_util.hpp"

using namespace vkgi;
using namespace vkgi::gi::lpv;
using gpu::vec3;
using gpu::vec4;

namespace {

constexpr float kPi = 3.14159265f;
constexpr int kRsm = 16;
constexpr int kGrid = 8;

struct Surfel {
    glm::ivec2 texel;
    glm::vec4 position; // w = valid
    glm::vec3 normal;
    glm::vec3 flux;
};

std::vector<uint8_t> bytesOf(const std::vector<glm::vec4>& texels, VkFormat format) {
    std::vector<uint8_t> out;
    if (format == VK_FORMAT_R32G32B32A32_SFLOAT) {
        out.resize(texels.size() * 16);
        std::memcpy(out.data(), texels.data(), out.size());
    } else {
        out.resize(texels.size() * 8);
        for (size_t i = 0; i < texels.size(); ++i) {
            glm::uint64 h = glm::packHalf4x16(texels[i]);
            std::memcpy(out.data() + 8 * i, &h, 8);
        }
    }
    return out;
}

std::vector<glm::vec4> texelsOf(const std::vector<uint8_t>& bytes, VkFormat format) {
    bool full = format == VK_FORMAT_R32G32B32A32_SFLOAT;
    std::vector<glm::vec4> out(bytes.size() / (full ? 16 : 8));
    for (size_t i = 0; i < out.size(); ++i) {
        if (full) {
            std::memcpy(&out[i], bytes.data() + 16 * i, 16);
        } else {
            glm::uint64 h;
            std::memcpy(&h, bytes.data() + 8 * i, 8);
            out[i] = glm::unpackHalf4x16(h);
        }
    }
    return out;
}

class LpvInject : public test::GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        if (IsSkipped())
            return;
        auto inj = Injector::create(ctx());
        ASSERT_TRUE(inj) << inj.error().message;
        m_injector = *inj;
        m_pool = std::make_unique<rg::TransientPool>(ctx());
        m_ready = true;
    }
    void TearDown() override {
        for (Image* img : m_images)
            destroyImage(ctx(), *img);
        for (auto& v : m_volumes)
            for (rg::PersistentImage& c : v)
                if (c.image)
                    destroyImage(ctx(), c.image);
        if (m_buffer.buffer)
            destroyBuffer(ctx(), m_buffer.buffer);
        if (m_views.buffer)
            destroyBuffer(ctx(), m_views);
        if (m_output.image)
            destroyImage(ctx(), m_output.image);
        if (m_ready) {
            m_pool.reset();
            m_injector.destroy(ctx());
        }
        GpuTest::TearDown();
    }

    // A 2D (array) image filled with `texels`, left in TRANSFER_DST for import as TransferWrite.
    Image* uploaded(const std::vector<glm::vec4>& texels, VkFormat format, uint32_t w, uint32_t h, bool array) {
        ImageDesc desc;
        desc.format = format;
        desc.width = w;
        desc.height = h;
        desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT; // as the shared RSM and G-buffer
        auto* img = new Image(createImage(ctx(), desc, array ? "lpv.test.rsm" : "lpv.test.gbuffer"));
        if (array) { // a 1-layer array view is what sampler2DArray needs
            vkDestroyImageView(ctx().device(), img->view, nullptr);
            VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
            info.image = img->image;
            info.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
            info.format = format;
            info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            vkCreateImageView(ctx().device(), &info, nullptr, &img->view);
        }
        auto bytes = bytesOf(texels, format);
        uploadImage(ctx(), *img, bytes.data(), bytes.size(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        m_images.push_back(img);
        m_owned.emplace_back(img);
        return img;
    }

    // Runs clear/range/inject/resolve (and the lookup when `gbuffer` is given) in one graph.
    void run(const std::vector<Surfel>& surfels, VkFormat format, float fluxScale, const Image* gbuffer = nullptr,
             uint32_t gbufferWidth = 0, float damping = 0.0f, uint32_t reduce = 1) {
        std::vector<glm::vec4> pos(kRsm * kRsm, glm::vec4(0.0f)), nrm(kRsm * kRsm, glm::vec4(0.0f)),
            flux(kRsm * kRsm, glm::vec4(0.0f));
        for (const Surfel& s : surfels) {
            size_t i = size_t(s.texel.y * kRsm + s.texel.x);
            pos[i] = s.position;
            nrm[i] = glm::vec4(s.normal, 0.0f);
            flux[i] = glm::vec4(s.flux * fluxScale, 0.0f);
        }
        Image* rsmPos = uploaded(pos, VK_FORMAT_R32G32B32A32_SFLOAT, kRsm, kRsm, true);
        Image* rsmNrm = uploaded(nrm, VK_FORMAT_R16G16B16A16_SFLOAT, kRsm, kRsm, true);
        Image* rsmFlux = uploaded(flux, VK_FORMAT_R32G32B32A32_SFLOAT, kRsm, kRsm, true);
        m_format = format;
        for (auto& v : m_volumes)
            for (rg::PersistentImage& c : v) {
                if (c.image)
                    destroyImage(ctx(), c.image);
                c.image = createImage(ctx(), shImageDesc(glm::ivec3(kGrid), format), "lpv.test.volume");
                c.state.clear();
            }
        if (!m_buffer.buffer.buffer)
            m_buffer.buffer = createBuffer(ctx(),
                                           {injectionBufferBytes(glm::ivec3(kGrid)),
                                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::GpuToCpu},
                                           "lpv.test.injection");
        rg::RenderGraph g;
        RsmInput rsm{g.importImage("rsm.position", *rsmPos, rg::Access::TransferWrite),
                     g.importImage("rsm.normal", *rsmNrm, rg::Access::TransferWrite),
                     g.importImage("rsm.flux", *rsmFlux, rg::Access::TransferWrite), kRsm, 1};
        // The RSM's one layer: its view's eye is m_lightEye (w = 0: a directional layer).
        if (!m_views.buffer)
            m_views = createBuffer(ctx(), {sizeof(gpu::GpuShadowView), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                           MemoryUsage::CpuToGpu}, "lpv.test.views");
        gpu::GpuShadowView view{};
        view.eye = m_lightEye;
        std::memcpy(m_views.mapped(), &view, sizeof(view));
        rsm.views = g.importBuffer("views", m_views, rg::Access::None);
        rsm.nearLightRadius = grid().origin.w; // one cell, as the technique's single grid
        if (reduce > 1)
            rsm = addRsmReducePass(g, m_injector, rsm, reduce, m_mergeRadius);
        ShHandles wave, acc;
        for (int c = 0; c < 3; ++c) {
            wave.channel[c] = g.importImage("wave", m_volumes[0][c]);
            acc.channel[c] = g.importImage("acc", m_volumes[1][c]);
        }
        InjectionResult r = addInjectionPasses(g, m_injector, grid(), format, {rsm}, wave, acc,
                                               g.importBuffer("injection", m_buffer));
        g.exportBuffer(r.buffer, rg::Access::HostRead);
        for (int c = 0; c < 3; ++c)
            g.markOutput(r.accumulation.channel[c]);
        if (gbuffer) {
            if (!m_output.image) {
                ImageDesc desc;
                desc.format = VK_FORMAT_R32G32B32A32_SFLOAT;
                desc.width = gbufferWidth;
                desc.usage = VK_IMAGE_USAGE_STORAGE_BIT;
                m_output.image = createImage(ctx(), desc, "lpv.test.indirect");
            }
            GBufferInput gb{g.importImage("g.position", gbuffer[0], rg::Access::TransferWrite),
                            g.importImage("g.normal", gbuffer[1], rg::Access::TransferWrite),
                            g.importImage("g.albedo", gbuffer[2], rg::Access::TransferWrite), gbufferWidth, 1};
            rg::ImageHandle out = addLookupPass(g, m_injector, grid(), r.accumulation, r.buffer, gb, damping,
                                                g.importImage("indirect", m_output));
            g.markOutput(out);
        }
        auto compiled = g.compile();
        ASSERT_TRUE(compiled) << compiled.error().message;
        ctx().submitAndWait([&](VkCommandBuffer cmd) { g.execute(cmd, ctx(), *m_pool); });
    }

    static gpu::LpvGrid grid() {
        gpu::LpvGrid g{};
        g.origin = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
        g.size = glm::ivec4(kGrid, kGrid, kGrid, 0);
        return g;
    }

    float maxTexelFlux() const {
        uint32_t bits;
        std::memcpy(&bits, m_buffer.buffer.mapped(), 4);
        float m;
        std::memcpy(&m, &bits, 4);
        return m;
    }

    // Accumulated (normalised) SH of channel c, per cell.
    std::vector<glm::vec4> accumulated(int c) {
        rg::PersistentImage& img = m_volumes[1][c];
        return texelsOf(readbackImage(ctx(), img.image, img.state.at(0).layout), m_format);
    }

    std::vector<glm::vec4> indirect() {
        return texelsOf(readbackImage(ctx(), m_output.image, m_output.state.at(0).layout),
                        VK_FORMAT_R32G32B32A32_SFLOAT);
    }

    // The geometry volume's (kGrid + 1)^3 corner texels (RGBA16F blocking SH) built from a
    // camera G-buffer of camW x camH and, when rsmPos is given, a rsmSize^2 single-layer RSM.
    std::vector<glm::vec4> geometryVolume(Image* rsmPos, Image* rsmNrm, uint32_t rsmSize, Image* camPos,
                                          Image* camNrm, uint32_t camW, uint32_t camH) {
        const int corners = kGrid + 1;
        rg::RenderGraph g;
        RsmInput rsm{};
        if (rsmPos)
            rsm = RsmInput{g.importImage("rsm.position", *rsmPos, rg::Access::TransferWrite),
                           g.importImage("rsm.normal", *rsmNrm, rg::Access::TransferWrite), {}, rsmSize, 1};
        GBufferInput cam{g.importImage("cam.position", *camPos, rg::Access::TransferWrite),
                         g.importImage("cam.normal", *camNrm, rg::Access::TransferWrite), {}, camW, camH};
        rg::ImageHandle gv = addGeometryVolumePasses(g, m_injector, grid(), rsm, cam);
        std::vector<uint8_t> bytes =
            test::runAndReadImage(ctx(), g, gv, VkDeviceSize(corners * corners * corners * 8), m_pool.get());
        return texelsOf(bytes, VK_FORMAT_R16G16B16A16_SFLOAT);
    }

    Injector m_injector;
    float m_mergeRadius = 0.5f; // half of grid()'s cell
    std::unique_ptr<rg::TransientPool> m_pool;
    bool m_ready = false;
    VkFormat m_format = VK_FORMAT_R32G32B32A32_SFLOAT;
    rg::PersistentImage m_volumes[2][3]; // wavefront, accumulation
    rg::PersistentBuffer m_buffer;
    rg::PersistentImage m_output;
    Buffer m_views;                    // the RSM layer's GpuShadowView
    glm::vec4 m_lightEye{0.0f};        // its eye: light position, w > 0 for a point or spot light
    std::vector<Image*> m_images;
    std::vector<std::unique_ptr<Image>> m_owned;
};

size_t cellIndex(int x, int y, int z) { return size_t(x + kGrid * (y + kGrid * z)); }

const float kNan = std::numeric_limits<float>::quiet_NaN();

// Surfels exercising every rule; M = 4 (the NaN and w = 0 texels must not count).
std::vector<Surfel> testSurfels() {
    return {
        {{0, 0}, {2.9f, 3.2f, 3.5f, 1.0f}, {1, 0, 0}, {1, 2, 3}},    // +x: 3.4 -> cell (3, 3, 3)
        {{1, 0}, {2.9f, 3.2f, 3.5f, 1.0f}, {-1, 0, 0}, {0.5f, 0.5f, 0.5f}}, // -x: 2.4 -> cell (2, 3, 3)
        {{2, 0}, {5.5f, 5.5f, 5.5f, 1.0f}, {0, 1, 0}, {4, 0, 0}},    // +y: 6.0 -> cell (5, 6, 5)
        {{3, 0}, {5.5f, 5.5f, 5.5f, 1.0f}, {0, 1, 0}, {0, 4, 0}},    // same cell, same run
        {{4, 0}, {-3.0f, 1.0f, 1.0f, 1.0f}, {0, 1, 0}, {1, 1, 1}},   // outside the grid
        {{5, 0}, {1.0f, 1.0f, 1.0f, 0.0f}, {0, 1, 0}, {1e30f, 1e30f, 1e30f}}, // no geometry (w = 0)
        {{6, 0}, {1.0f, 1.0f, 1.0f, 1.0f}, {0, 1, 0}, {kNan, 1, 1}}, // NaN flux
        {{7, 0}, {1.0f, 1.0f, 1.0f, 1.0f}, {0, 0, 0}, {1, 1, 1}},    // zero normal
        {{8, 0}, {5.5f, 5.5f, 5.5f, 1.0f}, {0, 1, 0}, {0, 0, 4}},    // same cell, next run (invocation)
    };
}

} // namespace

TEST_F(LpvInject, SurfelsLandInTheCellInFrontOfThem) {
    run(testSurfels(), VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f);
    EXPECT_EQ(maxTexelFlux(), 4.0f);
    // Expected normalised SH: sum of (flux / M / pi) * cosineLobe(n). Fixed-point rounding is
    // 0.5 / scale = 2e-8 per run (scale = lpvFixedPointScale(256) = 2.4e7): tolerance 1e-6.
    const float m = 4.0f;
    std::vector<glm::vec4> expected[3];
    for (auto& e : expected)
        e.assign(kGrid * kGrid * kGrid, glm::vec4(0.0f));
    auto add = [&](size_t cell, vec3 n, glm::vec3 flux) {
        for (int c = 0; c < 3; ++c)
            expected[c][cell] += (flux[c] / m / kPi) * gpu::shCosineLobe(n);
    };
    add(cellIndex(3, 3, 3), {1, 0, 0}, {1, 2, 3});
    add(cellIndex(2, 3, 3), {-1, 0, 0}, {0.5f, 0.5f, 0.5f});
    add(cellIndex(5, 6, 5), {0, 1, 0}, {4, 4, 4});
    float worst = 0.0f;
    for (int c = 0; c < 3; ++c) {
        std::vector<glm::vec4> got = accumulated(c);
        ASSERT_EQ(got.size(), expected[c].size());
        for (size_t i = 0; i < got.size(); ++i)
            worst = std::max(worst, glm::length(got[i] - expected[c][i]));
    }
    EXPECT_LE(worst, 1e-6f);
    EXPECT_EQ(validation().count(), 0u);
}

// Surfels closer than one cell to a point or spot light are not injected (lpvInjectsNearLight,
// docs/lpv.md "Surfels next to a light"): a light 0.99 cells from the two surfels at
// (2.9, 3.2, 3.5) leaves out exactly those two, one 1.01 cells away none, and an eye on them
// that is a directional layer's (w = 0) none.
TEST_F(LpvInject, SurfelsWithinACellOfAPointLightAreLeftOut) {
    const float m = 4.0f;
    auto expectedWithout = [&](bool nearOnes) {
        std::vector<glm::vec4> e[3];
        for (auto& v : e)
            v.assign(kGrid * kGrid * kGrid, glm::vec4(0.0f));
        auto add = [&](size_t cell, vec3 n, glm::vec3 flux) {
            for (int c = 0; c < 3; ++c)
                e[c][cell] += (flux[c] / m / kPi) * gpu::shCosineLobe(n);
        };
        if (!nearOnes) {
            add(cellIndex(3, 3, 3), {1, 0, 0}, {1, 2, 3});
            add(cellIndex(2, 3, 3), {-1, 0, 0}, {0.5f, 0.5f, 0.5f});
        }
        add(cellIndex(5, 6, 5), {0, 1, 0}, {4, 4, 4});
        return std::array<std::vector<glm::vec4>, 3>{e[0], e[1], e[2]};
    };
    auto worstAgainst = [&](const std::array<std::vector<glm::vec4>, 3>& expected) {
        float worst = 0.0f;
        for (int c = 0; c < 3; ++c) {
            std::vector<glm::vec4> got = accumulated(c);
            for (size_t i = 0; i < got.size(); ++i)
                worst = std::max(worst, glm::length(got[i] - expected[c][i]));
        }
        return worst;
    };
    // 0.99 cells from the surfels at (2.9, 3.2, 3.5), 2.9 cells from those at (5.5, 5.5, 5.5).
    const glm::vec3 nearLight(2.9f, 3.2f, 3.5f - 0.99f);
    m_lightEye = glm::vec4(nearLight, 10.0f);
    run(testSurfels(), VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f);
    EXPECT_EQ(maxTexelFlux(), m); // M is still the largest texel flux (a scale; the range pass sees all)
    EXPECT_LE(worstAgainst(expectedWithout(true)), 1e-6f);
    // 1.01 cells away: all injected, as on a directional layer with the eye on the surfels.
    m_lightEye = glm::vec4(2.9f, 3.2f, 3.5f - 1.01f, 10.0f);
    run(testSurfels(), VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f);
    EXPECT_LE(worstAgainst(expectedWithout(false)), 1e-6f);
    m_lightEye = glm::vec4(2.9f, 3.2f, 3.5f, 0.0f);
    run(testSurfels(), VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f);
    EXPECT_LE(worstAgainst(expectedWithout(false)), 1e-6f);
    EXPECT_EQ(validation().count(), 0u);
}

TEST_F(LpvInject, ReducedRsmInjectsTheSameLight) {
    // Two 2x2 blocks whose texels all land in one cell each. Block (0, 0): grey surfels of flux 1,
    // 2, 3 on a corner (normals +y, +y, +x) and a NaN-flux texel; block (1, 0): four surfels
    // facing +y with the same coloured flux. Reduced by 2, each block is one surfel (flux summed,
    // flux-weighted mean position and unnormalised mean normal); since cosineLobe is linear in n,
    // the injected SH (times M) must equal the full-resolution injection's. Block (0, 0)'s mean
    // normal (0.5, 0.5, 0) puts it at (2.17, 3.1, 2.3) + 0.35 (1, 1, 0): cell (2, 3, 2), where
    // the texels land too.
    const std::vector<Surfel> surfels = {
        {{0, 0}, {2.2f, 3.0f, 2.2f, 1.0f}, {0, 1, 0}, {1, 1, 1}},
        {{1, 0}, {2.4f, 3.0f, 2.2f, 1.0f}, {0, 1, 0}, {2, 2, 2}},
        {{0, 1}, {2.0f, 3.2f, 2.4f, 1.0f}, {1, 0, 0}, {3, 3, 3}},
        {{1, 1}, {2.0f, 3.2f, 2.4f, 1.0f}, {1, 0, 0}, {kNan, 1, 1}},
        {{2, 0}, {5.2f, 5.6f, 5.2f, 1.0f}, {0, 1, 0}, {1, 0.5f, 0.25f}},
        {{3, 0}, {5.4f, 5.6f, 5.2f, 1.0f}, {0, 1, 0}, {1, 0.5f, 0.25f}},
        {{2, 1}, {5.2f, 5.6f, 5.4f, 1.0f}, {0, 1, 0}, {1, 0.5f, 0.25f}},
        {{3, 1}, {5.4f, 5.6f, 5.4f, 1.0f}, {0, 1, 0}, {1, 0.5f, 0.25f}},
    };
    std::vector<glm::vec4> full[3], reduced[3];
    run(surfels, VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f);
    EXPECT_EQ(maxTexelFlux(), 3.0f);
    for (int c = 0; c < 3; ++c) {
        full[c] = accumulated(c);
        for (glm::vec4& v : full[c])
            v *= 3.0f;
    }
    run(surfels, VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f, nullptr, 0, 0.0f, 2);
    EXPECT_EQ(maxTexelFlux(), 6.0f); // block sums: (6, 6, 6) and (4, 2, 1)
    for (int c = 0; c < 3; ++c) {
        reduced[c] = accumulated(c);
        for (glm::vec4& v : reduced[c])
            v *= 6.0f;
    }
    // Band 0 is the flux: exact up to the fixed point (~1e-7). Band 1 goes through the RGBA16F
    // mean normal (2^-11 relative).
    float worst0 = 0.0f, worst1 = 0.0f;
    for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < full[c].size(); ++i) {
            worst0 = std::max(worst0, std::abs(full[c][i].x - reduced[c][i].x));
            worst1 = std::max(worst1, glm::length(glm::vec3(full[c][i]) - glm::vec3(reduced[c][i])));
        }
    const float b0 = 6.0f / kPi * gpu::kShCosineBand0; // block (0, 0)'s band 0
    EXPECT_NEAR(full[0][cellIndex(2, 3, 2)].x, b0, 1e-5f * b0);
    EXPECT_LE(worst0, 1e-5f * b0);
    EXPECT_LE(worst1, 1e-3f * b0);
    EXPECT_EQ(validation().count(), 0u);
}

TEST_F(LpvInject, ReducedRsmSplitsBlocksOneSurfelCannotStandFor) {
    // Block (0, 0) of a 2x2 reduction sees a ground at y = 0.2 and a roof at y = 5.2 (a depth
    // discontinuity in one block); block (1, 0) a 150-degree fold at one spot (normals +y and
    // (sin 150, cos 150, 0)). Merged, the first would inject its light at y = 2.7 + 0.5 (cell y
    // 3), where none of its texels are, and the second with one offset for both faces. The first
    // lies 2.5 m off its mean plane (more than half a cell), the second folds too sharply (mean
    // normal 0.26 long), so both are injected texel by texel from the full RSM: the reduced
    // injection must equal
    // the full-resolution one. With an unbounded merge radius the first block is merged and its
    // light appears in cell y 3 (the control: the split is what keeps it out).
    const glm::vec3 fold(0.5f, -0.8660254f, 0.0f);
    const std::vector<Surfel> surfels = {
        {{0, 0}, {2.2f, 0.2f, 2.2f, 1.0f}, {0, 1, 0}, {1, 1, 1}},
        {{1, 0}, {2.4f, 0.2f, 2.2f, 1.0f}, {0, 1, 0}, {1, 1, 1}},
        {{0, 1}, {2.2f, 5.2f, 2.4f, 1.0f}, {0, 1, 0}, {1, 1, 1}},
        {{1, 1}, {2.4f, 5.2f, 2.4f, 1.0f}, {0, 1, 0}, {1, 1, 1}},
        {{2, 0}, {5.5f, 5.5f, 5.5f, 1.0f}, {0, 1, 0}, {2, 2, 2}},
        {{3, 0}, {5.5f, 5.5f, 5.5f, 1.0f}, fold, {2, 2, 2}},
    };
    std::vector<glm::vec4> full[3], split[3];
    run(surfels, VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f);
    const float fullM = maxTexelFlux();
    for (int c = 0; c < 3; ++c) {
        full[c] = accumulated(c);
        for (glm::vec4& v : full[c])
            v *= fullM;
    }
    run(surfels, VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f, nullptr, 0, 0.0f, 2);
    const float reducedM = maxTexelFlux();
    EXPECT_EQ(reducedM, 4.0f); // the blocks' sums, though neither is injected as one surfel
    for (int c = 0; c < 3; ++c) {
        split[c] = accumulated(c);
        for (glm::vec4& v : split[c])
            v *= reducedM;
    }
    const float b0 = 1.0f / kPi * gpu::kShCosineBand0; // one texel's band 0
    float worst = 0.0f;
    for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < full[c].size(); ++i)
            worst = std::max(worst, glm::length(full[c][i] - split[c][i]));
    EXPECT_NEAR(full[0][cellIndex(2, 0, 2)].x, 2.0f * b0, 1e-5f * b0); // the ground's two texels
    EXPECT_NEAR(full[0][cellIndex(2, 5, 2)].x, 2.0f * b0, 1e-5f * b0); // the roof's
    EXPECT_EQ(full[0][cellIndex(2, 3, 2)].x, 0.0f);
    EXPECT_LE(worst, 1e-5f * b0);

    // The control: merged regardless, the discontinuous block's light lands between its texels.
    m_mergeRadius = 1e9f;
    run(surfels, VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f, nullptr, 0, 0.0f, 2);
    EXPECT_NEAR(accumulated(0)[cellIndex(2, 3, 2)].x * maxTexelFlux(), 4.0f * b0, 1e-5f * b0);
    m_mergeRadius = 0.5f;
    EXPECT_EQ(validation().count(), 0u);
}

TEST_F(LpvInject, StoredValuesAreIndependentOfTheLightScale) {
    // The same RSM scaled by 1e-6 and by 1e9 stores the same normalised SH (float16, which would
    // overflow at 65504 without the normalisation), and M carries the scale.
    std::vector<glm::vec4> reference[3];
    run(testSurfels(), VK_FORMAT_R16G16B16A16_SFLOAT, 1.0f);
    for (int c = 0; c < 3; ++c)
        reference[c] = accumulated(c);
    for (float scale : {1e-6f, 1e9f}) {
        run(testSurfels(), VK_FORMAT_R16G16B16A16_SFLOAT, scale);
        EXPECT_NEAR(maxTexelFlux(), 4.0f * scale, 1e-6f * 4.0f * scale);
        float worst = 0.0f;
        for (int c = 0; c < 3; ++c) {
            std::vector<glm::vec4> got = accumulated(c);
            for (size_t i = 0; i < got.size(); ++i) {
                ASSERT_TRUE(std::isfinite(got[i].x) && std::isfinite(got[i].w));
                worst = std::max(worst, glm::length(got[i] - reference[c][i]));
            }
        }
        // flux * scale / (M * scale) differs from flux / M by float rounding only, far below
        // float16's 2^-11: identical halves expected, allow one half ulp at 0.33 (1.2e-4).
        EXPECT_LE(worst, 2.5e-4f) << "scale " << scale;
    }
}

TEST_F(LpvInject, LookupGivesTheClosedFormIrradianceAndDamping) {
    // The lookup samples half a cell in front of the surface (x = p + 0.5 n). Pixels, by their
    // sample point x: (0) the centre of cell (5, 6, 5), facing down into its upward light;
    // (1) same, facing up (the light travels away from it: zero); (2) background; (3) outside
    // the grid; (4) x at y = 6.2 facing down, where trilinear weights are 0.7 of cell (5, 6, 5)
    // at x, 0.2 half a cell in front (y = 5.7) and 0.8 half a cell behind (y = 6.7).
    std::vector<glm::vec4> pos = {{5.5f, 7.0f, 5.5f, 1.0f}, {5.5f, 6.0f, 5.5f, 1.0f}, {5.5f, 7.0f, 5.5f, 0.0f},
                                  {20.0f, 7.0f, 5.5f, 1.0f}, {5.5f, 6.7f, 5.5f, 1.0f}};
    std::vector<glm::vec4> nrm = {{0, -1, 0, 0}, {0, 1, 0, 0}, {0, -1, 0, 0}, {0, -1, 0, 0}, {0, -1, 0, 0}};
    std::vector<glm::vec4> alb(5, glm::vec4(0.5f, 0.25f, 1.0f, 0.0f));
    const uint32_t w = 5;
    // One surfel: flux (4, 4, 4) facing +y into cell (5, 6, 5); M = 4, so the cell holds
    // (1 / pi) cosineLobe(+y), and the irradiance facing down is
    // dot((1 / pi) cosineLobe(+y), cosineLobe(+y)) * M / cell^2 = (pi/4 + pi/3) / pi * 4 = 4.6667 (cell = 1).
    const float e = (0.78539816f + 1.04719755f) / kPi * 4.0f;
    for (float damping : {0.0f, 0.5f, 1.0f}) {
        // Fresh uploads each round: the graph imports them as just written by a transfer.
        Image gbuffer[3] = {*uploaded(pos, VK_FORMAT_R32G32B32A32_SFLOAT, w, 1, false),
                            *uploaded(nrm, VK_FORMAT_R16G16B16A16_SFLOAT, w, 1, false),
                            *uploaded(alb, VK_FORMAT_R16G16B16A16_SFLOAT, w, 1, false)};
        run({{{0, 0}, {5.5f, 5.5f, 5.5f, 1.0f}, {0, 1, 0}, {4, 4, 4}}}, VK_FORMAT_R32G32B32A32_SFLOAT, 1.0f, gbuffer,
            w, damping);
        std::vector<glm::vec4> out = indirect();
        ASSERT_EQ(out.size(), 5u);
        const glm::vec3 albedoOverPi = glm::vec3(alb[0]) / kPi;
        // Pixel 0 sits on a cell centre (exact weights) with equal light half a cell in front and
        // behind (0.5 each): no damping at any strength.
        // The lookup's 32-point cosine-weighted quadrature integrates the linear band-1 term to
        // 2.7e-4 (measured): tolerance 1e-3.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(out[0][c], albedoOverPi[c] * e, 1e-3f * e) << "damping " << damping;
        // Pixel 1 faces up, away from the light: the lookup integrates the non-negative part of
        // the radiance, and the 2-band lobe (1/pi)(1/4 + cos/2) is still positive down to
        // cos = -1/2 behind it: 2 pi integral_0^1/2 (1/4 - u/2) u du / pi = 1/48 per unit of M,
        // times M = 4: 1/12 (the unclamped dot product was -1/3, clamped to 0, which also
        // cancelled other light; measured 0.0833 with the 32-point quadrature).
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(out[1][c], albedoOverPi[c] / 12.0f, 0.02f * albedoOverPi[c] / 12.0f) << "damping " << damping;
        EXPECT_EQ(out[2], glm::vec4(0, 0, 0, 1));
        EXPECT_EQ(out[3], glm::vec4(0, 0, 0, 1));
        // Pixel 4: 0.7 e, damped by 1 - damping * (0.8 - 0.2) / (0.8 + 0.2). lavapipe filters with
        // 8-bit sub-texel weights: tolerance 1/256 of e.
        float expected4 = 0.7f * e * (1.0f - damping * 0.6f);
        EXPECT_NEAR(out[4].x, albedoOverPi.x * expected4, albedoOverPi.x * e / 256.0f) << "damping " << damping;
    }
}

namespace {

// A wall of surfels on the plane x = 4 covering y, z in [0, 8) at 0.25 spacing (32 x 32),
// normals facing -x: every interior GV corner on the plane gets 16 surfels of 1/16 cell area.
// A wall at x = 4 covering the grid's cross-section, sampled by n x n texels.
std::vector<glm::vec4> wallPositions(int n = 32) {
    std::vector<glm::vec4> p;
    const float d = float(kGrid) / float(n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            p.push_back({4.0f, d * (0.5f + float(i)), d * (0.5f + float(j)), 1.0f});
    return p;
}

// The GV corners of the wall of wallPositions ((kGrid + 1)^3, x fastest): the largest
// deviation of an interior corner on the plane x = 4 from a full cosine lobe around +x
// (`worst`), and the largest lobe off the plane (`off`).
struct WallCheck {
    float worst = 0.0f, off = 0.0f;
};
WallCheck checkWall(const std::vector<glm::vec4>& blocking) {
    const int corners = kGrid + 1;
    const glm::vec4 full = gpu::shCosineLobe(glm::vec3(1, 0, 0));
    WallCheck c;
    for (int z = 0; z < corners; ++z)
        for (int y = 0; y < corners; ++y)
            for (int x = 0; x < corners; ++x) {
                glm::vec4 b = blocking[size_t(x + corners * (y + corners * z))];
                if (x != 4)
                    c.off = std::max(c.off, glm::length(b));
                else if (y > 0 && y < kGrid && z > 0 && z < kGrid)
                    c.worst = std::max(c.worst, glm::length(b - full));
            }
    return c;
}

} // namespace

TEST_F(LpvInject, GeometryVolumeCountsASurfaceSeenTwiceOnceAndStopsLight) {
    const std::vector<glm::vec4> pos = wallPositions();
    const std::vector<glm::vec4> nrm(pos.size(), glm::vec4(-1, 0, 0, 0));
    // The same wall as RSM surfels and as camera surfels: combined by max, not summed.
    Image* rsmPos = uploaded(pos, VK_FORMAT_R32G32B32A32_SFLOAT, 32, 32, true);
    Image* rsmNrm = uploaded(nrm, VK_FORMAT_R16G16B16A16_SFLOAT, 32, 32, true);
    Image* camPos = uploaded(pos, VK_FORMAT_R32G32B32A32_SFLOAT, 32, 32, false);
    Image* camNrm = uploaded(nrm, VK_FORMAT_R16G16B16A16_SFLOAT, 32, 32, false);
    const int corners = kGrid + 1;
    GeometryVolume volume;
    volume.size = glm::ivec3(corners);
    volume.blocking = geometryVolume(rsmPos, rsmNrm, 32, camPos, camNrm, 32, 32);

    // Interior corners of the wall: coverage 16 x 1/16 = 1 (not 2), lobe around +x (the
    // direction of the light it stops). float16: tolerance 1e-3. Off the plane: exactly zero.
    WallCheck wall = checkWall(volume.blocking);
    EXPECT_LE(wall.worst, 1e-3f);
    EXPECT_EQ(wall.off, 0.0f);

    // Leak: a cosine lobe facing the wall two cells in front of it, 16 steps (CPU reference,
    // which the GPU propagation matches: lpv_propagation_test). A fully covered face stops
    // 0.75 of head-on light (the 2-band clamped cosine peaks at 0.75) and less at an angle;
    // the border corners have half coverage. Measured 0.183; bound 0.25.
    ShVolume initial{glm::ivec3(kGrid)};
    for (int c = 0; c < 3; ++c)
        initial.channel[c][initial.index({2, 4, 4})] = gpu::shCosineLobe(vec3(1, 0, 0)) / kPi;
    auto behindTheWall = [&](const GeometryVolume& occlusion) {
        ShVolume cur = initial, next, acc = initial;
        for (int step = 0; step < 16; ++step) {
            propagateStep(cur, next, &acc, occlusion);
            std::swap(cur, next);
        }
        double sum = 0.0;
        for (int z = 0; z < kGrid; ++z)
            for (int y = 0; y < kGrid; ++y)
                for (int x = 4; x < kGrid; ++x)
                    sum += double(gpu::shIntegral(acc.channel[0][acc.index({x, y, z})]));
        return sum;
    };
    const double open = behindTheWall(GeometryVolume{}), blocked = behindTheWall(volume);
    std::printf("[lpv] light behind a wall: %.4f with GV, %.4f without (%.1f%%)\n", blocked, open,
                100.0 * blocked / open);
    EXPECT_GT(open, 0.0);
    // A fully covered face passes at least 0.25 of head-on light (the 2-band clamped cosine
    // peaks at 0.75). Propagation keeps light in the direction it crossed a face, so most of it
    // meets the wall head-on: measured 26.2% (18.3% with Lambertian reprojection, which turned
    // light sideways before it reached the wall).
    EXPECT_LE(blocked, 0.3 * open);
}

TEST_F(LpvInject, CameraGeometryVolumeIsTheSameWhenTheGBufferIsSampledSparsely) {
    // The wall of GeometryVolumeCountsASurfaceSeenTwiceOnce as a 64 x 64 camera G-buffer over an
    // 8^3 grid: 8 pixels per cell, so the camera pass samples every 2nd pixel (>= 4 samples per
    // cell per axis, gi/src/lpv/lpv_inject.cpp), each standing for 2 x 2 pixels' area. Interior
    // corners: 4 x 4 samples of 1/16 of a cell face = coverage 1, as with every pixel.
    const std::vector<glm::vec4> pos = wallPositions(64);
    const std::vector<glm::vec4> nrm(pos.size(), glm::vec4(-1, 0, 0, 0));
    Image* camPos = uploaded(pos, VK_FORMAT_R32G32B32A32_SFLOAT, 64, 64, false);
    Image* camNrm = uploaded(nrm, VK_FORMAT_R16G16B16A16_SFLOAT, 64, 64, false);
    WallCheck wall = checkWall(geometryVolume(nullptr, nullptr, 0, camPos, camNrm, 64, 64));
    EXPECT_LE(wall.worst, 1e-3f);
    EXPECT_EQ(wall.off, 0.0f);
    EXPECT_EQ(validation().count(), 0u);
}
