// Pass selection (gi/src/pass_selection.hpp): the exact compiled pass list and the resources it uses
// for every built-in scene and technique, the reasons of what is left out, and dirty tracking:
// a static frame reuses the persistent volumes and gives the same image bit for bit, a moved
// light or object re-runs exactly what depends on it.
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/gi.hpp"
#include "lpv/lpv_grid.hpp"
#include "pass_selection.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/image_stats.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

// Small sizes: the listings only compile graphs; the executed tests render 64^2 frames.
GiSettings smallSettings(Technique technique) {
    GiSettings s;
    s.technique = technique;
    s.shadowMapSize = 64;
    s.vct.gridResolution = 16;
    s.lpv.gridSize = 16;
    s.lpv.iterations = 4;
    s.vpl.vplCount = 16;
    return s;
}

std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names)
        out += (out.empty() ? "" : " ") + n;
    return out;
}

std::vector<std::string> names(const std::vector<rg::PassTiming>& passes) {
    std::vector<std::string> out;
    for (const rg::PassTiming& p : passes)
        out.push_back(p.name);
    return out;
}

// "name=reason" of every left-out entry, in order.
std::string leftOut(const std::vector<LeftOutPass>& passes) {
    std::vector<std::string> out;
    for (const LeftOutPass& p : passes)
        out.push_back(p.name + "=" + toString(p.reason));
    return join(out);
}

// The passes whose results do not depend on the camera (shadow maps, voxels and their light, LPV
// volumes), in order: what dirty tracking decides. The per-pixel passes run every frame.
std::string viewIndependent(const FrameResult& frame) {
    std::vector<std::string> out;
    for (const rg::PassTiming& p : frame.passes)
        for (const char* prefix : {"gi.light[", "gi.voxel.", "gi.vct.list", "gi.vct.light", "gi.vct.mip[",
                                   "gi.vct.bounce", "gi.lpv.inject", "gi.lpv.gv.", "gi.lpv.propagate"})
            if (p.name.rfind(prefix, 0) == 0) {
                out.push_back(p.name);
                break;
            }
    return join(out);
}

bool ran(const FrameResult& frame, const std::string& prefix) {
    for (const rg::PassTiming& p : frame.passes)
        if (p.name.rfind(prefix, 0) == 0)
            return true;
    return false;
}

bool sameImage(const HdrImage& a, const HdrImage& b) {
    return a.width == b.width && a.height == b.height && a.pixels == b.pixels;
}

// One compiled (not executed) first frame: pass list, transients, persistent imports, left out.
struct Listing {
    std::string passes, transients, persistent, leftOut;
};

// Expected first-frame listings per "scene/technique" (composite requested, 32x32).
struct Expected {
    const char* key;
    Listing listing;
};

#include "pass_selection_expected.inc"

class PassSelectionTest : public test::GpuTest {
protected:
    std::unique_ptr<GiSystem> system(const GiSettings& settings, const Scene& scene) {
        auto s = test::systemWithScene(ctx(), settings, scene);
        EXPECT_TRUE(s) << (s ? "" : s.error().message);
        return s ? std::move(*s) : nullptr;
    }

    Listing list(GiSystem& system, const Scene& scene) {
        rg::RenderGraph graph;
        rg::Blackboard bb;
        auto out = system.addPasses(graph, bb, scene.cameraOrDefault(), 32, 32, {});
        EXPECT_TRUE(out) << (out ? "" : out.error().message);
        auto ok = graph.compile();
        EXPECT_TRUE(ok) << (ok ? "" : ok.error().message);
        std::vector<LeftOutPass> left = bb.get<gi::PassSelection>().leftOut;
        for (const std::string& c : graph.culledPassNames())
            left.push_back({c, LeftOutReason::Culled, ""});
        return {join(graph.orderedPassNames()), join(graph.usedResourceNames(false)),
                join(graph.usedResourceNames(true)), leftOut(left)};
    }

    FrameResult frame(GiSystem& system, const Scene& scene, FrameRequest request = {}) {
        auto f = system.renderFrame(scene.cameraOrDefault(), 64, 64, request);
        EXPECT_TRUE(f) << (f ? "" : f.error().message);
        return f ? std::move(*f) : FrameResult{};
    }
};

