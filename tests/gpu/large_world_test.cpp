// Issue #16, large scenes: the same interior placed in a world ~27x larger than it must render
// about as well. `hall_world` is the built-in hall on a 400 m ground plane among low buildings,
// seen from the same camera (its closed walls hide the world, so the two references agree). Each
// technique's error against its own scene's path-traced reference (all bounces) in the big
// world must stay within 15% of the hall's, at no more than 64 MiB of technique memory; and
// what the technique did before (a volume or a constant sized by the scene's bounds) must miss
// that bar, so the test fails without the feature. `atrium_world` is the sun-lit atrium in the
// same kind of world: its VPL indirect image (visibility and two bounces, the sun-lit defaults)
// is compared against the all-bounce reference's indirect part, the column.
#include <cmath>
#include <cstdio>
#include <string>

#include "vkgi/gi.hpp"
#include "vkgi/image_metrics.hpp"
#include "vkgi/reference.hpp"
#include "vkgi/vpl.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "voxel/scene_voxel_grid.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

constexpr uint32_t kSize = 64;
constexpr uint64_t kMaxTechniqueBytes = 64ull << 20;

struct Measured {
    double relMse = 0.0;         // composite against the all-bounce reference
    double relMseIndirect = 0.0; // composite - direct against the reference's paths of 2+ reflections
    uint64_t techniqueBytes = 0;
    // The composite at epsilon 1e-3 (weighs the dark regions), and the best constant ambient
    // term's errors at epsilon 0.01 and 1e-3 (issue #15's baseline).
    double relMseDark = 0.0, constant = 0.0, constantDark = 0.0;
};

class LargeWorld : public test::GpuTest {
protected:
    Measured measure(const std::string& name, const GiSettings& settings, uint32_t size = kSize) {
        Scene scene = test::builtinScene(name);
        auto ref = test::allBounceReference(scene, *scene.camera, size, size);
        EXPECT_TRUE(ref) << (ref ? "" : ref.error().message);
        FrameRequest request;
        request.direct = true;
        auto frame = test::renderOnce(ctx(), settings, scene, *scene.camera, size, size, request);
        EXPECT_TRUE(frame) << (frame ? "" : frame.error().message);
        if (!ref || !frame)
            return {};
        auto full = compareImages(frame->composite, ref->full);
        auto indirect = subtract(frame->composite, frame->direct);
        EXPECT_TRUE(full && indirect);
        if (!full || !indirect)
            return {};
        auto e = compareImages(*indirect, ref->indirect);
        EXPECT_TRUE(e) << (e ? "" : e.error().message);
        if (!e)
            return {};
        EXPECT_EQ(full->nonFinite + e->nonFinite, 0u) << name;
        Measured m{full->relMse, e->relMse, frame->persistentByOwner.technique};
        const std::vector<bool> surface = surfacePixels(frame->composite, ref->full);
        m.relMseDark = compareImages(frame->composite, ref->full, 0.001f)->relMse;
        m.constant = compareImages(bestAmbient(frame->direct, ref->full, surface), ref->full)->relMse;
        m.constantDark =
            compareImages(bestAmbient(frame->direct, ref->full, surface, 0.001f), ref->full, 0.001f)->relMse;
        return m;
    }

    // The technique's error in hall_world within 15% of the hall's; returns the two.
    std::pair<Measured, Measured> expectSameAsTheHall(const GiSettings& settings, const char* what) {
        Measured hall = measure("hall", settings);
        Measured world = measure("hall_world", settings);
        std::printf("[large world] %s: relMSE hall %.4f, hall_world %.4f (%.3fx); technique memory %.2f / %.2f MiB\n",
                    what, hall.relMse, world.relMse, world.relMse / hall.relMse, double(hall.techniqueBytes) / 1048576.0,
                    double(world.techniqueBytes) / 1048576.0);
        EXPECT_GT(hall.relMse, 0.0);
        EXPECT_LE(world.relMse, 1.15 * hall.relMse) << what;
        EXPECT_GE(world.relMse, hall.relMse / 1.15) << what;
        EXPECT_LE(world.techniqueBytes, kMaxTechniqueBytes) << what;
        return {hall, world};
    }
};

} // namespace

