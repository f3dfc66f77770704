// The VPL passes on a synthetic RSM and G-buffer built on the CPU, so every number has a closed
// form: a spotlight 1 m above the floor plane y = 0 lights a disc; the G-buffer is a wall and a
// piece of floor. Checks: VPLs on the lit surface inside the cone with the exact flux, smooth
// motion with the light, the gather against the same sum on the CPU, convergence to the
// continuous integral as the VPL count grows, finiteness from 1e-6 to 1e9 cd, negative VPLs
// never adding light, and the low-resolution refinement matching full resolution where it refines.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "vkgi/context.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "gi/direct_types.h"
#include "gi/vpl.h"
#include "vkgi/vpl.hpp"
#include "support/gpu_fixture.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kRsm = 64;                  // RSM texels per side
constexpr float kRsmHalfFov = 0.6108652f;      // 35 degrees: covers the 30-degree cone
constexpr float kConeHalf = 0.5235988f;        // 30 degrees
constexpr uint32_t kW = 32, kH = 32;           // G-buffer
const glm::vec3 kAlbedoFloor(0.5f, 0.6f, 0.7f);
constexpr float kAlbedoWall = 0.8f;

struct Light {
    glm::vec3 position{0.0f, 1.0f, 0.0f};
    glm::vec3 direction{0.0f, -1.0f, 0.0f};
    float intensity = 10.0f; // cd
};

// Host-side images of the RSM layer and its shadow view.
struct SyntheticRsm {
    std::vector<glm::vec4> position, normal, flux;
    gpu::GpuShadowView view{};
};

glm::mat4 lightViewProj(const Light& l) {
    glm::vec3 up = std::abs(l.direction.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
    glm::mat4 proj = glm::perspective(2.0f * kRsmHalfFov, 1.0f, 0.01f, 10.0f);
    proj[1][1] *= -1.0f; // Vulkan clip space: y down
    return proj * glm::lookAt(l.position, l.position + l.direction, up);
}

// Ray through each texel centre hits the floor; flux = albedo * I * texel solid angle.
SyntheticRsm makeRsm(const Light& l) {
    SyntheticRsm r;
    glm::mat4 vp = lightViewProj(l);
    glm::mat4 inv = glm::inverse(vp);
    float side = 2.0f * std::tan(kRsmHalfFov) / float(kRsm);
    r.view.viewProj = vp;
    r.view.eye = glm::vec4(l.position, 10.0f);
    r.view.axisArea = glm::vec4(l.direction, side * side);
    r.view.texel = glm::vec4(side, 10.0f, float(kRsm), 0.0f);
    for (uint32_t y = 0; y < kRsm; ++y)
        for (uint32_t x = 0; x < kRsm; ++x) {
            glm::vec4 ndc((x + 0.5f) / kRsm * 2.0f - 1.0f, (y + 0.5f) / kRsm * 2.0f - 1.0f, 0.5f, 1.0f);
            glm::vec4 w = inv * ndc;
            glm::vec3 dir = glm::normalize(glm::vec3(w) / w.w - l.position);
            if (dir.y >= -1e-4f) {
                r.position.emplace_back(0.0f);
                r.normal.emplace_back(0.0f);
                r.flux.emplace_back(0.0f);
                continue;
            }
            float t = -l.position.y / dir.y;
            float c = glm::dot(dir, l.direction);
            r.position.emplace_back(l.position + t * dir, 1.0f);
            r.normal.emplace_back(0.0f, 1.0f, 0.0f, 0.0f);
            r.flux.emplace_back(kAlbedoFloor * l.intensity * (side * side * c * c * c), 0.0f);
        }
    return r;
}

// G-buffer columns: 0-9 a wall x = 0.6 facing -x, 10-20 a second wall x = 1.2 behind it (the
// floor VPLs, all at x < tan(30 deg) = 0.58, light it through the first wall: no visibility),
// 21-30 floor points, 31 background.
struct GBuffer {
    std::vector<glm::vec4> position, normal, albedo;
};
GBuffer makeGBuffer() {
    GBuffer g;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            float v = (y + 0.5f) / kH;
            if (x == kW - 1) {
                g.position.emplace_back(0.0f);
                g.normal.emplace_back(0.0f, 0.0f, 1.0f, 0.0f);
                g.albedo.emplace_back(0.0f);
            } else if (x < 21) {
                float wallX = x < 10 ? 0.6f : 1.2f;
                float u = x < 10 ? (x + 0.5f) / 10.0f : (x - 10 + 0.5f) / 11.0f;
                g.position.emplace_back(wallX, 0.02f + 0.9f * v, -0.5f + u, 1.0f);
                g.normal.emplace_back(-1.0f, 0.0f, 0.0f, 0.0f);
                g.albedo.emplace_back(kAlbedoWall, kAlbedoWall, kAlbedoWall, 0.0f);
            } else {
                float u = (x - 21 + 0.5f) / 10.0f;
                g.position.emplace_back(-0.6f + 1.2f * u, 0.0f, -0.6f + 1.2f * v, 1.0f);
                g.normal.emplace_back(0.0f, 1.0f, 0.0f, 0.0f);
                g.albedo.emplace_back(kAlbedoWall, kAlbedoWall, kAlbedoWall, 0.0f);
            }
        }
    return g;
}