const std::vector<std::pair<Technique, const char*>> kTechniques = {
    {Technique::None, "none"}, {Technique::Vct, "vct"}, {Technique::Lpv, "lpv"}, {Technique::Vpl, "vpl"}};

} // namespace

TEST(SceneAnalysis, FeaturesOfTheBuiltinScenes) {
    // scene: directional, point, spot lights; emissive, metallic, dynamic
    std::map<std::string, std::string> expected = {
        {"cornell", "0 0 1 000"},   {"cornell_point", "0 1 0 000"}, {"cornell_spot", "0 0 1 000"},
        {"cornell_emissive", "0 0 0 100"}, {"furnace", "0 0 0 100"}, {"sphere", "0 1 0 000"},
        {"room", "1 0 0 000"},      {"bunny_box", "0 0 1 000"},     {"atrium", "1 0 0 000"},
        {"hall", "0 1 0 000"},      {"hall_world", "0 1 0 000"},    {"atrium_world", "1 0 0 000"},
    };
    for (const std::string& name : builtinSceneNames()) {
        auto scene = makeBuiltinScene(name);
        ASSERT_TRUE(scene) << scene.error().message;
        SceneFeatures f = analyzeScene(*scene);
        char got[32];
        std::snprintf(got, sizeof(got), "%u %u %u %d%d%d", f.directionalLights, f.pointLights, f.spotLights,
                      int(f.emissive), int(f.metallic), int(f.dynamicObjects));
        ASSERT_TRUE(expected.count(name)) << "new built-in scene " << name << ": add its features here";
        EXPECT_EQ(got, expected[name]) << name;
    }
}

TEST(SceneAnalysis, DiffMarksExactlyWhatChanged) {
    auto scene = makeBuiltinScene("cornell");
    ASSERT_TRUE(scene);
    Scene moved = *scene;
    EXPECT_FALSE(diffScenes(*scene, moved).any()) << "no edit, no change";
    moved.lights[0].position.x += 0.1f;
    SceneChanges c = diffScenes(*scene, moved);
    EXPECT_EQ(c.lights, std::vector<uint32_t>{0});
    EXPECT_FALSE(c.geometry());
    moved = *scene;
    moved.instances[1].transform[3].y += 0.1f;
    c = diffScenes(*scene, moved);
    EXPECT_TRUE(c.staticGeometry);
    EXPECT_FALSE(c.dynamicGeometry);
    EXPECT_FALSE(c.anyLight());
    c.merge(diffScenes(moved, *scene));
    EXPECT_TRUE(c.staticGeometry);
    moved = *scene;
    moved.instances.pop_back();
    EXPECT_TRUE(diffScenes(*scene, moved).all) << "a different instance count is not an edit";
}

TEST_F(PassSelectionTest, FirstFrameOfEveryBuiltinSceneAndTechnique) {
    // VKGI_PRINT_LISTINGS=1 prints the table in the format of pass_selection_expected.inc.
    bool print = std::getenv("VKGI_PRINT_LISTINGS") != nullptr;
    std::map<std::string, Listing> expected;
    for (const Expected& e : kExpected)
        expected[e.key] = e.listing;
    for (const auto& [technique, techniqueName] : kTechniques) {
        for (const std::string& sceneName : builtinSceneNames()) {
            auto scene = makeBuiltinScene(sceneName);
            ASSERT_TRUE(scene) << scene.error().message;
            auto sys = system(smallSettings(technique), *scene);
            ASSERT_TRUE(sys);
            Listing got = list(*sys, *scene);
            std::string key = sceneName + "/" + techniqueName;
            if (print) {
                std::printf("    {\"%s\",\n     {\"%s\",\n      \"%s\",\n      \"%s\",\n      \"%s\"}},\n", key.c_str(),
                            got.passes.c_str(), got.transients.c_str(), got.persistent.c_str(), got.leftOut.c_str());
                continue;
            }
            ASSERT_TRUE(expected.count(key)) << key << ": no expected listing";
            const Listing& want = expected[key];
            EXPECT_EQ(got.passes, want.passes) << key;
            EXPECT_EQ(got.transients, want.transients) << key;
            EXPECT_EQ(got.persistent, want.persistent) << key;
            EXPECT_EQ(got.leftOut, want.leftOut) << key;
        }
    }
}

