// Shadow windows (planShadows' `shadowWindows`, docs/direct.md "Windows"): the depth-only atlas
// layers of a sun fitted to boxes a technique names, rendered by addLightPasses. No technique
// names windows yet, so the test plans them itself and renders them through the light passes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "vkgi/frame_data.hpp"
#include "vkgi/gi.hpp"
#include "direct/direct_passes.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/gpu_util.hpp"
#include "support/test_scenes.hpp"

using namespace vkgi;

namespace {

using test::box;

class ShadowWindow : public test::GpuTest {
protected:
    struct Frame {
        gi::ShadowLayout layout;
        std::vector<float> atlas;                // every layer, row after row
        std::vector<gpu::GpuLightShadow> lights; // the table the shaders read
    };
    // Plans the atlas of `scene` with `windows` (no cascades, no RSM) and renders it through
    // addLightPasses into shadow targets of the test's own, in a frame of `sys`.
    Frame render(gi::GiSystem& sys, const Scene& scene, uint32_t n, const std::vector<Aabb>& windows) {
        Frame out;
        auto pipelines = gi::createDirectPipelines(ctx());
        EXPECT_TRUE(pipelines) << (pipelines ? "" : pipelines.error().message);
        if (!pipelines)
            return out;
        gi::ShadowTargets targets;
        for (int pass = 0; pass < 2; ++pass) { // the atlas, then the light table
            rg::RenderGraph graph;
            rg::Blackboard bb;
            auto frame = sys.addPasses(graph, bb, scene.cameraOrDefault(), 8, 8);
            EXPECT_TRUE(frame) << (frame ? "" : frame.error().message);
            if (!frame)
                break;
            const gi::FrameData& f = bb.get<gi::FrameData>();
            out.layout = gi::planShadows(scene, f.gpuScene->bounds, n, 64, {}, {}, windows);
            const uint32_t layers = uint32_t(out.layout.views.size());
            gi::ensureShadowTargets(ctx(), targets, layers, out.layout.lightLayers(), n, false);
            rg::Blackboard mine;
            gi::addLightPasses(graph, mine, *pipelines, f, bb.get<gi::SceneHandles>(), out.layout, targets, false);
            const gi::ShadowData& shadow = mine.get<gi::ShadowData>();
            if (pass == 0)
                out.atlas = test::asArray<float>(
                    test::runAndReadImage(ctx(), graph, shadow.atlas, VkDeviceSize(n) * n * layers * sizeof(float)));
            else
                out.lights = test::asArray<gpu::GpuLightShadow>(test::runAndReadBuffer(
                    ctx(), graph, shadow.lightShadows, scene.lights.size() * sizeof(gpu::GpuLightShadow)));
        }
        gi::destroyShadowTargets(ctx(), targets);
        gi::destroyDirectPipelines(ctx(), *pipelines);
        return out;
    }
};

} // namespace