// LPV at its defaults: the hall keeps its fitted grid (1.1 m cells); in the 400 m world a grid
// fitted to the lit region would have 28 m cells, so the automatic setting switches to three
// camera-centred cascades of 1, 2 and 4 m cells.
TEST_F(LargeWorld, LpvCascadesKeepTheHallsErrorInA400mWorld) {
    GiSettings settings;
    settings.technique = Technique::Lpv;
    expectSameAsTheHall(settings, "lpv defaults");
    GiSettings fitted = settings;
    fitted.lpv.cascades = 1;
    Measured hall = measure("hall", fitted);
    Measured world = measure("hall_world", fitted);
    std::printf("[large world] lpv one fitted grid: relMSE hall %.4f, hall_world %.4f\n", hall.relMse, world.relMse);
    EXPECT_GT(world.relMse, 1.15 * hall.relMse) << "a grid fitted to the world's bounds fails the bar";
}

// LPV in the sun-lit atrium_world: cascades (the atrium alone keeps its fitted grid), which
// read the sun's RSM through a window fitted to their coarsest level; the sun's own layer spans
// the 400 m world, and its texels, 27x wider than in the atrium, put the light of the ground
// beside the walls into the cells inside (1.19x the atrium's error at 128^2 before the window).
// The indirect image against the all-bounce reference's, the bench's column.
TEST_F(LargeWorld, LpvSunWindowKeepsTheAtriumsErrorInA400mWorld) {
    GiSettings settings;
    settings.technique = Technique::Lpv;
    const Measured atrium = measure("atrium", settings);
    const Measured world = measure("atrium_world", settings);
    std::printf("[large world] lpv: indirect relMSE atrium %.4f, atrium_world %.4f (%.3fx); memory %.2f MiB\n",
                atrium.relMseIndirect, world.relMseIndirect, world.relMseIndirect / atrium.relMseIndirect,
                double(world.techniqueBytes) / 1048576.0);
    EXPECT_GT(atrium.relMseIndirect, 0.0);
    EXPECT_LE(world.relMseIndirect, 1.15 * atrium.relMseIndirect);
    EXPECT_LE(world.techniqueBytes, kMaxTechniqueBytes);
}

// LPV's multi-bounce reads the shared voxel grid too: in hall_world the rule centres it on the
// camera (the fitted one would have 6.3 m voxels), and the light the bounce reflects at its
// occupied voxels must still bring the composite closer to the all-bounce reference, and leave
// the world no worse than the hall. Measured at 64^2: hall 0.248 -> 0.232, hall_world (three
// camera-centred cascades) 0.233 -> 0.180; bounds with margin.
TEST_F(LargeWorld, LpvBouncesReadTheCameraCentredGrid) {
    GiSettings settings;
    settings.technique = Technique::Lpv;
    GiSettings bounces = settings;
    bounces.lpv.bounces = true;
    double withBounces[2] = {0.0, 0.0};
    int k = 0;
    for (const char* name : {"hall", "hall_world"}) {
        const Measured one = measure(name, settings);
        const Measured two = measure(name, bounces);
        std::printf("[large world] lpv in %s: relMSE %.4f without bounces, %.4f with\n", name, one.relMse, two.relMse);
        EXPECT_LT(two.relMse, 0.97 * one.relMse) << name;
        EXPECT_LE(two.techniqueBytes, kMaxTechniqueBytes) << name;
        withBounces[k++] = two.relMse;
    }
    EXPECT_LE(withBounces[1], 1.15 * withBounces[0]);
}