TEST_F(PassSelectionTest, TechniqueNoneAllocatesNoTechniqueVolume) {
    auto scene = makeBuiltinScene("cornell");
    ASSERT_TRUE(scene);
    auto none = system(smallSettings(Technique::None), *scene);
    ASSERT_TRUE(none);
    FrameResult f = frame(*none, *scene);
    EXPECT_EQ(join(f.persistentResources), "gi.shadow.atlas");
    for (const std::string& r : f.transientResources)
        EXPECT_TRUE(r.rfind("gi.voxel", 0) != 0 && r.rfind("gi.lpv", 0) != 0 && r.rfind("gi.vct", 0) != 0) << r;
    // The same scene with VCT holds more: exactly the technique's volumes.
    auto vct = system(smallSettings(Technique::Vct), *scene);
    ASSERT_TRUE(vct);
    FrameResult v = frame(*vct, *scene);
    EXPECT_GT(v.persistentBytes, f.persistentBytes);
}

TEST_F(PassSelectionTest, DirectOnlyRequestAddsNoTechniquePass) {
    auto scene = makeBuiltinScene("cornell");
    ASSERT_TRUE(scene);
    auto sys = system(smallSettings(Technique::Vct), *scene);
    ASSERT_TRUE(sys);
    FrameRequest direct;
    direct.composite = false;
    direct.direct = true;
    FrameResult f = frame(*sys, *scene, direct);
    EXPECT_EQ(join(names(f.passes)), "gi.gbuffer gi.shadow.setup gi.light[0].spot gi.direct gi.readback.direct");
    // No indirect image, so no composite pass either: the direct image is the frame.
    EXPECT_EQ(leftOut(f.leftOut), "gi.light[*].directional=not-needed gi.light[*].point=not-needed "
                                  "gi.vct.*=not-needed");
    EXPECT_EQ(join(f.persistentResources), "gi.shadow.atlas");
    // The voxels were never made: the first frame that wants indirect light voxelizes.
    FrameResult g = frame(*sys, *scene);
    EXPECT_TRUE(ran(g, "gi.voxel.voxelize"));
    EXPECT_TRUE(ran(g, "gi.vct.light"));
}

TEST_F(PassSelectionTest, VctStaticFrameSkipsVoxelWorkAndMatchesTheRecomputedImage) {
    auto scene = makeBuiltinScene("cornell");
    ASSERT_TRUE(scene);
    auto sys = system(smallSettings(Technique::Vct), *scene);
    ASSERT_TRUE(sys);
    FrameRequest request;
    request.indirect = true;
    FrameResult first = frame(*sys, *scene, request);
    FrameResult second = frame(*sys, *scene, request);
    EXPECT_EQ(viewIndependent(second), "");
    EXPECT_TRUE(ran(second, "gi.vct.trace"));
    EXPECT_EQ(leftOut(second.leftOut),
              "gi.light[*].directional=not-needed gi.light[*].point=not-needed gi.light[0].spot=not-dirty "
              "gi.voxel.*=not-dirty gi.vct.light=not-dirty gi.vct.mip[*]=not-dirty gi.vct.bounce*=not-dirty "
              "gi.vct.trace:glossy-cone=not-needed gi.vct.trace:glossy-image=not-needed");
    EXPECT_GT(test::sumRgb(second.indirect), 0.0);
    EXPECT_TRUE(sameImage(first.composite, second.composite));
    EXPECT_TRUE(sameImage(first.indirect, second.indirect));
    sys->invalidate();
    FrameResult recomputed = frame(*sys, *scene, request);
    EXPECT_TRUE(ran(recomputed, "gi.voxel.voxelize"));
    EXPECT_TRUE(ran(recomputed, "gi.vct.bounce"));
    EXPECT_TRUE(ran(recomputed, "gi.light[0].spot"));
    EXPECT_TRUE(sameImage(recomputed.composite, second.composite)) << "the skipped frame equals the recomputed one";
    EXPECT_TRUE(sameImage(recomputed.indirect, second.indirect));
}