// A G-buffer of one smooth surface: the wall x = 0.6 facing -x over the whole image, where the
// floor VPLs' irradiance varies slowly.
GBuffer makeWallGBuffer() {
    GBuffer g;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            g.position.emplace_back(0.6f, 0.02f + 0.9f * (y + 0.5f) / kH, -0.5f + (x + 0.5f) / kW, 1.0f);
            g.normal.emplace_back(-1.0f, 0.0f, 0.0f, 0.0f);
            g.albedo.emplace_back(kAlbedoWall, kAlbedoWall, kAlbedoWall, 0.0f);
        }
    return g;
}

struct RunResult {
    std::vector<gpu::VplRecord> vpls;
    std::vector<gpu::VplRecord> negative;
    std::vector<glm::vec4> indirect;
    uint32_t refined = 0;
};

class VplSynthetic : public test::GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        if (HasFatalFailure() || IsSkipped())
            return;
        auto r = VplTechnique::create(ctx());
        ASSERT_TRUE(r) << r.error().message;
        m_technique = std::move(r.value());
    }
    void TearDown() override {
        vkDeviceWaitIdle(ctx().device());
        m_technique.reset();
        GpuTest::TearDown();
    }

    // `layers` = 2 for the RSM: a 2D-array view as the RSM arrays have (layer 1 stays empty).
    Image uploadArray(std::vector<glm::vec4> texels, uint32_t w, uint32_t h, const char* name, uint32_t layers = 1) {
        ImageDesc d;
        d.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        d.width = w;
        d.height = h;
        d.arrayLayers = layers;
        texels.resize(size_t(w) * h * layers, glm::vec4(0.0f));
        d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        Image img = createImage(ctx(), d, name);
        uploadImage(ctx(), img, texels.data(), texels.size() * sizeof(glm::vec4),
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        return img;
    }

    // Adds a copy of `h` (buffer or image) into a host buffer; returns the host buffer.
    Buffer& hostCopy(rg::RenderGraph& g, rg::BufferHandle h, VkDeviceSize bytes) {
        m_host.push_back(createBuffer(ctx(), {bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::GpuToCpu}, "host"));
        rg::BufferHandle host = g.importBuffer("host", m_host.back(), rg::Access::None);
        g.addPass(
            "readback",
            [&](rg::PassBuilder& b) {
                b.read(h, rg::Access::TransferRead);
                host = b.write(host, rg::Access::TransferWrite);
                b.sideEffect();
            },
            [=](rg::PassContext& pc) {
                VkBufferCopy region{0, 0, bytes};
                vkCmdCopyBuffer(pc.cmd(), pc.buffer(h).buffer, pc.buffer(host).buffer, 1, &region);
            });
        g.exportBuffer(host, rg::Access::HostRead);
        return m_host.back();
    }
    Buffer& hostCopy(rg::RenderGraph& g, rg::ImageHandle h, uint32_t w, uint32_t hgt) {
        m_host.push_back(
            createBuffer(ctx(), {VkDeviceSize(w) * hgt * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::GpuToCpu},
                         "host"));
        rg::BufferHandle host = g.importBuffer("host", m_host.back(), rg::Access::None);
        g.addPass(
            "readback",
            [&](rg::PassBuilder& b) {
                b.read(h, rg::Access::TransferRead);
                host = b.write(host, rg::Access::TransferWrite);
                b.sideEffect();
            },
            [=](rg::PassContext& pc) {
                VkBufferImageCopy region{};
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.imageExtent = {w, hgt, 1};
                vkCmdCopyImageToBuffer(pc.cmd(), pc.image(h).image, pc.layout(h), pc.buffer(host).buffer, 1, &region);
            });
        g.exportBuffer(host, rg::Access::HostRead);
        return m_host.back();
    }

    template <typename T> static std::vector<T> read(const Buffer& b, size_t count) {
        std::vector<T> v(count);
        std::memcpy(v.data(), b.mapped(), count * sizeof(T));
        return v;
    }

    RunResult run(const Light& light, const VplSettings& settings, float fluxScale = 1.0f,
                  const GBuffer& gb = makeGBuffer()) {
        RunResult result;
        m_host.reserve(8); // hostCopy hands out references into m_host
        SyntheticRsm rsm = makeRsm(light);
        for (glm::vec4& f : rsm.flux)
            f *= fluxScale;
        Image rsmPos = uploadArray(rsm.position, kRsm, kRsm, "rsm.position", 2);
        Image rsmNrm = uploadArray(rsm.normal, kRsm, kRsm, "rsm.normal", 2);
        Image rsmFlux = uploadArray(rsm.flux, kRsm, kRsm, "rsm.flux", 2);
        Image gPos = uploadArray(gb.position, kW, kH, "g.position");
        Image gNrm = uploadArray(gb.normal, kW, kH, "g.normal");
        Image gAlb = uploadArray(gb.albedo, kW, kH, "g.albedo");
        Buffer views = createBuffer(ctx(), {sizeof(rsm.view), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT}, "views");
        uploadBuffer(ctx(), views, &rsm.view, sizeof(rsm.view));
        {
            rg::RenderGraph g;
            VplInputs in;
            auto sampled = rg::Access::ComputeSampledRead;
            in.gPosition = g.importImage("g.position", gPos, sampled);
            in.gNormal = g.importImage("g.normal", gNrm, sampled);
            in.gAlbedo = g.importImage("g.albedo", gAlb, sampled);
            in.width = kW;
            in.height = kH;
            in.camera.position = glm::vec3(-1.0f, 0.5f, 0.0f);
            in.rsmPosition = g.importImage("rsm.position", rsmPos, sampled);
            in.rsmNormal = g.importImage("rsm.normal", rsmNrm, sampled);
            in.rsmFlux = g.importImage("rsm.flux", rsmFlux, sampled);
            in.shadowViews = g.importBuffer("views", views, rg::Access::TransferWrite);
            in.spots.push_back({light.position, light.direction, std::cos(kConeHalf), 0, 1});
            auto out = m_technique->addPasses(g, in, settings);
            EXPECT_TRUE(out) << out.error().message;
            if (!out)
                return result;
            Buffer& vpls = hostCopy(g, out->vpls, out->vplCount * sizeof(gpu::VplRecord));
            Buffer* neg = out->negativeVpls.valid()
                              ? &hostCopy(g, out->negativeVpls, settings.negativeVplCount * sizeof(gpu::VplRecord))
                              : nullptr;
            Buffer* list = out->refineList.valid() ? &hostCopy(g, out->refineList, 16) : nullptr;
            Buffer& indirect = hostCopy(g, out->indirect, kW, kH);
            auto compiled = g.compile();
            EXPECT_TRUE(compiled) << compiled.error().message;
            rg::TransientPool pool(ctx());
            ctx().submitAndWait([&](VkCommandBuffer cmd) { g.execute(cmd, ctx(), pool); });
            result.vpls = read<gpu::VplRecord>(vpls, out->vplCount);
            if (neg)
                result.negative = read<gpu::VplRecord>(*neg, settings.negativeVplCount);
            if (list)
                result.refined = read<uint32_t>(*list, 1)[0];
            result.indirect = read<glm::vec4>(indirect, kW * kH);
        }
        for (Image* i : {&rsmPos, &rsmNrm, &rsmFlux, &gPos, &gNrm, &gAlb})
            destroyImage(ctx(), *i);
        destroyBuffer(ctx(), views);
        for (Buffer& b : m_host)
            destroyBuffer(ctx(), b);
        m_host.clear();
        return result;
    }

    std::unique_ptr<VplTechnique> m_technique;
    std::vector<Buffer> m_host;
};

