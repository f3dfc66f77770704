// Reflective shadow map flux: summed over all texels it must equal albedo x the light's power
// that reaches the surfaces (vkgi/frame_data.hpp documents the per-texel formula).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "vk_check.hpp"
#include "vkgi/frame_data.hpp"
#include "vkgi/gi.hpp"
#include "direct/direct_passes.hpp"
#include "engine/lights.h"
#include "engine/scene_types.h"
#include "lpv/lpv_grid.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/gpu_util.hpp"
#include "support/test_scenes.hpp"

using namespace vkgi;

namespace {

constexpr double kPi = 3.14159265358979;

class RsmTest : public test::GpuTest {
protected:
    // Renders one frame with the RSM forced on and returns the summed flux (rgb) over all layers,
    // plus the number of layers.
    glm::dvec3 totalFlux(const Scene& scene, uint32_t* layers = nullptr) {
        gi::GiSettings s;
        s.forceRsm = true;
        auto sys = test::systemWithScene(ctx(), s, scene);
        EXPECT_TRUE(sys) << (sys ? "" : sys.error().message);
        if (!sys)
            return {};
        rg::RenderGraph graph;
        rg::Blackboard bb;
        auto out = (*sys)->addPasses(graph, bb, scene.cameraOrDefault(), 8, 8);
        EXPECT_TRUE(out);
        const gi::RsmData& rsm = bb.get<gi::RsmData>();
        const uint32_t n = rsm.resolution, count = uint32_t(rsm.layers.size());
        if (layers)
            *layers = count;
        auto texels =
            test::asArray<glm::vec4>(test::runAndReadImage(ctx(), graph, rsm.flux, VkDeviceSize(n) * n * count * 16));
        glm::dvec3 sum(0.0);
        for (const glm::vec4& t : texels)
            sum += glm::dvec3(t);
        return sum;
    }
};

Scene bigPlane(float albedo, float halfSize) {
    Scene s = test::plane(albedo, halfSize);
    Camera c;
    c.position = {0.0f, 3.0f, 0.1f};
    c.forward = {0.0f, -1.0f, 0.0f};
    s.camera = c;
    return s;
}

} // namespace

// Spot 1 m above a 20 m plane, straight down: every ray of the cone hits the plane, so the RSM
// must hold albedo x the cone's power, 2 pi I [(1 - cos inner) + (cos inner - cos outer)/3]
// (the glTF smooth ramp t^2 integrates to 1/3 of the ramp's solid-angle width in cos).
TEST_F(RsmTest, SpotFluxEqualsAlbedoTimesConePower) {
    const float albedo = 0.6f, intensity = 3.0f;
    Scene scene = bigPlane(albedo, 10.0f);
    Light spot;
    spot.type = LightType::Spot;
    spot.position = {0.0f, 1.0f, 0.0f};
    spot.direction = {0.0f, -1.0f, 0.0f};
    spot.intensity = intensity;
    spot.innerConeAngle = 0.5f;
    spot.outerConeAngle = 0.8f; // below kMaxSpotFrustumHalfAngle: one perspective layer
    scene.lights.push_back(spot);
    uint32_t layers = 0;
    glm::dvec3 flux = totalFlux(scene, &layers);
    EXPECT_EQ(layers, 1u);
    double ci = std::cos(0.5), co = std::cos(0.8);
    double expected = albedo * 2.0 * kPi * intensity * ((1.0 - ci) + (ci - co) / 3.0);
    // Midpoint sums of a smooth integrand over 256^2 texels: error O(1/N^2) ~ 1e-5 (measured 1e-6);
    // 1e-4 covers that and float32 rounding, and fails a wrong cos^3 or a missed ramp.
    std::printf("spot: RSM flux / expected = %.7f\n", flux.g / expected);
    EXPECT_NEAR(flux.r / expected, 1.0, 1e-4) << flux.r << " vs " << expected;
    EXPECT_NEAR(flux.g / expected, 1.0, 1e-4);
}

// Point light at the centre of a closed box: the 6 cube faces see every direction once, so the
// flux sums to albedo x 4 pi I.
TEST_F(RsmTest, PointLightInAClosedBoxReflectsAlbedoTimesFourPiI) {
    BuiltinSceneParams p;
    p.furnaceAlbedo = 0.5f;
    auto furnace = makeBuiltinScene("furnace", p);
    ASSERT_TRUE(furnace) << furnace.error().message;
    Scene scene = *furnace;
    Light point;
    point.type = LightType::Point;
    point.position = scene.bounds().centre() + glm::vec3(0.05f, -0.03f, 0.02f); // off-centre on purpose
    point.intensity = 2.0f;
    scene.lights.push_back(point);
    uint32_t layers = 0;
    glm::dvec3 flux = totalFlux(scene, &layers);
    EXPECT_EQ(layers, 6u);
    double expected = 0.5 * 4.0 * kPi * 2.0;
    std::printf("point: RSM flux / expected = %.7f\n", flux.g / expected);
    // Same midpoint-rule argument as the spot, over six faces (measured 4e-6).
    EXPECT_NEAR(flux.g / expected, 1.0, 1e-4) << flux.g << " vs " << expected;
}