// A sun over a 400 m plane at y = 0 and a 2 x 2 m tile at y = 6 above two window boxes (16 and
// 64 m wide, 4 m high): outside the boxes, between them and the sun. Each window layer's texel
// (i, j) must store the orthographic depth of the first surface on its ray: the line through
// the texel centre at depths 0 and 1 (the layer's inverse matrix) meets the tile or the plane,
// and the stored depth is that intersection's parameter (or 1, the cleared depth, where the
// plane lies beyond the box's far side). The texels are 0.09 and 0.35 m against the own layer's
// 2.2 m; the own layer is bitwise the same with and without the windows, and
// GpuLightShadow::cascades holds (0, 0, first window layer, 2).
TEST_F(ShadowWindow, WindowLayersStoreTheFirstSurfaceTowardTheSun) {
    const float half = 200.0f, tileY = 6.0f;
    Scene scene = test::plane(0.5f, half);
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    sun.intensity = 10.0f;
    scene.lights.push_back(sun);
    // The tile's shadow falls on the windows' centre: its centre is on the ray from the origin
    // toward the sun.
    const glm::vec3 tile = -sun.direction * (tileY / -sun.direction.y);
    Instance occluder;
    occluder.transform = glm::translate(glm::mat4(1.0f), tile) * glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / half));
    scene.instances.push_back(occluder);
    const std::vector<Aabb> windows = {box({-8, -1, -8}, {8, 3, 8}), box({-32, -1, -32}, {32, 3, 32})};

    auto sys = test::systemWithScene(ctx(), gi::GiSettings{}, scene);
    ASSERT_TRUE(sys) << sys.error().message;
    const uint32_t n = 256;
    const Frame plain = render(**sys, scene, n, {});
    const Frame windowed = render(**sys, scene, n, windows);
    ASSERT_EQ(plain.layout.views.size(), 1u);
    ASSERT_EQ(windowed.layout.views.size(), 3u);
    const gi::LightShadowPlan& plan = windowed.layout.lights[0];
    ASSERT_EQ(plan.windowFirst, 1u);
    ASSERT_EQ(plan.windowCount, 2u);
    ASSERT_EQ(windowed.atlas.size(), size_t(n) * n * 3);
    ASSERT_EQ(plain.atlas.size(), size_t(n) * n);
    EXPECT_TRUE(std::equal(plain.atlas.begin(), plain.atlas.end(), windowed.atlas.begin()))
        << "the own layer does not depend on the windows";
    ASSERT_EQ(windowed.lights.size(), 1u);
    EXPECT_EQ(windowed.lights[0].info, glm::uvec4(0u, 1u, GI_SHADOW_SINGLE, 0u));
    EXPECT_EQ(windowed.lights[0].cascades, glm::uvec4(0u, 0u, 1u, 2u));
    EXPECT_EQ(plain.lights[0].cascades, glm::uvec4(0u));

    for (uint32_t k = 0; k < 2; ++k) {
        const gpu::GpuShadowView& v = windowed.layout.views[plan.windowFirst + k];
        const glm::dmat4 inv = glm::inverse(glm::dmat4(v.viewProj));
        const double texel = v.texel.x;
        const float* layer = windowed.atlas.data() + size_t(plan.windowFirst + k) * n * n;
        double maxError = 0.0;
        int tileTexels = 0, planeTexels = 0, skipped = 0;
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const glm::dvec2 ndc = (glm::dvec2(i, j) + 0.5) / double(n) * 2.0 - 1.0;
                const glm::dvec4 a = inv * glm::dvec4(ndc, 0.0, 1.0), b = inv * glm::dvec4(ndc, 1.0, 1.0);
                const glm::dvec3 p0 = glm::dvec3(a) / a.w, p1 = glm::dvec3(b) / b.w;
                const double tPlane = -p0.y / (p1.y - p0.y), tTile = (tileY - p0.y) / (p1.y - p0.y);
                const glm::dvec3 hit = p0 + tTile * (p1 - p0);
                // Distance of the ray's tile-plane point inside the tile's edge (negative outside);
                // texel centres within a twentieth of a texel of the edge may fall either way in
                // the rasteriser's float arithmetic: skipped.
                const double inside =
                    1.0 - std::max(std::abs(hit.x - double(tile.x)), std::abs(hit.z - double(tile.z)));
                if (std::abs(inside) < 0.05 * texel) {
                    ++skipped;
                    continue;
                }
                // Beyond the box's far side (the plane under the square's corners, outside the
                // box) nothing is stored: the cleared depth 1, behind every receiver of the box.
                const double expected = std::min(inside > 0.0 ? tTile : tPlane, 1.0);
                (inside > 0.0 ? tileTexels : planeTexels)++;
                const double error = std::abs(double(layer[size_t(j) * n + i]) - expected);
                maxError = std::max(maxError, error);
                // A few float ulps at depth 1 (1.2e-7 each; 1.6e-7 measured): the vertices' clip z
                // and the rasteriser's interpolation are float.
                ASSERT_LT(error, 1e-6) << "window " << k << " texel " << i << ", " << j << ": stored "
                                       << layer[size_t(j) * n + i] << ", expected " << expected;
            }
        std::printf("window %u: texel %.4f m (own layer %.3f m), depth range %.1f m, %d tile and %d plane texels "
                    "(%d at the tile's edge skipped), max |stored - expected| %.2e\n",
                    k, v.texel.x, windowed.layout.views[0].texel.x, v.texel.y, tileTexels, planeTexels, skipped,
                    maxError);
        EXPECT_LT(v.texel.x, 0.2f * windowed.layout.views[0].texel.x);
        // The tile covers 4 m^2 x cos(sun) of the layer's texels: the caster above the box is in it.
        EXPECT_GT(tileTexels, 0.8 * 4.0 * -sun.direction.y / (texel * texel));
        EXPECT_GT(planeTexels, 1000);
    }
}
