// The cascade planner of directional-light shadows (gi/src/direct/cascades.hpp): splits, fitting,
// texel snapping, and how planShadows spends the atlas's layers on them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "direct/cascades.hpp"
#include "direct/direct_passes.hpp"
#include "pass_selection.hpp"
#include "vkgi/gi.hpp"
#include "support/test_scenes.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

Camera camera(glm::vec3 position, glm::vec3 forward, float znear = 0.05f, float zfar = 100.0f) {
    Camera c;
    c.position = position;
    c.forward = glm::normalize(forward);
    c.yfov = 60.0f * 3.14159265f / 180.0f;
    c.znear = znear;
    c.zfar = zfar;
    return c;
}

using test::box;

const glm::vec3 kSun = glm::normalize(glm::vec3(0.35f, -1.0f, 0.5f));
const Aabb kWorld = box({-200.0f, -0.25f, -200.0f}, {200.0f, 9.6f, 200.0f});

// Texel coordinates (0..n) and clip depth of world point x in `view`.
glm::vec3 texelOf(const gpu::GpuShadowView& view, const glm::vec3& x) {
    glm::vec4 c = view.viewProj * glm::vec4(x, 1.0f);
    return glm::vec3((glm::vec2(c) / c.w * 0.5f + 0.5f) * view.texel.z, c.z / c.w);
}

// A scene with just the sun (planShadows reads only the lights).
Scene sunScene() {
    Scene scene;
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = kSun;
    sun.intensity = 1e4f;
    scene.lights = {sun};
    return scene;
}

} // namespace

TEST(ShadowCascades, SplitsIncreaseAndCoverTheRange) {
    for (uint32_t count : {1u, 2u, 4u, 8u})
        for (float lambda : {0.0f, 0.5f, 0.75f, 1.0f}) {
            std::vector<float> d = cascadeSplits(0.05f, 100.0f, count, lambda);
            ASSERT_EQ(d.size(), count + 1);
            EXPECT_EQ(d.front(), 0.05f);
            EXPECT_EQ(d.back(), 100.0f);
            for (uint32_t i = 0; i < count; ++i)
                EXPECT_LT(d[i], d[i + 1]) << count << " cascades, lambda " << lambda << ", split " << i;
        }
    // Lambda 1 is the logarithmic scheme: a constant ratio between consecutive splits.
    std::vector<float> logSplits = cascadeSplits(0.1f, 1000.0f, 4, 1.0f);
    for (uint32_t i = 0; i < 4; ++i)
        EXPECT_NEAR(logSplits[i + 1] / logSplits[i], 10.0f, 1e-3f);
}

TEST(ShadowCascades, SceneDepthRangeLimitsTheCameraRange) {
    CascadeFrustum f = cascadeFrustum(camera({0, 1.7f, -12.5f}, {0, 0, 1}), 1.0f);
    float near = 0, far = 0;
    ASSERT_TRUE(sceneDepthRange(f, box({-7, 0, -14}, {7, 9.6f, 14}), near, far));
    EXPECT_FLOAT_EQ(near, 0.05f);          // the camera is inside the bounds
    EXPECT_NEAR(far, 26.5f, 1e-4f);        // the far wall, not zfar = 100
    ASSERT_TRUE(sceneDepthRange(f, kWorld, near, far));
    EXPECT_FLOAT_EQ(far, 100.0f);          // zfar, not the world's far edge
    EXPECT_FALSE(sceneDepthRange(f, box({-1, 0, -30}, {1, 1, -20}), near, far)); // behind
}