TEST_F(PassSelectionTest, VctMovedLightRelightsWithoutRevoxelizing) {
    auto base = makeBuiltinScene("cornell");
    ASSERT_TRUE(base);
    // A second light, so that "only the moved light's shadow map" is visible.
    Scene scene = *base;
    Light point;
    point.type = LightType::Point;
    point.position = glm::vec3(0.2f, 1.2f, 0.1f);
    point.intensity = 0.5f;
    scene.lights.push_back(point);
    auto sys = system(smallSettings(Technique::Vct), scene);
    ASSERT_TRUE(sys);
    frame(*sys, scene);
    Scene moved = scene;
    moved.lights[1].position.x -= 0.3f;
    ASSERT_TRUE(sys->updateScene(moved));
    FrameResult f = frame(*sys, moved);
    EXPECT_EQ(viewIndependent(f), "gi.light[1].point gi.vct.light gi.vct.bounce.jobs.clear gi.vct.mip[1] "
                                  "gi.vct.mip[2-4] gi.vct.bounce.blocks gi.vct.bounce.misfits "
                                  "gi.vct.bounce gi.vct.bounce.mip[1] gi.vct.bounce.mip[2-4]");
    EXPECT_EQ(leftOut(f.leftOut), "gi.light[*].directional=not-needed gi.light[0].spot=not-dirty "
                                  "gi.voxel.*=not-dirty gi.vct.light:emission=not-needed "
                                  "gi.vct.trace:glossy-cone=not-needed gi.vct.trace:glossy-image=not-needed");
    // The edited system's frame equals a fresh system's first frame of the moved scene.
    auto fresh = system(smallSettings(Technique::Vct), moved);
    ASSERT_TRUE(fresh);
    FrameResult g = frame(*fresh, moved);
    EXPECT_TRUE(sameImage(f.composite, g.composite));
}

TEST_F(PassSelectionTest, VctMovedDynamicObjectRevoxelizesOnlyItself) {
    auto base = makeBuiltinScene("cornell");
    ASSERT_TRUE(base);
    Scene scene = *base;
    uint32_t box = uint32_t(scene.instances.size() - 1);
    scene.instances[box].dynamic = true;
    auto sys = system(smallSettings(Technique::Vct), scene);
    ASSERT_TRUE(sys);
    FrameResult first = frame(*sys, scene);
    EXPECT_TRUE(ran(first, "gi.voxel.voxelize.static")) << "the static objects are baked once";
    EXPECT_TRUE(ran(first, "gi.voxel.voxelize.dynamic"));
    Scene moved = scene;
    moved.instances[box].transform[3].x += 0.05f;
    ASSERT_TRUE(sys->updateScene(moved));
    FrameResult f = frame(*sys, moved);
    EXPECT_FALSE(ran(f, "gi.voxel.voxelize.static"));
    EXPECT_TRUE(ran(f, "gi.voxel.voxelize.dynamic"));
    EXPECT_TRUE(ran(f, "gi.voxel.merge"));
    EXPECT_TRUE(ran(f, "gi.vct.light"));
    EXPECT_TRUE(ran(f, "gi.light[0].spot")) << "shadow maps see every object";
    auto fresh = system(smallSettings(Technique::Vct), moved);
    ASSERT_TRUE(fresh);
    EXPECT_TRUE(sameImage(f.composite, frame(*fresh, moved).composite));
}

TEST_F(PassSelectionTest, LpvStaticFrameRunsOnlyTheLookup) {
    auto scene = makeBuiltinScene("cornell");
    ASSERT_TRUE(scene);
    auto sys = system(smallSettings(Technique::Lpv), *scene);
    ASSERT_TRUE(sys);
    FrameRequest request;
    request.indirect = true;
    FrameResult first = frame(*sys, *scene, request);
    EXPECT_TRUE(ran(first, "gi.lpv.propagate"));
    FrameResult second = frame(*sys, *scene, request);
    EXPECT_EQ(join(names(second.passes)), "gi.gbuffer gi.shadow.setup gi.direct gi.lpv.lookup gi.composite "
                                          "gi.readback.composite gi.readback.indirect");
    EXPECT_EQ(viewIndependent(second), "");
    // Only injection reads the RSM: the kept volume, its channel sum (the damping's input) and its
    // injection header are all the lookup needs.
    EXPECT_EQ(join(second.persistentResources), "gi.shadow.atlas gi.lpv.accumulation.r gi.lpv.accumulation.g "
                                                "gi.lpv.accumulation.b gi.lpv.accumulation.sum gi.lpv.injection");
    EXPECT_GT(test::sumRgb(second.indirect), 0.0);
    EXPECT_TRUE(sameImage(first.indirect, second.indirect));
    EXPECT_TRUE(sameImage(first.composite, second.composite));
    sys->invalidate();
    FrameResult recomputed = frame(*sys, *scene, request);
    EXPECT_TRUE(ran(recomputed, "gi.lpv.inject"));
    EXPECT_TRUE(sameImage(recomputed.indirect, second.indirect));
}