// VPL at its defaults: the lamp's VPLs land inside the hall in both scenes, and the 1/d^2 clamp
// follows each VPL's footprint. The visibility maps (a lamp-lit scene's default) read the hall's
// fitted grid (0.25 m voxels) and, in the world, the lamps' 32 m camera-centred grid (0.5 m
// voxels, 0.25 m halves): measured hall 0.1585, hall_world 0.1588 (1.002x), 29 MiB each; the
// 64 m grid's 0.5 m halves gave the world about 1.5x the hall's indirect error (docs/vpl.md). A clamp set as a fraction of the scene's diagonal grows 27x in
// the world (from 0.4 m to 11 m at the former 2%), which the second half checks would fail.
TEST_F(LargeWorld, VplKeepsTheHallsErrorInA400mWorld) {
    GiSettings settings;
    settings.technique = Technique::Vpl;
    auto [hall, world] = expectSameAsTheHall(settings, "vpl defaults");
    (void)world;
    // Near the former clamp's radius in the world: 16 footprint radii of the hall's floor VPLs
    // (256 VPLs over 4 pi sr at 4.5 m: r = 4.5 sqrt(4 pi / 256 / pi) = 0.56 m), 9 m.
    GiSettings former = settings;
    former.vpl.clampDistance = 16.0f;
    Measured formerWorld = measure("hall_world", former);
    std::printf("[large world] vpl with the former clamp's radius in the world: relMSE %.4f\n", formerWorld.relMse);
    EXPECT_TRUE(formerWorld.relMse > 1.15 * hall.relMse || formerWorld.relMse < hall.relMse / 1.15);
}

namespace {

struct VctMeasured : Measured {
    uint32_t levels = 0; // clipmap levels the automatic choice made (1 = the fitted grid)
};

class LargeWorldVct : public LargeWorld {
protected:
    VctMeasured measureVct(const std::string& name, const VctSettings& vct = {}, uint32_t size = kSize) {
        GiSettings settings;
        settings.technique = Technique::Vct;
        settings.vct = vct;
        VctMeasured m;
        static_cast<Measured&>(m) = measure(name, settings, size);
        Scene scene = test::builtinScene(name);
        m.levels = resolveVctLevels(settings.vct, scene.bounds(), *scene.camera).levels;
        std::printf("[large world] vct, %s at %u^2: %u level(s), relMSE %.4f (best constant %.4f), at eps 1e-3 "
                    "%.4f (%.4f), indirect relMSE %.4f, technique memory %.2f MiB\n",
                    name.c_str(), size, m.levels, m.relMse, m.constant, m.relMseDark, m.constantDark,
                    m.relMseIndirect, double(m.techniqueBytes) / 1048576.0);
        return m;
    }
    // Issue #15's bar on every scene: the full image beats the best constant ambient term at
    // epsilon 0.01 and 1e-3.
    static void expectBeatsTheBestConstant(const Measured& m) {
        EXPECT_LT(m.relMse, m.constant);
        EXPECT_LT(m.relMseDark, m.constantDark);
    }
};

} // namespace

// VCT at its defaults: the hall keeps its fitted 64^3 grid (0.25 m voxels); in the 400 m world
// the automatic choice is the camera-centred clipmap (4 levels of 32^3, 0.5 to 4 m). The
// clipmap's second bounce gathers on into the coarser levels beyond each level's box, and each
// sample's level follows the footprint the level cap lets it read (docs/vct.md "Clipmap"):
// with both, hall_world measured relMSE 0.1925 and indirect 0.2980 against the hall's 0.1710 and
// 0.2642 (1.13x), and 0.2246 / 0.3661 (1.31x, 1.39x) without them. The rotated cone sets that
// followed (docs/vct.md "Rotated cone sets") lowered the fitted hall's error more than the
// clipmap's (hall 0.1680 / 0.2419, hall_world 0.1967 / 0.2962: 1.17x, 1.22x). With the finest
// level spanning 16 m instead of 8 (docs/vct.md "Clipmap", where the error comes from):
// hall_world 0.1922 / 0.2909, 1.14x and 1.20x. With the clipmap's pre-filtered opacity
// (docs/vct.md "Pre-filtered opacity", the clipmap's default) hall_world measures 0.1777 / 0.2635
// against the hall's 0.1680 / 0.2419: 1.06x and 1.09x, within issue #16's 15% on both (1.14x and
// 1.20x with vct.prefilter off). With the voxel light's march through the pre-filtered fill
// (docs/vct.md "Pre-filtered opacity") hall_world measures 0.1593 / 0.2319: 0.95x and 0.96x the
// hall's. With the shadow map's visibility for the voxel light (docs/vct.md "Visibility") the
// hall measures 0.1570 / 0.2239 and hall_world 0.1351 / 0.1905 (0.86x, 0.85x): the coarse levels
// gain most from it. With surfaces on voxel faces setting only the voxels behind them
// (docs/vct.md "Voxelization"; a clipmap's world-aligned lattice meets the hall's floor and
// walls), hall_world measures 0.1422 / 0.2025 against the hall's 0.1571 / 0.2240 (0.91x,
// 0.90x); with the levels centred ahead of the camera (docs/vct.md "Clipmap") 0.1354 / 0.1903
// (0.86x, 0.85x); with world voxels centred on the lattice 0.1195 / 0.1609 (0.76x, 0.72x); with
// refined pixels tracing both turned cone sets 0.1180 / 0.1575 against the hall's 0.1494 /
// 0.2141 (0.79x, 0.74x); with the skipped segments tested (docs/vct.md "The skipped segment")
// 0.1183 / 0.1608 against 0.1470 / 0.2119 (0.80x, 0.76x). The bar is the upper one;
// under 64 MiB.
TEST_F(LargeWorldVct, ClipmapKeepsTheHallsErrorInA400mWorld) {
    VctMeasured hall = measureVct("hall");
    VctMeasured world = measureVct("hall_world");
    EXPECT_EQ(hall.levels, 1u);
    EXPECT_EQ(world.levels, kVctAutoLevels);
    EXPECT_GT(hall.relMse, 0.0);
    EXPECT_LE(world.relMse, 1.15 * hall.relMse);
    EXPECT_LE(world.relMseIndirect, 1.15 * hall.relMseIndirect);
    EXPECT_LE(world.techniqueBytes, kMaxTechniqueBytes);
    expectBeatsTheBestConstant(hall);
    expectBeatsTheBestConstant(world);
}