TEST(ShadowCascades, EveryBoxHoldsItsSliceWithTheMargin) {
    const uint32_t n = 256;
    const float margin = 3.0f;
    for (glm::vec3 forward : {glm::vec3(0, 0.1f, 1), glm::vec3(1, -0.3f, 0.2f), glm::vec3(-0.4f, 0.9f, -0.1f)})
        for (float aspect : {1.0f, 16.0f / 9.0f}) {
            CascadeFrustum f = cascadeFrustum(camera({3, 1.7f, -12.5f}, forward), aspect);
            CascadeSet set = planCascades(f, kSun, kWorld, 4, n, margin);
            ASSERT_EQ(set.views.size(), 4u);
            for (uint32_t i = 0; i < 4; ++i) {
                for (const glm::vec3& corner : sliceCorners(f, set.splits[i], set.splits[i + 1])) {
                    glm::vec3 t = texelOf(set.views[i], corner);
                    EXPECT_GE(t.x, margin) << "cascade " << i;
                    EXPECT_GE(t.y, margin) << "cascade " << i;
                    EXPECT_LE(t.x, float(n) - margin) << "cascade " << i;
                    EXPECT_LE(t.y, float(n) - margin) << "cascade " << i;
                    // Corners inside the bounds are receivers: inside the depth range.
                    if (glm::all(glm::greaterThanEqual(corner, kWorld.min)) &&
                        glm::all(glm::lessThanEqual(corner, kWorld.max))) {
                        EXPECT_GE(t.z, 0.0f);
                        EXPECT_LE(t.z, 1.0f);
                    }
                }
                // Every caster in the bounds between the light and the slice is in the depth
                // range: the bounds' corner nearest the light maps to depth >= 0.
                for (const glm::vec3& corner : kWorld.corners())
                    EXPECT_GE(texelOf(set.views[i], corner).z, 0.0f);
            }
        }
}

TEST(ShadowCascades, TexelSizeDoesNotDependOnTheViewDirection) {
    CascadeSet a = planCascades(cascadeFrustum(camera({0, 2, 0}, {0, 0, 1}), 1.0f), kSun, kWorld, 4, 256, 3.0f);
    CascadeSet b = planCascades(cascadeFrustum(camera({5, 2, -3}, {1, -0.2f, 0.3f}), 1.0f), kSun, kWorld, 4, 256, 3.0f);
    ASSERT_EQ(a.views.size(), 4u);
    ASSERT_EQ(b.views.size(), 4u);
    for (uint32_t i = 0; i < 4; ++i) {
        EXPECT_FLOAT_EQ(a.views[i].texel.x, b.views[i].texel.x) << i;
        if (i > 0) {
            EXPECT_GT(a.views[i].texel.x, a.views[i - 1].texel.x) << "finest first";
        }
    }
}

// Moving the camera by a fraction of a texel: the cascade's translation stays on the texel
// lattice (a whole number of texels from the world origin), so the same world squares map to
// the same texels and static shadows do not shimmer; a small move keeps the matrix bit for bit.
TEST(ShadowCascades, SnappedTranslationStaysOnTheTexelLattice) {
    const uint32_t n = 256;
    const glm::vec3 start(3.0f, 1.7f, -12.5f), forward(0.1f, 0.2f, 1.0f);
    CascadeSet base = planCascades(cascadeFrustum(camera(start, forward), 1.0f), kSun, kWorld, 4, n, 3.0f);
    ASSERT_EQ(base.views.size(), 4u);
    int unchanged = 0;
    for (int step = 1; step <= 20; ++step) {
        glm::vec3 moved = start + glm::vec3(0.013f, 0.007f, -0.011f) * float(step);
        CascadeSet set = planCascades(cascadeFrustum(camera(moved, forward), 1.0f), kSun, kWorld, 4, n, 3.0f);
        for (uint32_t i = 0; i < 4; ++i) {
            const glm::mat4& m = set.views[i].viewProj;
            for (int axis = 0; axis < 2; ++axis) {
                float texels = m[3][axis] * float(n) * 0.5f; // clip units -> texels
                EXPECT_NEAR(texels, std::round(texels), 2e-3f) << "cascade " << i << " step " << step;
            }
            // Same texel size, same rotation: only the lattice offset may change.
            EXPECT_EQ(set.views[i].texel.x, base.views[i].texel.x);
            unchanged += m == base.views[i].viewProj;
        }
    }
    // The coarse cascades' texels are tens of centimetres: most of these moves stay inside one.
    EXPECT_GT(unchanged, 20);
}

// Four cascades with the deferred pass's default margin (3 texels) for a camera at
// (0, 1.7, -12.5) looking along `forward`.
CascadeRequest fourCascades(glm::vec3 forward) {
    CascadeRequest req;
    req.count = 4;
    req.camera = camera({0, 1.7f, -12.5f}, forward);
    req.marginTexels = 3.0f;
    return req;
}