// CPU version of the gather (gi/vpl_gather.h) for one G-buffer pixel: each VPL's 1/d^2 is clamped
// at clamp times its footprint radius (flux.w = radius^2).
glm::vec3 cpuGather(const std::vector<gpu::VplRecord>& vpls, glm::vec3 x, glm::vec3 n, float clamp) {
    glm::dvec3 e(0.0);
    for (const auto& v : vpls) {
        glm::dvec3 d = glm::dvec3(v.position) - glm::dvec3(x);
        double d2 = glm::dot(d, d);
        glm::dvec3 w = d / std::sqrt(std::max(d2, 1e-30));
        double g = std::max(glm::dot(glm::dvec3(n), w), 0.0) * std::max(-glm::dot(glm::dvec3(v.direction), w), 0.0) /
                   std::max(d2, double(clamp) * double(clamp) * double(v.flux.w));
        e += glm::dvec3(v.flux) * g * double(v.position.w);
    }
    return glm::vec3(e / glm::pi<double>());
}

// The continuous limit of the VPL sum: irradiance at x from the lit floor disc, integrated over
// the cone's solid angle with a midpoint rule in (cos, phi) (uniform in solid angle), same clamp.
glm::vec3 coneIntegral(const Light& l, glm::vec3 x, glm::vec3 n, float clamp2) {
    const int kZ = 200, kPhi = 400; // 8e4 midpoints: quadrature error far below the 1e-2 VPL errors
    double cosOuter = std::cos(double(kConeHalf));
    double dOmega = (1.0 - cosOuter) / kZ * (2.0 * glm::pi<double>() / kPhi);
    double sum = 0.0;
    for (int i = 0; i < kZ; ++i) {
        double z = cosOuter + (i + 0.5) * (1.0 - cosOuter) / kZ;
        double r = std::sqrt(1.0 - z * z);
        for (int j = 0; j < kPhi; ++j) {
            double phi = (j + 0.5) * 2.0 * glm::pi<double>() / kPhi;
            glm::dvec3 dir(r * std::cos(phi), -z, r * std::sin(phi)); // spot points down
            glm::dvec3 p = glm::dvec3(l.position) + dir * (double(l.position.y) / z);
            glm::dvec3 d = p - glm::dvec3(x);
            double d2 = glm::dot(d, d);
            glm::dvec3 w = d / std::sqrt(d2);
            sum += std::max(glm::dot(glm::dvec3(n), w), 0.0) * std::max(-w.y, 0.0) / std::max(d2, double(clamp2));
        }
    }
    return glm::vec3(kAlbedoFloor) * float(l.intensity * sum * dOmega / glm::pi<double>());
}

} // namespace