// The atrium in the 400 m world: the indirect error within the 15% of the fitted atrium's,
// under 64 MiB. History (each change against its parent): 1.86x before the second bounce across
// levels, 1.70x with the 16 m finest level, 1.58x with a second bounce per side of a thin wall's
// voxel, 1.53x with the shadow map's visibility, 1.43x with surfaces on voxel faces setting the
// voxels behind them, 1.30x with the levels ahead of the camera, 1.21x with world voxels centred
// on the lattice, 1.11x (0.1176 against 0.1056) with refined pixels tracing both turned cone sets
// (1.27x at 128^2 in the bench), 1.08x (0.1043 against 0.0963) with the skipped segments tested
// (docs/vct.md "The skipped segment"). The bar holds at 128^2 as well: 1.10x (0.0952 against
// 0.0868), where without the test it measures 1.30x (0.1252 against 0.0963). What the test
// fixed: the cones of the piers' pixels behind the banners (0.3 m in front of them) started
// beyond the banners and read the sunlit courtyard; at 128^2 about 14 such pixels made half of
// the world's excess.
// Both scenes of each pair also beat the best constant at epsilon 0.01 and 1e-3 (issue #15):
// atrium_world 0.2539 against the constant's 0.2920 at both; its composite is dominated by a few
// pixels of the sun's shadow edge on the floor.
// The world itself adds no error: the atrium alone with the clipmap the world gets (forced: 4
// levels of 32^3 from 0.5 m) is the best that clipmap can do there, and the world is within the
// issue's 15% of it (measured 0.1043 against 0.1243, 0.84x). What remains between the world and
// the fitted atrium is the fitted grid's voxel size, 0.454 m, and where its blocks fall: a
// clipmap level on the fitted grid's voxels and blocks gives the fitted image, and the same level
// moved by one voxel along x 1.44x its error (docs/vct.md "Known limits", "Coarse levels in the
// world").
TEST_F(LargeWorldVct, ClipmapKeepsTheAtriumsIndirectErrorInA400mWorld) {
    VctMeasured atrium = measureVct("atrium");
    VctMeasured world = measureVct("atrium_world");
    VctSettings sameClipmap;
    sameClipmap.levels = kVctAutoLevels;
    sameClipmap.gridResolution = kVctAutoLevelResolution;
    VctMeasured atriumClipmap = measureVct("atrium", sameClipmap);
    EXPECT_EQ(atriumClipmap.levels, kVctAutoLevels);
    EXPECT_LE(world.relMseIndirect, 1.15 * atriumClipmap.relMseIndirect);
    EXPECT_EQ(atrium.levels, 1u);
    EXPECT_EQ(world.levels, kVctAutoLevels);
    EXPECT_GT(atrium.relMseIndirect, 0.0);
    EXPECT_LE(world.relMseIndirect, 1.15 * atrium.relMseIndirect) << "the issue's bar";
    // At 128^2 too, where more of the piers' pixels behind the banners show.
    VctMeasured atrium128 = measureVct("atrium", {}, 128);
    VctMeasured world128 = measureVct("atrium_world", {}, 128);
    EXPECT_LE(world128.relMseIndirect, 1.15 * atrium128.relMseIndirect) << "the issue's bar at 128^2";
    EXPECT_LE(world.techniqueBytes, kMaxTechniqueBytes);
    expectBeatsTheBestConstant(atrium);
    expectBeatsTheBestConstant(world);
}