// planShadows: the cascades finer than the whole-scene layer (the near slices' first), counted in
// maxShadowLayers after every light's own layer, never in the RSM's layers.
TEST(ShadowCascades, PlanShadowsSpendsLayersOnCascadesOnlyWhereTheyHelp) {
    Scene scene = sunScene();
    CascadeRequest req = fourCascades(glm::vec3(0, 3.5f, 6) - glm::vec3(0, 1.7f, -12.5f));

    ShadowLayout world = planShadows(scene, kWorld, 256, 64, req);
    ASSERT_EQ(world.lights.size(), 1u);
    EXPECT_EQ(world.lights[0].cascadeCount, 4u);
    EXPECT_EQ(world.lights[0].cascadeFirst, 1u);
    EXPECT_EQ(world.views.size(), 5u);
    EXPECT_EQ(world.lightLayers(), 1u); // the RSM has the light's own layer only
    for (uint32_t i = 1; i < 5; ++i)
        EXPECT_LT(world.views[i].texel.x, world.views[0].texel.x);

    // The courtyard alone: the camera sees most of it. Only the near slices' cascades are finer
    // than the whole-scene layer; they are kept and the far slices keep the whole-scene layer.
    const Aabb courtyard = box({-7.3f, -0.2f, -14.3f}, {7.3f, 9.6f, 14.3f});
    ShadowLayout small = planShadows(scene, courtyard, 256, 64, req);
    const uint32_t kept = small.lights[0].cascadeCount;
    EXPECT_GE(kept, 1u);
    EXPECT_LT(kept, 4u);
    EXPECT_EQ(small.lights[0].cascadeFirst, 1u);
    EXPECT_EQ(small.views.size(), 1u + kept);
    for (uint32_t i = 1; i <= kept; ++i)
        EXPECT_LT(small.views[i].texel.x, small.views[0].texel.x);
    CascadeSet all = planCascades(cascadeFrustum(req.camera, req.aspect), glm::normalize(kSun), courtyard, 4, 256,
                                  req.marginTexels);
    ASSERT_EQ(all.views.size(), 4u);
    EXPECT_GE(all.views[kept].texel.x, small.views[0].texel.x) << "the first slice left out is not finer";
    std::printf("courtyard: %u of 4 cascades finer than the whole-scene layer\n", kept);

    // No room for the cascades: the light keeps its own layer, shadowed as before.
    ShadowLayout tight = planShadows(scene, kWorld, 256, 4, req);
    EXPECT_EQ(tight.lights[0].kind, GI_SHADOW_SINGLE);
    EXPECT_EQ(tight.lights[0].cascadeCount, 0u);
    EXPECT_EQ(tight.views.size(), 1u);

    // Cascades off: exactly the layout without a camera.
    req.count = 0;
    ShadowLayout off = planShadows(scene, kWorld, 256, 64, req);
    ShadowLayout plain = planShadows(scene, kWorld, 256, 64);
    ASSERT_EQ(off.views.size(), 1u);
    EXPECT_EQ(off.views[0].viewProj, plain.views[0].viewProj);
}