// In atrium_world the LPV's cascades read the sun's RSM through a window fitted to their
// coarsest level (4 m cells). A repeated frame re-renders neither the light's own layer nor its
// window; a camera step that stays in the coarsest cell keeps them too, and one that moves it a
// cell re-renders the window (the own layer, whose view does not follow the camera, stays),
// with an image equal to a fresh system's there.
TEST_F(PassSelectionTest, LpvSunWindowRerendersOnlyWhenTheCoarsestCascadeMoves) {
    auto scene = makeBuiltinScene("atrium_world");
    ASSERT_TRUE(scene);
    GiSettings s = smallSettings(Technique::Lpv);
    auto sys = system(s, *scene);
    ASSERT_TRUE(sys);
    FrameRequest request;
    request.indirect = true;
    FrameResult first = frame(*sys, *scene, request);
    EXPECT_TRUE(ran(first, "gi.light[0].directional.rsm"));
    FrameResult second = frame(*sys, *scene, request);
    EXPECT_FALSE(ran(second, "gi.light[0].directional")) << join(names(second.passes));
    EXPECT_TRUE(sameImage(first.indirect, second.indirect));

    // The coarsest cascade's origin is snapped to 4 m: find a step that keeps it and one that
    // moves it (the cascades are centred ahead of the camera).
    const Camera start = scene->cameraOrDefault();
    auto coarsestOrigin = [&](const Camera& c) {
        return glm::vec3(lpv::fitCascades(c.position, glm::normalize(c.forward), s.lpv.cellSize, s.lpv.gridSize, 3)
                             .back()
                             .origin);
    };
    Camera within = start, across = start;
    within.position.x += 0.01f;
    across.position.x += 4.0f;
    ASSERT_EQ(coarsestOrigin(within), coarsestOrigin(start));
    ASSERT_NE(coarsestOrigin(across), coarsestOrigin(start));
    auto kept = sys->renderFrame(within, 64, 64, request);
    ASSERT_TRUE(kept) << kept.error().message;
    EXPECT_FALSE(ran(*kept, "gi.light[0].directional.rsm"));
    EXPECT_TRUE(ran(*kept, "gi.lpv.inject")) << "cascades re-inject every frame";
    auto moved = sys->renderFrame(across, 64, 64, request);
    ASSERT_TRUE(moved) << moved.error().message;
    EXPECT_TRUE(ran(*moved, "gi.light[0].directional.rsm"));
    EXPECT_TRUE(ran(*moved, "gi.light[0].directional.cascade"));
    auto fresh = system(s, *scene);
    ASSERT_TRUE(fresh);
    auto again = fresh->renderFrame(across, 64, 64, request);
    ASSERT_TRUE(again) << again.error().message;
    EXPECT_TRUE(sameImage(moved->indirect, again->indirect));
}

TEST_F(PassSelectionTest, LpvCameraMoveRerunsOnlyWithTheViewDependentGeometryVolume) {
    auto scene = makeBuiltinScene("cornell");
    ASSERT_TRUE(scene);
    Camera moved = scene->cameraOrDefault();
    moved.position.x += 0.05f;
    for (bool occlusion : {true, false}) {
        GiSettings s = smallSettings(Technique::Lpv);
        s.lpv.occlusion = occlusion;
        auto sys = system(s, *scene);
        ASSERT_TRUE(sys);
        frame(*sys, *scene);
        auto f = sys->renderFrame(moved, 64, 64, {});
        ASSERT_TRUE(f) << f.error().message;
        EXPECT_EQ(ran(*f, "gi.lpv.propagate"), occlusion) << "occlusion " << occlusion;
        EXPECT_EQ(ran(*f, "gi.lpv.gv.camera"), occlusion);
        EXPECT_TRUE(ran(*f, "gi.lpv.lookup"));
        EXPECT_FALSE(ran(*f, "gi.light[0]")) << "the camera does not move shadow maps";
    }
}