// An LPV emitter proxy (GI_LIGHT_EMITTER, docs/lpv.md "Emissive surfaces") in a closed box,
// facing down: its intensity I max(0, n.w) integrates to pi I over the lower hemisphere, all of
// which reaches the walls, so its cube RSM (addPointSourceRsmPass) sums to albedo x pi I. The
// point light's profile would give 4 pi I, a cos^2 one 2 pi I / 3.
TEST_F(RsmTest, EmitterProxyInAClosedBoxReflectsAlbedoTimesPiI) {
    BuiltinSceneParams p;
    p.furnaceAlbedo = 0.5f;
    auto furnace = makeBuiltinScene("furnace", p);
    ASSERT_TRUE(furnace) << furnace.error().message;
    const Scene scene = *furnace;
    auto sys = test::systemWithScene(ctx(), gi::GiSettings{}, scene);
    ASSERT_TRUE(sys) << sys.error().message;
    rg::RenderGraph graph;
    rg::Blackboard bb;
    ASSERT_TRUE((*sys)->addPasses(graph, bb, scene.cameraOrDefault(), 8, 8));
    auto pipelines = gi::createDirectPipelines(ctx());
    ASSERT_TRUE(pipelines) << pipelines.error().message;
    const gi::FrameData& frame = bb.get<gi::FrameData>();
    const glm::vec3 position = scene.bounds().centre() + glm::vec3(0.05f, 0.2f, 0.02f); // off-centre on purpose
    const float intensity = 2.0f;
    gpu::GpuLight light{};
    light.positionType = glm::vec4(position, float(GI_LIGHT_EMITTER));
    light.directionRange = glm::vec4(0.0f, -1.0f, 0.0f, 0.0f);
    light.colorIntensity = glm::vec4(1.0f, 1.0f, 1.0f, intensity);
    rg::BufferHandle lights = graph.createBuffer("test.emitter.lights", BufferDesc{sizeof(light)});
    graph.addPass(
        "test.emitter.upload", [&](rg::PassBuilder& b) { lights = b.write(lights, rg::Access::TransferWrite); },
        [lights, light](rg::PassContext& pc) {
            vkCmdUpdateBuffer(pc.cmd(), pc.buffer(lights).buffer, 0, sizeof(light), &light);
        });
    constexpr uint32_t kRes = 128;
    const gi::RsmImages rsm =
        gi::addPointSourceRsmPass(graph, *pipelines, frame, bb.get<gi::SceneHandles>(), lights,
                                  gi::cubeShadowViews(position, frame.gpuScene->bounds, kRes), kRes, "test.emitter.rsm");
    auto texels =
        test::asArray<glm::vec4>(test::runAndReadImage(ctx(), graph, rsm.flux, VkDeviceSize(kRes) * kRes * 6 * 16));
    gi::destroyDirectPipelines(ctx(), *pipelines);
    glm::dvec3 flux(0.0);
    for (const glm::vec4& t : texels)
        flux += glm::dvec3(t);
    const double expected = 0.5 * kPi * intensity;
    std::printf("emitter proxy: RSM flux / expected = %.7f\n", flux.g / expected);
    // The midpoint argument of the point light, plus the cosine's kink at the horizon on the side
    // faces' centre rows (measured 3e-5 at 128^2); a wrong profile is off by factors.
    EXPECT_NEAR(flux.g / expected, 1.0, 2e-4) << flux.g << " vs " << expected;
}

// Sun on a 2 x 2 m plane: the orthographic texels tile the plane's projection, so the flux is
// albedo x E x (area x cos of the sun's elevation from the normal).
TEST_F(RsmTest, DirectionalFluxEqualsAlbedoTimesIlluminanceTimesProjectedArea) {
    const float albedo = 0.5f, lux = 10.0f, half = 1.0f;
    Scene scene = bigPlane(albedo, half);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    sun.intensity = lux;
    scene.lights.push_back(sun);
    glm::dvec3 flux = totalFlux(scene);
    double area = 4.0 * half * half, cosSun = -sun.direction.y;
    double expected = albedo * lux * area * cosSun;
    // Texels whose centre falls inside the projected square are counted whole: the error is at
    // most half a texel along the perimeter, perimeter x texel / 2 / area. The ortho box spans
    // the bounds' diagonal (<= 2.9 m) over 256 texels.
    double texel = 2.0 * std::sqrt(2.0) * half / 256.0 * 1.01;
    double bound = (8.0 * half) * texel / 2.0 / area;
    std::printf("sun: RSM flux / expected = %.7f (bound %.4f)\n", flux.g / expected, bound);
    EXPECT_NEAR(flux.g / expected, 1.0, bound) << flux.g << " vs " << expected;
}