TEST_F(VplSynthetic, VplsLieOnTheLitFloorInsideTheConeWithExactFlux) {
    Light l;
    VplSettings s;
    s.vplCount = 200;
    RunResult r = run(l, s);
    ASSERT_EQ(r.vpls.size(), 200u);
    float omegaPerVpl = coneSolidAngle(std::cos(kConeHalf)) / 200.0f;
    for (const auto& v : r.vpls) {
        ASSERT_EQ(v.position.w, 1.0f);
        EXPECT_NEAR(v.position.y, 0.0f, 1e-5f);
        glm::vec3 d = glm::normalize(glm::vec3(v.position) - l.position);
        EXPECT_LE(std::acos(glm::dot(d, l.direction)), kConeHalf + 1e-4f) << "exact ray, not the texel centre";
        EXPECT_NEAR(v.direction.y, 1.0f, 1e-6f);
        // albedo * I * cone solid angle / N, independent of the texel (float rounding only).
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(v.flux[c], kAlbedoFloor[c] * l.intensity * omegaPerVpl, 1e-4f * omegaPerVpl * l.intensity);
        // Footprint: the floor area of its solid angle, omega d^2 / cos with cos = 1 / d (the
        // light is 1 m above the floor), as the squared radius of a disc: omega d^3 / pi.
        const float dist = glm::distance(glm::vec3(v.position), l.position);
        const float footprint = omegaPerVpl * dist * dist * dist / glm::pi<float>();
        EXPECT_NEAR(v.flux.w, footprint, 1e-4f * footprint);
    }
}