TEST_F(PassSelectionTest, ModelledBouncesFollowTheBounceKnobs) {
    GiSettings s;
    EXPECT_EQ(modelledBounces(s), 1);
    s.technique = Technique::Vct;
    EXPECT_EQ(modelledBounces(s), 3);
    s.vct.bounces = 1;
    EXPECT_EQ(modelledBounces(s), 2);
    s.vct.bounces = 3; // the bench compares with 4 reflections
    EXPECT_EQ(modelledBounces(s), 4);
    s.technique = Technique::Lpv;
    EXPECT_EQ(modelledBounces(s), 2);
    s.lpv.bounces = true;
    EXPECT_EQ(modelledBounces(s), 3);
    s.technique = Technique::Vpl;
    EXPECT_EQ(modelledBounces(s), 2); // no scene, as with spotlights only: the paper's one generation
    auto lamp = makeBuiltinScene("cornell_point");
    ASSERT_TRUE(lamp);
    EXPECT_EQ(modelledBounces(s, &*lamp), 3); // a point light: the visibility maps and two generations
    s.vpl.visibility = VplVisibilityMode::Off;
    EXPECT_EQ(modelledBounces(s, &*lamp), 2);
}

TEST_F(PassSelectionTest, LpvMovedLightReinjectsAndMatchesAFreshSystem) {
    auto scene = makeBuiltinScene("cornell");
    ASSERT_TRUE(scene);
    auto sys = system(smallSettings(Technique::Lpv), *scene);
    ASSERT_TRUE(sys);
    frame(*sys, *scene);
    Scene moved = *scene;
    moved.lights[0].position.x += 0.1f;
    ASSERT_TRUE(sys->updateScene(moved));
    FrameResult f = frame(*sys, moved);
    EXPECT_EQ(viewIndependent(f), "gi.light[0].spot gi.lpv.inject.reduce gi.lpv.inject.clear gi.lpv.inject.range gi.lpv.inject "
                                  "gi.lpv.inject.resolve gi.lpv.gv.clear gi.lpv.gv.rsm gi.lpv.gv.camera "
                                  "gi.lpv.gv.resolve gi.lpv.propagate[0] gi.lpv.propagate[1] gi.lpv.propagate[2] "
                                  "gi.lpv.propagate[3]");
    auto fresh = system(smallSettings(Technique::Lpv), moved);
    ASSERT_TRUE(fresh);
    EXPECT_TRUE(sameImage(f.composite, frame(*fresh, moved).composite));
}

// The emissive box (lit by its ceiling quad alone): the emitter proxies' RSM is rendered in the
// first frame and not in a repeated one, which runs only the lookup; moving the quad moves the
// proxies (placed on the CPU when the scene changes), re-renders their RSM and gives a fresh
// system's image, different from the unmoved one.
TEST_F(PassSelectionTest, LpvEmitterProxiesFollowTheEmitterAndRerenderOnlyWhenItChanges) {
    auto scene = makeBuiltinScene("cornell_emissive");
    ASSERT_TRUE(scene);
    const uint32_t quad = uint32_t(scene->instances.size() - 1); // added last
    ASSERT_GT(scene->materials[scene->meshes[scene->instances[quad].mesh].material].emission.r, 0.0f);
    auto sys = system(smallSettings(Technique::Lpv), *scene);
    ASSERT_TRUE(sys);
    FrameRequest request;
    request.indirect = true;
    FrameResult first = frame(*sys, *scene, request);
    EXPECT_TRUE(ran(first, "gi.lpv.emitter.rsm"));
    EXPECT_TRUE(ran(first, "gi.lpv.inject.emitter"));
    EXPECT_FALSE(ran(first, "gi.light[")) << "no punctual light: no shadow-atlas RSM";
    FrameResult second = frame(*sys, *scene, request);
    EXPECT_EQ(join(names(second.passes)), "gi.gbuffer gi.shadow.setup gi.direct gi.lpv.lookup gi.composite "
                                          "gi.readback.composite gi.readback.indirect");
    EXPECT_GT(test::sumRgb(second.indirect), 0.0);
    EXPECT_TRUE(sameImage(first.indirect, second.indirect));
    Scene moved = *scene;
    moved.instances[quad].transform[3].x -= 0.15f;
    ASSERT_TRUE(sys->updateScene(moved));
    FrameResult f = frame(*sys, moved, request);
    EXPECT_TRUE(ran(f, "gi.lpv.emitter.rsm"));
    EXPECT_FALSE(sameImage(f.indirect, second.indirect));
    auto fresh = system(smallSettings(Technique::Lpv), moved);
    ASSERT_TRUE(fresh);
    EXPECT_TRUE(sameImage(f.indirect, frame(*fresh, moved, request).indirect));
}