// A sun's RSM window (what the LPV's cascades read): the RSM view covers the window with texels
// as much finer as the window is smaller, its depth range still spans everything between the
// window and the sun (a roof above the window, outside it, must occlude), and the own layer the
// shadow lookups read is the same as without a window. A window no finer than the own layer,
// or none, leaves the plan as it was.
TEST(ShadowCascades, SunRsmWindowIsFinerAndKeepsTheOccludersTowardTheSun) {
    Scene scene = sunScene();
    const Aabb window = box({-32.0f, -24.0f, -20.0f}, {32.0f, 40.0f, 44.0f}); // 16 cells of 4 m
    ShadowLayout plain = planShadows(scene, kWorld, 256, 64);
    ShadowLayout windowed = planShadows(scene, kWorld, 256, 64, {}, window);
    ASSERT_EQ(windowed.views.size(), 1u);
    EXPECT_EQ(windowed.views[0].viewProj, plain.views[0].viewProj);
    EXPECT_EQ(windowed.lightLayers(), 1u);
    const LightShadowPlan& plan = windowed.lights[0];
    ASSERT_TRUE(plan.rsmWindowed);
    EXPECT_FALSE(plain.lights[0].rsmWindowed);
    const gpu::GpuShadowView& w = plan.rsmView;
    // The window clipped to the world is 64 x 9.85 x 64 m against the world's 400 x 9.85 x 400 m:
    // its texels are about that ratio finer (0.16, up to the projection of the boxes' heights).
    const double ratio = double(w.texel.x) / double(plain.views[0].texel.x);
    std::printf("RSM window texel %.3f m, own layer %.3f m (%.3fx)\n", w.texel.x, plain.views[0].texel.x, ratio);
    EXPECT_LT(ratio, 0.25);
    EXPECT_GT(w.axisArea.w, 0.0f); // the texel's area in m^2, which sets the RSM's flux per texel
    EXPECT_LE(w.axisArea.w, w.texel.x * w.texel.x * 1.0001f);
    // Every corner of the clipped window lands inside the RSM; a point on the world's top face
    // straight toward the sun from the window's centre lies within the depth range (an occluder).
    Aabb clipped = window;
    clipped.min = glm::max(clipped.min, kWorld.min);
    clipped.max = glm::min(clipped.max, kWorld.max);
    for (const glm::vec3& c : clipped.corners()) {
        glm::vec3 t = texelOf(w, c);
        EXPECT_GE(t.x, 0.0f);
        EXPECT_LE(t.x, 256.0f);
        EXPECT_GE(t.y, 0.0f);
        EXPECT_LE(t.y, 256.0f);
        EXPECT_GE(t.z, 0.0f);
        EXPECT_LE(t.z, 1.0f);
    }
    for (const glm::vec3& corner : {kWorld.min, kWorld.max, glm::vec3(kWorld.min.x, kWorld.max.y, kWorld.max.z)}) {
        const float z = texelOf(w, corner).z;
        EXPECT_GE(z, 0.0f);
        EXPECT_LE(z, 1.0f);
    }
    // A window as large as the world is not finer: no extra pass.
    ShadowLayout whole = planShadows(scene, kWorld, 256, 64, {}, kWorld);
    EXPECT_FALSE(whole.lights[0].rsmWindowed);
    // Punctual lights never get a window.
    Light spot;
    spot.type = LightType::Spot;
    spot.position = {0, 5, 0};
    spot.direction = {0, -1, 0};
    scene.lights = {spot};
    EXPECT_FALSE(planShadows(scene, kWorld, 256, 64, {}, window).lights[0].rsmWindowed);
}

// VCT's clipmap levels around a camera at `centre` (finest first): cubes of 16, 32, 64, 128 m.
std::vector<Aabb> clipmapBoxes(glm::vec3 centre) {
    std::vector<Aabb> boxes;
    for (float side : {16.0f, 32.0f, 64.0f, 128.0f})
        boxes.push_back(box(centre - 0.5f * side, centre + 0.5f * side));
    return boxes;
}

Aabb clipped(const Aabb& b, const Aabb& bounds) {
    return box(glm::max(b.min, bounds.min), glm::min(b.max, bounds.max));
}