TEST_F(VplSynthetic, VplsMoveSmoothlyWithTheLight) {
    VplSettings s;
    s.vplCount = 100;
    Light a;
    RunResult ra = run(a, s);
    // Translation by 1 mm: on the plane every VPL moves by exactly the same 1 mm.
    Light b = a;
    b.position.x += 1e-3f;
    RunResult rb = run(b, s);
    ASSERT_EQ(ra.vpls.size(), rb.vpls.size());
    for (size_t i = 0; i < ra.vpls.size(); ++i)
        EXPECT_NEAR(glm::length(glm::vec3(rb.vpls[i].position - ra.vpls[i].position) - glm::vec3(1e-3f, 0, 0)), 0.0f,
                    1e-5f)
            << i;
    // Rotation by 0.01 rad: a hit at angle theta from the vertical moves by h / cos^2(theta) per
    // radian (<= 1.34 m at 30 degrees), so no VPL may move more than 1.34 * 0.01 (+ 10 % for the twist).
    Light c = a;
    c.direction = glm::normalize(glm::vec3(std::sin(0.01f), -std::cos(0.01f), 0.0f));
    RunResult rc = run(c, s);
    float maxMove = 0.0f;
    for (size_t i = 0; i < ra.vpls.size(); ++i)
        maxMove = std::max(maxMove, glm::length(glm::vec3(rc.vpls[i].position - ra.vpls[i].position)));
    EXPECT_LE(maxMove, 1.34f * 0.01f * 1.1f);
    EXPECT_GT(maxMove, 0.5f * 0.01f); // it did move (at least h * angle on the axis)
}

TEST_F(VplSynthetic, GatherMatchesTheCpuSum) {
    Light l;
    VplSettings s;
    s.interleave = 1; // the full gather, pixel by pixel
    s.vplCount = 100;
    s.clampDistance = 1.5f;
    RunResult r = run(l, s);
    GBuffer gb = makeGBuffer();
    double maxRel = 0.0;
    for (uint32_t i = 0; i < kW * kH; ++i) {
        glm::vec3 want(0.0f);
        if (gb.position[i].w > 0.0f)
            want = glm::vec3(gb.albedo[i]) / glm::pi<float>() *
                   cpuGather(r.vpls, glm::vec3(gb.position[i]), glm::vec3(gb.normal[i]), s.clampDistance);
        for (int c = 0; c < 3; ++c)
            maxRel = std::max(maxRel, double(std::abs(r.indirect[i][c] - want[c])) / (std::abs(want[c]) + 1e-6));
    }
    EXPECT_LT(maxRel, 1e-4) << "float sums of <= 100 terms against double";
}