// VPL at its defaults in the sun-lit atrium: visibility and two bounces through the shared voxel
// grid. The atrium keeps its fitted grid (0.45 m voxels); fitted to atrium_world's 400 m bounds
// the grid's voxels would be 6.3 m, which close the courtyard and stop nearly all VPL light (the
// indirect image is then about black: the fitted grid misses the 15% bar by far), so the
// automatic rule centres a 64 m grid of 1 m voxels on the camera instead, whose visibility march
// and bounce rays run on half voxels (the voxelizer's 2x2x2 bits per voxel; docs/vpl.md,
// "Visibility"). Two causes kept the world from the atrium's error; this test checks both:
// - the grid: the atrium alone with the same camera-centred grid (forced) is the best a 64^3 grid
//   of 64 m can do. With whole 1 m voxels it measured 0.376 against 0.242 with the atrium's
//   0.45 m fitted voxels (1.55x: conservative 1 m voxels half close the 2.4 m arcade openings);
//   with the half voxels 0.285 (1.18x);
// - the sun's VPLs: in the 400 m window the ring lattices around the camera (vpl.focus) put
//   fewer of them in the courtyard than the atrium's own window does, and where the lattices
//   fall decides much of the rest (vpl.candidates 0: 0.327, 1.35x the atrium). Drawn from 8x as
//   many candidates by their light on the frame (vpl.candidates, the default), they land where
//   the camera sees.
// Measured at 64^2: atrium 0.2417, atrium with the camera grid 0.2852, atrium_world 0.2430
// (1.005x the atrium, 0.85x the atrium with the same grid), its lattice points alone 0.3270,
// fitted in the world 0.861. Bounds: the camera grid within 1.3x the fitted one on the atrium
// (whole voxels fail it); the world within the 15% of the atrium and no worse than the
// atrium with the same grid, where the lattice points alone miss the 15%; below 0.5x the fitted
// grid's error, which itself stays beyond the bar.
TEST_F(LargeWorld, VplVisibilityKeepsTheAtriumsErrorInA400mWorld) {
    const Scene atriumWorld = test::builtinScene("atrium_world");
    EXPECT_TRUE(sharedGridFollowsCamera(atriumWorld.bounds(), 64, atriumWorld.cameraOrDefault().position));
    const Scene atriumScene = test::builtinScene("atrium");
    EXPECT_FALSE(sharedGridFollowsCamera(atriumScene.bounds(), 64, atriumScene.cameraOrDefault().position));
    GiSettings settings;
    settings.technique = Technique::Vpl;
    GiSettings camera = settings, fitted = settings, lattice = settings;
    camera.vpl.visibilityPlacement = VplGridPlacement::Camera;
    fitted.vpl.visibilityPlacement = VplGridPlacement::Fitted;
    lattice.vpl.candidates = 0;
    const Measured atrium = measure("atrium", settings);
    const Measured atriumCamera = measure("atrium", camera);
    const Measured world = measure("atrium_world", settings);
    const Measured worldLattice = measure("atrium_world", lattice);
    const Measured worldFitted = measure("atrium_world", fitted);
    std::printf("[large world] vpl defaults, indirect against all bounces: relMSE atrium %.4f, atrium with the "
                "camera grid %.4f, atrium_world %.4f (%.3fx the atrium, %.3fx with the same grid), lattice points "
                "alone %.4f, fitted to the world %.4f; technique memory %.2f / %.2f MiB\n",
                atrium.relMseIndirect, atriumCamera.relMseIndirect, world.relMseIndirect, world.relMseIndirect / atrium.relMseIndirect,
                world.relMseIndirect / atriumCamera.relMseIndirect, worldLattice.relMseIndirect, worldFitted.relMseIndirect,
                double(atrium.techniqueBytes) / 1048576.0, double(world.techniqueBytes) / 1048576.0);
    EXPECT_GT(atrium.relMseIndirect, 0.0);
    EXPECT_LE(atriumCamera.relMseIndirect, 1.3 * atrium.relMseIndirect) << "the half voxels see the arcades";
    EXPECT_LE(world.relMseIndirect, 1.15 * atrium.relMseIndirect) << "the issue's bar";
    EXPECT_LE(world.relMseIndirect, atriumCamera.relMseIndirect);
    EXPECT_GT(worldLattice.relMseIndirect, 1.15 * atrium.relMseIndirect) << "the lattice points alone miss the bar";
    EXPECT_LT(world.relMseIndirect, 0.5 * worldFitted.relMseIndirect);
    EXPECT_GT(worldFitted.relMseIndirect, 1.15 * atrium.relMseIndirect) << "a grid fitted to the world's bounds fails the bar";
    EXPECT_LE(world.techniqueBytes, kMaxTechniqueBytes);
    EXPECT_EQ(world.techniqueBytes, atrium.techniqueBytes) << "the same 64^3 grid, placed elsewhere";
}