TEST_F(PassSelectionTest, VplStaticFrameReusesTheShadowMapAndRsm) {
    auto scene = makeBuiltinScene("cornell_spot");
    ASSERT_TRUE(scene);
    auto sys = system(smallSettings(Technique::Vpl), *scene);
    ASSERT_TRUE(sys);
    FrameResult first = frame(*sys, *scene);
    FrameResult second = frame(*sys, *scene);
    EXPECT_EQ(viewIndependent(second), "") << "VPL gathers per pixel every frame; only the RSM is kept";
    EXPECT_TRUE(ran(second, "vpl.gather"));
    EXPECT_TRUE(sameImage(first.composite, second.composite));
}

// GiSystem::setSettings rebuilds only what a setting feeds, and every frame after a change equals
// a fresh system's first frame with the new settings.
TEST_F(PassSelectionTest, SettingsChangesRebuildOnlyWhatDependsOnThem) {
    auto scene = makeBuiltinScene("cornell");
    ASSERT_TRUE(scene);
    GiSettings settings = smallSettings(Technique::Vct);
    auto sys = system(settings, *scene);
    ASSERT_TRUE(sys);
    frame(*sys, *scene);
    auto expectFresh = [&](const FrameResult& f, const GiSettings& s, const char* what) {
        auto fresh = system(s, *scene);
        ASSERT_TRUE(fresh);
        EXPECT_TRUE(sameImage(f.composite, frame(*fresh, *scene).composite)) << what;
    };

    // The PCF radius: no shadow map or voxel work; the voxel light follows the new filter.
    settings.pcfRadius = 2;
    ASSERT_TRUE(sys->setSettings(settings));
    FrameResult pcf = frame(*sys, *scene);
    EXPECT_FALSE(ran(pcf, "gi.light[")) << viewIndependent(pcf);
    EXPECT_FALSE(ran(pcf, "gi.voxel.")) << viewIndependent(pcf);
    EXPECT_TRUE(ran(pcf, "gi.vct.light"));
    expectFresh(pcf, settings, "pcf radius");

    // A larger shadow map: the atlas is re-rendered and the voxels relit, not re-voxelized.
    settings.shadowMapSize = 128;
    ASSERT_TRUE(sys->setSettings(settings));
    FrameResult atlas = frame(*sys, *scene);
    EXPECT_TRUE(ran(atlas, "gi.light[0].spot"));
    EXPECT_FALSE(ran(atlas, "gi.voxel.")) << viewIndependent(atlas);
    expectFresh(atlas, settings, "shadow map size");

    // A VCT knob rebuilds the technique (new volumes: voxelized again), nothing else.
    settings.vct.diffuseAperture = 0.25f;
    ASSERT_TRUE(sys->setSettings(settings));
    FrameResult cones = frame(*sys, *scene);
    EXPECT_TRUE(ran(cones, "gi.voxel.voxelize"));
    EXPECT_FALSE(ran(cones, "gi.light[")) << viewIndependent(cones);
    expectFresh(cones, settings, "vct aperture");

    // Another technique's knob changes nothing of this one.
    settings.lpv.iterations = 5;
    ASSERT_TRUE(sys->setSettings(settings));
    EXPECT_EQ(viewIndependent(frame(*sys, *scene)), "");

    // Another technique.
    settings.technique = Technique::Lpv;
    ASSERT_TRUE(sys->setSettings(settings));
    FrameResult lpv = frame(*sys, *scene);
    EXPECT_TRUE(ran(lpv, "gi.lpv.propagate"));
    expectFresh(lpv, settings, "switch to lpv");

    // Wrong settings change nothing.
    GiSettings bad = settings;
    bad.vct.gridResolution = 100;
    bad.technique = Technique::Vct;
    auto rejected = sys->setSettings(bad);
    ASSERT_FALSE(rejected);
    EXPECT_NE(rejected.error().message.find("gridResolution"), std::string::npos) << rejected.error().message;
    EXPECT_EQ(sys->settings().technique, Technique::Lpv);
    EXPECT_EQ(viewIndependent(frame(*sys, *scene)), "");
}