// Error against the continuous integral falls as the VPL count grows. Halton placement is a
// quasi-Monte Carlo rule, so the error need not fall at every step; allowed: each count may be
// at most 10 % worse than the previous one, and 400 VPLs must be at least 2x better than 50.
TEST_F(VplSynthetic, ErrorFallsWithVplCount) {
    Light l;
    GBuffer gb = makeGBuffer();
    VplSettings s;
    s.interleave = 1; // the full gather, pixel by pixel
    // The VPLs' clamp radius shrinks as their footprints do (1/sqrt(N)), so the sum tends to the
    // unclamped integral; the integral keeps a 2 cm clamp only to stay finite at the quadrature's
    // resolution where the wall meets the floor.
    const float clamp2 = 0.02f * 0.02f;
    std::vector<glm::vec3> want(kW * kH, glm::vec3(0.0f));
    for (uint32_t i = 0; i < kW * kH; i += 3) // every third pixel keeps the CPU integral short
        if (gb.position[i].w > 0.0f)
            want[i] = glm::vec3(gb.albedo[i]) / glm::pi<float>() *
                      coneIntegral(l, glm::vec3(gb.position[i]), glm::vec3(gb.normal[i]), clamp2);
    std::vector<double> errors;
    for (uint32_t n : {50u, 100u, 200u, 400u}) {
        s.vplCount = n;
        RunResult r = run(l, s);
        double num = 0.0, den = 0.0;
        for (uint32_t i = 0; i < kW * kH; i += 3) {
            glm::vec3 d = glm::vec3(r.indirect[i]) - want[i];
            num += glm::dot(d, d);
            den += glm::dot(want[i], want[i]);
        }
        errors.push_back(std::sqrt(num / den));
    }
    for (size_t k = 1; k < errors.size(); ++k)
        EXPECT_LE(errors[k], errors[k - 1] * 1.1) << "count step " << k;
    EXPECT_LT(errors.back(), 0.5 * errors.front());
    std::printf("relative RMS error vs continuous integral, 50/100/200/400 VPLs: %.4f %.4f %.4f %.4f\n", errors[0],
                errors[1], errors[2], errors[3]);
}

TEST_F(VplSynthetic, FiniteAndLinearFrom1eMinus6To1e9) {
    Light l;
    VplSettings s;
    s.vplCount = 64;
    s.negativeVplCount = 32;
    s.lowResFactor = 2;
    RunResult base = run(l, s, 1.0f);
    for (float scale : {1e-7f, 1e8f}) { // intensity 10 cd x scale: 1e-6 and 1e9 cd
        RunResult r = run(l, s, scale);
        uint32_t nonFinite = 0;
        double maxRel = 0.0;
        for (size_t i = 0; i < r.indirect.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                float v = r.indirect[i][c];
                nonFinite += !std::isfinite(v);
                double want = double(base.indirect[i][c]) * scale;
                maxRel = std::max(maxRel, std::abs(v - want) / (std::abs(want) + 1e-30 + 1e-6 * scale));
            }
        EXPECT_EQ(nonFinite, 0u) << scale;
        // The technique is linear in the light; only float rounding separates the scaled runs.
        EXPECT_LT(maxRel, 1e-3) << scale;
    }
}

TEST_F(VplSynthetic, NegativeVplsOnlyRemoveLight) {
    Light l;
    VplSettings s;
    s.vplCount = 100;
    RunResult positive = run(l, s);
    s.negativeVplCount = 64;
    RunResult withNeg = run(l, s);
    ASSERT_EQ(withNeg.negative.size(), 64u);
    uint32_t valid = 0;
    for (const auto& v : withNeg.negative) {
        valid += v.position.w > 0.0f;
        EXPECT_TRUE(std::isfinite(v.flux.x) && v.flux.x >= 0.0f);
        if (v.position.w > 0.0f) {
            EXPECT_NEAR(glm::length(glm::vec3(v.direction)), 1.0f, 1e-4f);
        }
    }
    // Samples on the walls (21 of 32 columns) carry light; floor samples receive none (coplanar).
    EXPECT_GT(valid, 25u);
    uint32_t darkerBack = 0, darkerFront = 0;
    for (size_t i = 0; i < positive.indirect.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            EXPECT_LE(withNeg.indirect[i][c], positive.indirect[i][c] * (1.0f + 1e-5f));
            EXPECT_GE(withNeg.indirect[i][c], 0.0f);
            bool darker = withNeg.indirect[i][c] < positive.indirect[i][c] * 0.99f;
            uint32_t x = uint32_t(i % kW);
            darkerBack += darker && x >= 10 && x < 21;
            darkerFront += darker && x < 10;
        }
    // The back wall sits in the front wall's shadow: negative VPLs on the front wall darken it,
    // while the front wall, in front of every negative VPL's lobe, keeps its light.
    EXPECT_GT(darkerBack, 11u * kH);
    EXPECT_EQ(darkerFront, 0u);
}