// The camera-centred grid moves in quarter-grid steps (16 m at 64^3): a camera moved across a
// step re-voxelizes only the slabs the grid newly covers and keeps the rest, in world voxels, so
// the moved system's VPL image equals a fresh system's at the new camera (the occupancy, albedo
// and faces of a voxel do not depend on where the grid's corner is); a move within a step
// voxelizes nothing.
TEST_F(LargeWorld, VplCameraGridMovesInStepsLikeAFreshGrid) {
    const Scene scene = test::builtinScene("atrium_world");
    GiSettings settings;
    settings.technique = Technique::Vpl;
    Camera camera = scene.cameraOrDefault();
    FrameRequest request;
    request.indirect = true;
    auto system = test::systemWithScene(ctx(), settings, scene);
    ASSERT_TRUE(system.ok()) << system.error().message;
    auto ran = [](const FrameResult& f, const std::string& prefix) {
        for (const rg::PassTiming& p : f.passes)
            if (p.name.rfind(prefix, 0) == 0)
                return true;
        return false;
    };
    auto first = (*system)->renderFrame(camera, kSize, kSize, request);
    ASSERT_TRUE(first.ok()) << first.error().message;
    EXPECT_TRUE(ran(*first, "gi.voxel.voxelize"));
    // Within the step (the camera at z = -12.5 m snaps to the centre -16 m until it passes -8 m).
    camera.position.z += 1.0f;
    auto still = (*system)->renderFrame(camera, kSize, kSize, request);
    ASSERT_TRUE(still.ok()) << still.error().message;
    EXPECT_FALSE(ran(*still, "gi.voxel.")) << "a move within a step voxelizes nothing";
    // Across a step: the centre snaps to 0 m.
    camera.position.z += 6.0f;
    auto moved = (*system)->renderFrame(camera, kSize, kSize, request);
    ASSERT_TRUE(moved.ok()) << moved.error().message;
    EXPECT_TRUE(ran(*moved, "gi.voxel.voxelize.slab")) << "only the newly covered slab is voxelized";
    auto fresh = test::renderOnce(ctx(), settings, scene, camera, kSize, kSize, request);
    ASSERT_TRUE(fresh.ok()) << fresh.error().message;
    auto e = compareImages(moved->indirect, fresh->indirect);
    ASSERT_TRUE(e.ok());
    std::printf("[large world] vpl grid moved a step: indirect relMSE against a fresh system %.3g\n", e->relMse);
    EXPECT_LT(e->relMse, 1e-6);
}