// The texel size of a window's layer in closed form: the square holding the box's projection
// along the sun (its larger side 2r in the light's frame) with (margin + 1) texels on each side,
// 2 h / n with h = r + (margin + 1) 2 h / n.
float expectedWindowTexel(const Aabb& b, const glm::vec3& sun, uint32_t n, float margin) {
    const glm::vec3 dir = glm::normalize(sun);
    const glm::vec3 up = std::abs(dir.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
    const glm::vec3 right = glm::normalize(glm::cross(dir, up)), v = glm::cross(right, dir);
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    for (const glm::vec3& c : b.corners()) {
        const float p[2] = {glm::dot(c, right), glm::dot(c, v)};
        for (int a = 0; a < 2; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    const float r = 0.5f * std::max(hi[0] - lo[0], hi[1] - lo[1]);
    return 2.0f * r / (float(n) - 2.0f * (margin + 1.0f));
}

// Shadow windows (TechniqueModule::shadowWindows, VCT's clipmap levels in atrium_world): one
// depth-only layer per box after all cascades (so neither the cascades nor the RSM's layers
// change), finest first, each holding its box clipped to the world with the margin, with the
// texel of the closed form, all finer than the sun's whole-scene layer.
TEST(ShadowCascades, ShadowWindowsFollowTheCascadesAndAreFinerThanTheOwnLayer) {
    Scene scene = sunScene();
    CascadeRequest req = fourCascades(glm::vec3(0, 3.5f, 6) - glm::vec3(0, 1.7f, -12.5f));
    const uint32_t n = 256;
    const std::vector<Aabb> windows = clipmapBoxes(req.camera.position);
    ShadowLayout without = planShadows(scene, kWorld, n, 64, req);
    ShadowLayout with = planShadows(scene, kWorld, n, 64, req, {}, windows);
    const LightShadowPlan& plan = with.lights[0];
    ASSERT_EQ(plan.cascadeCount, 4u);
    EXPECT_EQ(plan.windowFirst, 5u) << "after the light's own layer and its 4 cascades";
    ASSERT_EQ(plan.windowCount, 4u);
    ASSERT_EQ(with.views.size(), 9u);
    EXPECT_EQ(with.lightLayers(), 1u) << "the RSM has the light's own layer only";
    EXPECT_EQ(without.lights[0].windowCount, 0u);
    EXPECT_EQ(without.lights[0].windowFirst, 0u);
    ASSERT_EQ(without.views.size(), 5u);
    EXPECT_EQ(std::memcmp(with.views.data(), without.views.data(), 5 * sizeof(gpu::GpuShadowView)), 0)
        << "own layer and cascades as without windows";
    const float whole = with.views[0].texel.x;
    for (uint32_t k = 0; k < 4; ++k) {
        const gpu::GpuShadowView& v = with.views[plan.windowFirst + k];
        const Aabb b = clipped(windows[k], kWorld);
        const float expected = expectedWindowTexel(b, kSun, n, req.marginTexels);
        EXPECT_NEAR(v.texel.x / expected, 1.0f, 1e-5f) << "window " << k;
        EXPECT_LT(v.texel.x, whole) << "window " << k;
        if (k > 0) {
            EXPECT_GT(v.texel.x, with.views[plan.windowFirst + k - 1].texel.x) << "finest first";
        }
        EXPECT_FLOAT_EQ(v.axisArea.w, v.texel.x * v.texel.x);
        EXPECT_EQ(v.eye.w, 0.0f) << "orthographic";
        for (const glm::vec3& c : b.corners()) {
            glm::vec3 t = texelOf(v, c);
            EXPECT_GE(t.x, req.marginTexels) << "window " << k;
            EXPECT_GE(t.y, req.marginTexels) << "window " << k;
            EXPECT_LE(t.x, float(n) - req.marginTexels) << "window " << k;
            EXPECT_LE(t.y, float(n) - req.marginTexels) << "window " << k;
            EXPECT_GE(t.z, 0.0f);
            EXPECT_LE(t.z, 1.0f);
        }
        // 32 voxels per level: shadow texels per voxel side.
        const float voxel = (windows[k].max.x - windows[k].min.x) / 32.0f;
        std::printf("window %u (%.0f m): texel %.4f m = %.2f per %.2f m voxel; own layer %.3f m\n", k,
                    windows[k].max.x - windows[k].min.x, v.texel.x, voxel / v.texel.x, voxel, whole);
    }
}

// A window whose texels are not finer than the light's own layer is dropped, and every window
// after it (the technique's later boxes then read the own layer); so is a first window as large
// as the world, leaving the layout as without windows.
TEST(ShadowCascades, ShadowWindowNotFinerIsDroppedWithAllAfterIt) {
    Scene scene = sunScene();
    const Aabb small = box({-8, -1, -8}, {8, 7, 8});
    ShadowLayout layout = planShadows(scene, kWorld, 256, 64, {}, {}, {small, kWorld, small});
    EXPECT_EQ(layout.lights[0].windowFirst, 1u);
    EXPECT_EQ(layout.lights[0].windowCount, 1u);
    EXPECT_EQ(layout.views.size(), 2u);
    ShadowLayout none = planShadows(scene, kWorld, 256, 64, {}, {}, {kWorld, small});
    EXPECT_EQ(none.lights[0].windowCount, 0u);
    EXPECT_EQ(none.lights[0].windowFirst, 0u);
    EXPECT_EQ(none.views.size(), 1u);
    // A larger box than the world, clipped to it, is the world: not finer either.
    ShadowLayout larger = planShadows(scene, kWorld, 256, 64, {}, {}, {box(kWorld.min - 50.0f, kWorld.max + 50.0f)});
    EXPECT_EQ(larger.lights[0].windowCount, 0u);
}

// The window's depth range spans from the scene's point nearest the sun to the box's far side:
// a caster above the box (outside it, between it and the sun) lies inside the range at the box's
// texel, and so does every corner of the bounds toward the sun.
TEST(ShadowCascades, ShadowWindowDepthCoversTheCastersTowardTheSun) {
    Scene scene = sunScene();
    const Aabb low = box({-8, -1, -8}, {8, 3, 8});
    ShadowLayout layout = planShadows(scene, kWorld, 256, 64, {}, {}, {low});
    ASSERT_EQ(layout.lights[0].windowCount, 1u);
    const gpu::GpuShadowView& v = layout.views[layout.lights[0].windowFirst];
    const glm::vec3 dir = glm::normalize(kSun);
    const glm::vec3 top(0.0f, 3.0f, 0.0f), caster = top - 7.0f * dir;
    ASSERT_GT(caster.y, low.max.y);
    ASSERT_LT(caster.y, kWorld.max.y); // a point of the scene outside the box
    const glm::vec3 tTop = texelOf(v, top), tCaster = texelOf(v, caster);
    EXPECT_NEAR(tCaster.x, tTop.x, 1e-3f);
    EXPECT_NEAR(tCaster.y, tTop.y, 1e-3f);
    EXPECT_GE(tCaster.z, 0.0f);
    EXPECT_LT(tCaster.z, tTop.z) << "the caster is in front of the receiver";
    float nearest = 1e30f;
    for (const glm::vec3& c : kWorld.corners()) {
        const float z = texelOf(v, c).z;
        nearest = std::min(nearest, z);
        EXPECT_GE(z, 0.0f);
    }
    EXPECT_LT(nearest, 2e-3f) << "the range starts at the scene's point nearest the sun (plus the pad)";
    // It ends at the box's far side (clipped to the world): no depth is spent beyond it.
    float farthest = -1e30f;
    for (const glm::vec3& c : clipped(low, kWorld).corners())
        farthest = std::max(farthest, texelOf(v, c).z);
    EXPECT_LE(farthest, 1.0f);
    EXPECT_GT(farthest, 0.998f);
}

// Windows take the atlas's remaining layers one by one, light after light: each light keeps the
// leading windows that fit into maxShadowLayers after every light's own layers and cascades.
// Point and spot lights get none.
TEST(ShadowCascades, ShadowWindowsRespectMaxLayersAndSkipPunctualLights) {
    Scene scene = sunScene();
    CascadeRequest req = fourCascades({0, 0.1f, 1});
    const std::vector<Aabb> windows = clipmapBoxes(req.camera.position);
    ShadowLayout seven = planShadows(scene, kWorld, 256, 7, req, {}, windows);
    EXPECT_EQ(seven.lights[0].cascadeCount, 4u);
    EXPECT_EQ(seven.lights[0].windowFirst, 5u);
    EXPECT_EQ(seven.lights[0].windowCount, 2u);
    EXPECT_EQ(seven.views.size(), 7u);
    ShadowLayout five = planShadows(scene, kWorld, 256, 5, req, {}, windows);
    EXPECT_EQ(five.lights[0].windowCount, 0u);
    EXPECT_EQ(five.lights[0].windowFirst, 0u);
    EXPECT_EQ(five.views.size(), 5u);

    Light spot;
    spot.type = LightType::Spot;
    spot.position = {0, 5, 0};
    spot.direction = {0, -1, 0};
    spot.outerConeAngle = 0.5f;
    Light point;
    point.type = LightType::Point;
    point.position = {2, 3, 1};
    Light sun2 = scene.lights[0];
    sun2.direction = glm::normalize(glm::vec3(-0.5f, -1.0f, 0.1f));
    scene.lights = {spot, scene.lights[0], point, sun2};
    // Own layers 1 + 1 + 6 + 1, no cascades, then the first sun's 4 windows and 2 of the second's.
    ShadowLayout mixed = planShadows(scene, kWorld, 256, 15, {}, {}, windows);
    ASSERT_EQ(mixed.lights.size(), 4u);
    for (uint32_t i : {0u, 2u}) {
        EXPECT_EQ(mixed.lights[i].windowCount, 0u) << "light " << i;
        EXPECT_EQ(mixed.lights[i].windowFirst, 0u) << "light " << i;
    }
    EXPECT_EQ(mixed.lights[1].windowFirst, 9u);
    EXPECT_EQ(mixed.lights[1].windowCount, 4u);
    EXPECT_EQ(mixed.lights[3].windowFirst, 13u);
    EXPECT_EQ(mixed.lights[3].windowCount, 2u);
    EXPECT_EQ(mixed.views.size(), 15u);
    EXPECT_EQ(mixed.lightLayers(), 9u);
}

// A window's origin is on the light's texel lattice: the same box gives bitwise the same view
// (its pass is left out), a box moved by a voxel keeps the texel size and a translation of whole
// texels (static shadow edges stay on the same texels), and a moved window alone is re-rendered.
TEST(ShadowCascades, ShadowWindowSnapsToTheTexelLattice) {
    Scene scene = sunScene();
    const uint32_t n = 256;
    // Clipmap boxes lie on their voxel grid: their corners, and so their sizes, are exact.
    const glm::vec3 start(3.25f, 1.75f, -12.5f);
    ShadowLayout base = planShadows(scene, kWorld, n, 64, {}, {}, clipmapBoxes(start));
    ShadowLayout again = planShadows(scene, kWorld, n, 64, {}, {}, clipmapBoxes(start));
    ASSERT_EQ(base.lights[0].windowCount, 4u);
    ASSERT_EQ(base.views.size(), again.views.size());
    EXPECT_EQ(std::memcmp(base.views.data(), again.views.data(), base.views.size() * sizeof(gpu::GpuShadowView)), 0);
    for (int step = 1; step <= 8; ++step) {
        // Level 0 moves by its 0.5 m voxels, the others stay (as clipmap levels scroll).
        std::vector<Aabb> windows = clipmapBoxes(start);
        const glm::vec3 offset = glm::vec3(0.5f, 0.0f, -0.5f) * float(step);
        windows[0] = box(windows[0].min + offset, windows[0].max + offset);
        ShadowLayout moved = planShadows(scene, kWorld, n, 64, {}, {}, windows);
        ASSERT_EQ(moved.lights[0].windowCount, 4u);
        const gpu::GpuShadowView& v = moved.views[1];
        EXPECT_EQ(v.texel.x, base.views[1].texel.x) << "step " << step;
        for (int axis = 0; axis < 2; ++axis) {
            float texels = v.viewProj[3][axis] * float(n) * 0.5f; // clip units -> texels
            EXPECT_NEAR(texels, std::round(texels), 2e-3f) << "step " << step;
        }
        EXPECT_NE(v.viewProj, base.views[1].viewProj);
        SceneChanges none;
        none.reset();
        std::vector<uint32_t> clean = cleanShadowWindows(moved, base, none);
        EXPECT_EQ(clean[0], 0xEu) << "only window 0 moved, step " << step;
        SceneChanges light;
        light.reset();
        light.lights = {0};
        EXPECT_EQ(cleanShadowWindows(again, base, light)[0], 0u) << "a changed light re-renders every window";
    }
    SceneChanges none;
    none.reset();
    EXPECT_EQ(cleanShadowWindows(again, base, none)[0], 0xFu);
    EXPECT_EQ(windowPassName(0, 2), "gi.light[0].directional.window[2]");
}

TEST(ShadowCascades, SettingOutOfRangeIsAReadableError) {
    GiSettings s;
    s.shadowCascades = kMaxShadowCascades + 1;
    auto ok = validateSettings(s);
    ASSERT_FALSE(ok);
    EXPECT_NE(ok.error().message.find("shadowCascades 9 is outside 0..8"), std::string::npos) << ok.error().message;
    s.shadowCascades = 0;
    EXPECT_TRUE(validateSettings(s));
}

// Point and spot layers: the far plane is what the light reaches within the scene, clipped to its
// range; stored depth is distance / far, so it does not depend on the bounds beyond that.
TEST(ShadowCascades, PerspectiveFarPlaneIsClippedToTheLightsRange) {
    Scene scene;
    Light spot;
    spot.type = LightType::Spot;
    spot.position = {0.0f, 4.0f, 0.0f};
    spot.direction = {0.0f, -1.0f, 0.0f};
    spot.outerConeAngle = 0.5f;
    spot.intensity = 100.0f;
    scene.lights = {spot};
    ShadowLayout unlimited = planShadows(scene, kWorld, 256, 64);
    ASSERT_EQ(unlimited.views.size(), 1u);
    EXPECT_GT(unlimited.views[0].eye.w, 280.0f); // the world's farthest corner
    scene.lights[0].range = 12.0f;
    ShadowLayout ranged = planShadows(scene, kWorld, 256, 64);
    ASSERT_EQ(ranged.views.size(), 1u);
    EXPECT_NEAR(ranged.views[0].eye.w, 12.0f * 1.01f, 1e-3f);
    // The texel size per metre of distance is the cone's, whatever the far plane.
    EXPECT_EQ(ranged.views[0].texel.x, unlimited.views[0].texel.x);
}