TEST_F(VplSynthetic, LowResRefinesDiscontinuitiesExactly) {
    Light l;
    VplSettings s;
    s.interleave = 1; // the full gather, pixel by pixel
    s.vplCount = 100;
    RunResult full = run(l, s);
    s.lowResFactor = 2;
    s.refineThreshold = 0.05f;
    RunResult low = run(l, s);
    // Refined: pixels next to the background column and the seams between the three planes.
    EXPECT_GT(low.refined, 0u);
    EXPECT_LT(low.refined, kW * kH / 2);
    uint32_t exact = 0;
    for (size_t i = 0; i < full.indirect.size(); ++i)
        exact += std::abs(full.indirect[i].x - low.indirect[i].x) <= 1e-5f * std::abs(full.indirect[i].x);
    EXPECT_GE(exact, low.refined) << "refined pixels are recomputed at full resolution";
    // Every other pixel is a bilinear blend of the 4 nearest gather samples, whose values are the
    // full-resolution values at the sample pixels: it must lie within their range.
    uint32_t outside = 0;
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 0; x < kW; ++x) {
            size_t i = y * kW + x;
            if (std::abs(full.indirect[i].x - low.indirect[i].x) <= 1e-5f * std::abs(full.indirect[i].x))
                continue;
            float lo = 1e30f, hi = -1e30f;
            int ix = int(std::floor((float(x) - 1.0f) / 2.0f)), iy = int(std::floor((float(y) - 1.0f) / 2.0f));
            for (int k = 0; k < 4; ++k) {
                int sx = std::min(std::clamp(ix + (k & 1), 0, int(kW / 2) - 1) * 2 + 1, int(kW) - 1);
                int sy = std::min(std::clamp(iy + (k >> 1), 0, int(kH / 2) - 1) * 2 + 1, int(kH) - 1);
                lo = std::min(lo, full.indirect[size_t(sy) * kW + size_t(sx)].x);
                hi = std::max(hi, full.indirect[size_t(sy) * kW + size_t(sx)].x);
            }
            outside += low.indirect[i].x < lo * (1.0f - 1e-5f) || low.indirect[i].x > hi * (1.0f + 1e-5f);
        }
    EXPECT_EQ(outside, 0u);
}