// The LPV's cascades in a large world read a sun's RSM through a window fitted to their coarsest
// level: a 400 m plane (a 2 m tile raised 10 m in a far corner gives the world its height)
// seen from 3 m above its centre. The windowed RSM holds albedo x E x cos x the area of the
// plane inside the window's footprint, with texels about six times finer than the own layer's.
TEST_F(RsmTest, LpvSunWindowHoldsTheFluxOfThePlaneInsideIt) {
    const float albedo = 0.5f, lux = 10.0f, half = 200.0f;
    Scene scene = bigPlane(albedo, half);
    Instance tile;
    tile.transform = glm::translate(glm::mat4(1.0f), glm::vec3(190.0f, 10.0f, 190.0f)) *
                     glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / half));
    scene.instances.push_back(tile);
    Camera c;
    c.position = {0.0f, 3.0f, 0.0f};
    c.forward = glm::normalize(glm::vec3(0.0f, -0.3f, -1.0f));
    scene.camera = c;
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    sun.intensity = lux;
    scene.lights.push_back(sun);

    gi::GiSettings s;
    s.technique = gi::Technique::Lpv;
    auto sys = test::systemWithScene(ctx(), s, scene);
    ASSERT_TRUE(sys) << sys.error().message;
    rg::RenderGraph graph;
    rg::Blackboard bb;
    auto out = (*sys)->addPasses(graph, bb, c, 8, 8);
    ASSERT_TRUE(out) << out.error().message;
    const gi::RsmData& rsm = bb.get<gi::RsmData>();
    ASSERT_EQ(rsm.layers.size(), 1u);
    const uint32_t n = rsm.resolution;
    auto texels = test::asArray<glm::vec4>(test::runAndReadImage(ctx(), graph, rsm.flux, VkDeviceSize(n) * n * 16));
    glm::dvec3 flux(0.0);
    for (const glm::vec4& t : texels)
        flux += glm::dvec3(t);

    // The RSM's view (RsmData carries the window's matrix): its four NDC corners, carried along
    // the sun to the plane, bound the parallelogram of plane it sees.
    const glm::mat4 inv = glm::inverse(rsm.layers[0].viewProj);
    glm::dvec3 p[4];
    for (int i = 0; i < 4; ++i) {
        glm::vec4 w = inv * glm::vec4((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, 0.5f, 1.0f);
        glm::vec3 q = glm::vec3(w) / w.w;
        p[i] = glm::dvec3(q - sun.direction * (q.y / sun.direction.y));
        ASSERT_LT(std::abs(p[i].x), half); // well inside the plane
        ASSERT_LT(std::abs(p[i].z), half);
    }
    const double area = std::abs(glm::cross(p[1] - p[0], p[2] - p[0]).y);
    const double side = glm::length(p[1] - p[0]) / double(n), cosSun = -sun.direction.y;
    const double expected = albedo * lux * area * cosSun;
    // Half a texel along the parallelogram's perimeter, as for the own layer above.
    const double perimeter = 2.0 * (glm::length(p[1] - p[0]) + glm::length(p[2] - p[0]));
    const double bound = perimeter * side / 2.0 / area;
    // The window holds the LPV's coarsest cascade.
    const std::vector<gpu::LpvGrid> cascades =
        gi::lpv::fitCascades(c.position, c.forward, s.lpv.cellSize, s.lpv.gridSize, 3);
    const gpu::LpvGrid& coarsest = cascades.back();
    const glm::vec3 lo = glm::vec3(coarsest.origin), hi = lo + coarsest.origin.w * glm::vec3(coarsest.size);
    for (int i = 0; i < 8; ++i) {
        glm::vec3 corner((i & 1) ? hi.x : lo.x, std::clamp((i & 2) ? hi.y : lo.y, 0.0f, 10.0f), (i & 4) ? hi.z : lo.z);
        glm::vec4 clip = rsm.layers[0].viewProj * glm::vec4(corner, 1.0f);
        EXPECT_LE(std::abs(clip.x / clip.w), 1.0f) << i;
        EXPECT_LE(std::abs(clip.y / clip.w), 1.0f) << i;
    }
    std::printf("LPV sun window: %.0f m^2 of plane, RSM flux / expected = %.6f (bound %.4f)\n", area,
                flux.g / expected, bound);
    EXPECT_NEAR(flux.g / expected, 1.0, bound) << flux.g << " vs " << expected;
    // Without the window the own layer's RSM would hold the whole plane: 400^2 / area times more.
    EXPECT_LT(flux.g, 0.5 * albedo * lux * 4.0 * half * half * cosSun);
}