// Interleaved sampling on a smooth surface: every pixel gathers 1/n^2 of the VPLs and the tent
// filter sums the subsets back, so the result is the full gather smoothed over the tile. Bounds
// (measured: inside 0.07-0.10; at the border 0, 0.18 and 0.65 for n = 2, 3, 4): inside, each
// pixel within 15 % of the full gather (the largest differences sit in the bottom rows, 2 cm
// above the VPLs, where the full sum itself is far from smooth); at the image border, where
// windows are cut, within 75 % (at n = 4 a bottom-row pixel keeps 4 of the 16 subsets, 50 of
// the 200 VPLs, and is not refined); the image mean within 2 %; and the distance to the
// continuous integral no more than 10 % above the full gather's. Filters that weigh the subsets
// unequally or pull the window one way miss these (a one-sided tent: 1.09 at the border; a
// one-sided window with per-class weights: 1.65).
TEST_F(VplSynthetic, InterleavedGatherMatchesTheFullGatherOnASmoothWall) {
    Light l;
    GBuffer wall = makeWallGBuffer();
    VplSettings s;
    s.vplCount = 200;
    s.interleave = 1;
    RunResult full = run(l, s, 1.0f, wall);
    const float clamp2 = 0.02f * 0.02f; // as in ErrorFallsWithVplCount
    std::vector<float> integral(kW * kH, 0.0f);
    for (uint32_t i = 0; i < kW * kH; i += 3) // every third pixel keeps the CPU integral short
        integral[i] = kAlbedoWall / glm::pi<float>() *
                      coneIntegral(l, glm::vec3(wall.position[i]), glm::vec3(wall.normal[i]), clamp2).y;
    auto distanceToIntegral = [&](const RunResult& r) {
        double num = 0.0, den = 0.0;
        for (uint32_t i = 0; i < kW * kH; i += 3) {
            num += std::pow(double(r.indirect[i].y) - integral[i], 2.0);
            den += double(integral[i]) * integral[i];
        }
        return std::sqrt(num / den);
    };
    const double fullDistance = distanceToIntegral(full);
    for (uint32_t n : {2u, 3u, 4u}) {
        s.interleave = n;
        RunResult r = run(l, s, 1.0f, wall);
        double maxInterior = 0.0, maxBorder = 0.0, sumFull = 0.0, sum = 0.0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x) {
                size_t i = y * kW + x;
                double want = full.indirect[i].y, got = r.indirect[i].y;
                ASSERT_GT(want, 0.0);
                double rel = std::abs(got - want) / want;
                bool interior = x + 1 >= n && y + 1 >= n && x + n <= kW && y + n <= kH;
                double& worst = interior ? maxInterior : maxBorder;
                worst = std::max(worst, rel);
                sumFull += want;
                sum += got;
            }
        EXPECT_LT(maxInterior, 0.15) << "n = " << n;
        EXPECT_LT(maxBorder, 0.75) << "n = " << n;
        EXPECT_NEAR(sum / sumFull, 1.0, 0.02) << "n = " << n;
        const double distance = distanceToIntegral(r);
        EXPECT_LT(distance, 1.1 * fullDistance) << "n = " << n;
        std::printf("interleave %u: max relative difference inside %.4f, at the border %.4f, mean ratio %.4f, "
                    "distance to the integral %.4f (full gather %.4f)\n",
                    n, maxInterior, maxBorder, sum / sumFull, distance, fullDistance);
    }
}

// The filter sums subsets only over one surface: the floor (no light from the coplanar floor
// VPLs) stays black next to the lit wall, and the two walls (same normal, 0.6 m apart) keep
// their own light: the worst wall pixel within 60 % of the full gather (measured 0.51: a pixel
// next to a seam keeps 4 of the 16 subsets). Without the tangent-plane test (tolerance 1 = the
// whole distance to the camera) the walls mix and the worst pixel is off by 3.7 times its value.
TEST_F(VplSynthetic, InterleaveFilterKeepsSurfacesApart) {
    Light l;
    VplSettings s;
    s.vplCount = 200;
    s.interleave = 1;
    RunResult full = run(l, s);
    auto worstWallError = [&](const RunResult& r) {
        double worst = 0.0;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < 21; ++x) {
                size_t i = y * kW + x;
                worst = std::max(worst, double(std::abs(r.indirect[i].y - full.indirect[i].y) / full.indirect[i].y));
            }
        return worst;
    };
    s.interleave = 4;
    RunResult r = run(l, s);
    for (uint32_t y = 0; y < kH; ++y)
        for (uint32_t x = 21; x < kW; ++x)
            EXPECT_EQ(r.indirect[y * kW + x].y, 0.0f) << x << ", " << y;
    const double apart = worstWallError(r);
    EXPECT_GT(r.refined, 0u) << "one-pixel windows next to the seams are gathered again in full";
    s.interleaveTolerance = 1.0f;
    const double mixed = worstWallError(run(l, s));
    std::printf("worst wall pixel against the full gather: %.4f (planes kept apart), %.4f (mixed)\n", apart, mixed);
    EXPECT_LT(apart, 0.6);
    EXPECT_GT(mixed, 2.0);
}
