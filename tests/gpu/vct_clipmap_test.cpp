// The VCT clipmap (VctSettings::levels > 1, docs/vct.md "Clipmap"): error on a large world
// against the same view of the small scene, update of exactly the levels whose origin moved
// (equal to a fresh system at the new camera), memory that does not grow with the scene, and
// settings validation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/gi.hpp"
#include "vkgi/image_metrics.hpp"
#include "vkgi/reference.hpp"
#include "vkgi/vct.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

// The clipmap as the tests and the docs use it: 4 levels of 32^3, finest voxel automatic
// (kVctAutoFinestSpan / 32), so levels span 16, 32, 64 and 128 m.
VctSettings clipmapSettings() {
    VctSettings s;
    s.levels = 4;
    s.gridResolution = 32;
    s.lowResFactor = 2; // 64^2 images: f = 4 would trace 16^2 pixels
    return s;
}

GiSettings vctSettings(const VctSettings& vct) {
    GiSettings s;
    s.technique = Technique::Vct;
    s.vct = vct;
    return s;
}

bool hasLeftOut(const FrameResult& f, const std::string& name) {
    return std::any_of(f.leftOut.begin(), f.leftOut.end(), [&](const LeftOutPass& p) { return p.name == name; });
}

bool ran(const FrameResult& f, const std::string& name) {
    return std::any_of(f.passes.begin(), f.passes.end(), [&](const rg::PassTiming& p) { return p.name == name; });
}

size_t differingPixels(const HdrImage& a, const HdrImage& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        n += a.pixels[i] != b.pixels[i] ? 1 : 0;
    return n;
}

// How far a moved system's indirect image is from a fresh system's at the same camera: relMSE
// (epsilon 0.01) and the largest difference of a pixel channel over the fresh image's mean.
struct Gap {
    double relMse = 0.0;
    double maxOverMean = 0.0;
};
Gap indirectGap(const FrameResult& moved, const FrameResult& fresh) {
    Gap g;
    auto metrics = compareImages(moved.indirect, fresh.indirect);
    EXPECT_TRUE(metrics.ok()) << metrics.error().message;
    if (!metrics.ok())
        return {1e30, 1e30};
    g.relMse = metrics->relMse;
    double mean = 0.0, largest = 0.0;
    for (size_t i = 0; i < fresh.indirect.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            mean += fresh.indirect.pixels[i][c];
            largest = std::max(largest, double(std::abs(moved.indirect.pixels[i][c] - fresh.indirect.pixels[i][c])));
        }
    mean /= 3.0 * double(fresh.indirect.pixels.size());
    g.maxOverMean = mean > 0.0 ? largest / mean : largest;
    std::printf("indirect against a fresh system: relMSE %.3g, max difference / mean %.3g\n", g.relMse,
                g.maxOverMean);
    return g;
}

// A moved level keeps the voxel light of the voxels both corners cover whose marches to the
// lights stay clear of what the move changed and lights the others (docs/vct.md "Clipmap"): with
// one bounce the image equals a fresh system's up to the rounding of a voxel centre's world
// position (0 measured on every move below). kExact* leave room for that rounding and still
// fail a level that keeps every covered voxel's light: the 6-voxel move of
// MovingTheCameraUpdatesTheMovedLevelsAndStaysNearAFreshSystem then measured relMSE 0.017 and a
// largest difference of 0.77 times the mean (with the second bounce gathered whole).
constexpr double kExactRelMse = 1e-6;
constexpr double kExactMaxOverMean = 1e-2;
// With two or three bounces the kept voxels also keep their bounce, gathered at the old corner,
// where a fresh system gathers it at the new one (other bounce blocks, other mip alignment, the
// level's new content). Measured on the moves below: relMSE up to 0.046, largest difference up
// to 0.98 times the mean (the 6-voxel move and the all-axes move); bounds with margin.
constexpr double kKeptBounceRelMse = 0.08;
constexpr double kKeptBounceMaxOverMean = 1.5;

// `camera` moved onto the centre of a 2-voxel block of the finest level (voxel edge `v0`), so
// that a one-voxel step always moves level 0.
Camera onBlockCentre(Camera camera, float v0) {
    camera.position = (2.0f * glm::round(camera.position / (2.0f * v0)) + 0.5f) * v0;
    return camera;
}

class VctClipmap : public test::GpuTest {
protected:
    // relMSE (epsilon 0.01) of the composite against the path tracer at 64^2, 256 spp, with the
    // bounce count of VCT.
    double relMse(const char* sceneName, const VctSettings& vct, uint64_t* techniqueBytes = nullptr) {
        Scene scene = test::builtinScene(sceneName);
        Camera camera = scene.cameraOrDefault();
        FrameRequest request;
        request.direct = true;
        auto frame = test::renderOnce(ctx(), vctSettings(vct), scene, camera, kSize, kSize, request);
        EXPECT_TRUE(frame.ok()) << frame.error().message;
        if (!frame.ok())
            return 0.0;
        if (techniqueBytes)
            *techniqueBytes = frame->persistentByOwner.technique;
        ReferenceSettings rs;
        rs.spp = 256;
        rs.maxBounces = int(vct.bounces) + 1;
        rs.progress = false;
        auto ref = renderReferenceCached(scene, camera, kSize, kSize, rs);
        EXPECT_TRUE(ref.ok()) << ref.error().message;
        if (!ref.ok())
            return 0.0;
        double e = compareImages(frame->composite, ref->full)->relMse;
        std::printf("%s levels %u grid %u: relMSE %.4f, technique memory %.1f MiB\n", sceneName, vct.levels,
                    vct.gridResolution, e, double(frame->persistentByOwner.technique) / (1024.0 * 1024.0));
        return e;
    }
    static constexpr uint32_t kSize = 64;
};

} // namespace

TEST(VctSettings, ClipmapValuesAreReadableErrors) {
    auto expectError = [](VctSettings s, const char* word) {
        auto r = validateVctSettings(s);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().message.find(word), std::string::npos) << r.error().message;
    };
    VctSettings s;
    s.levels = 0; // automatic
    EXPECT_TRUE(validateVctSettings(s).ok());
    s.levels = 9;
    expectError(s, "levels 9");
    s = {};
    s.voxel = -0.1f;
    expectError(s, "voxel");
    s.voxel = std::numeric_limits<float>::quiet_NaN();
    expectError(s, "voxel");
    s.voxel = std::numeric_limits<float>::infinity();
    expectError(s, "voxel");
    s = {};
    s.levels = 4;
    s.gridResolution = 256;
    expectError(s, "array layers");
    s = {};
    s.levels = 2;
    s.softShadows = true;
    expectError(s, "soft_shadows");
    s = clipmapSettings();
    EXPECT_TRUE(validateVctSettings(s).ok());
    s.voxel = 0.1f;
    EXPECT_TRUE(validateVctSettings(s).ok());
    EXPECT_FLOAT_EQ(vctFinestVoxel(s), 0.1f);
    s.voxel = 0.0f;
    EXPECT_FLOAT_EQ(vctFinestVoxel(s), kVctAutoFinestSpan / 32.0f);
}

// The hall on a 400 m ground plane among buildings, same view: the clipmap's error stays within
// 15% of its error on the hall alone, clearly below a single grid fitted to the world, and its
// memory does not depend on the scene's size.
TEST_F(VctClipmap, LargeWorldErrorMatchesTheSmallScene) {
    uint64_t hallBytes = 0, worldBytes = 0;
    const double hall = relMse("hall", clipmapSettings(), &hallBytes);
    const double world = relMse("hall_world", clipmapSettings(), &worldBytes);
    VctSettings fitted = clipmapSettings();
    fitted.levels = 1;
    fitted.gridResolution = 64;
    const double worldFitted = relMse("hall_world", fitted);
    EXPECT_LE(world, 1.15 * hall);
    EXPECT_LT(world, 0.7 * worldFitted);
    EXPECT_EQ(hallBytes, worldBytes);
    EXPECT_LE(worldBytes, 64ull << 20);
}

// A camera move of one finest voxel re-voxelizes and relights the finest level only; several
// voxels move more levels. Either way the image stays within the moved-level tolerance of a new
// system rendering at the new camera, and the levels whose origin stayed are left out as not dirty.
TEST_F(VctClipmap, MovingTheCameraUpdatesTheMovedLevelsAndStaysNearAFreshSystem) {
    Scene scene = test::builtinScene("hall");
    VctSettings vct = clipmapSettings();
    vct.levels = 3;
    GiSettings settings = vctSettings(vct);
    const float v0 = vctFinestVoxel(vct);
    Camera camera = scene.cameraOrDefault();
    // Half a voxel before a level-0 boundary (its origins move at odd multiples of the voxel,
    // every coarser level's at even ones): one voxel along x moves level 0 only.
    camera.position.x = (2.0f * std::round(camera.position.x / (2.0f * v0)) + 0.5f) * v0;
    FrameRequest request;
    request.indirect = true;
    auto system = test::systemWithScene(ctx(), settings, scene);
    ASSERT_TRUE(system.ok()) << system.error().message;
    auto first = (*system)->renderFrame(camera, kSize, kSize, request);
    ASSERT_TRUE(first.ok()) << first.error().message;
    EXPECT_TRUE(ran(*first, "gi.vct.light@2"));

    // Level l's corner moves when round(x / (2 v0 2^l)) does (clipCell in vct_technique.cpp).
    auto block = [&](float x, uint32_t l) { return std::floor(x / (2.0f * v0 * float(1u << l)) + 0.5f); };
    struct Move {
        float voxels;
        uint32_t movedLevels; // levels 0 .. movedLevels - 1 re-voxelized
    };
    for (Move move : {Move{1.0f, 1u}, Move{6.0f, 0u}}) {
        const float before = camera.position.x;
        camera.position.x += move.voxels * v0;
        uint32_t movedLevels = 0;
        while (movedLevels < vct.levels && block(before, movedLevels) != block(camera.position.x, movedLevels))
            ++movedLevels;
        if (move.movedLevels > 0) { // the one-voxel move is placed to move the finest level only
            EXPECT_EQ(movedLevels, move.movedLevels);
        }
        EXPECT_GE(movedLevels, 1u);
        move.movedLevels = movedLevels;
        auto moved = (*system)->renderFrame(camera, kSize, kSize, request);
        ASSERT_TRUE(moved.ok()) << moved.error().message;
        auto fresh = test::renderOnce(ctx(), settings, scene, camera, kSize, kSize, request);
        ASSERT_TRUE(fresh.ok()) << fresh.error().message;
        const Gap gap = indirectGap(*moved, *fresh);
        EXPECT_LE(gap.relMse, kKeptBounceRelMse) << move.voxels << " voxels";
        EXPECT_LE(gap.maxOverMean, kKeptBounceMaxOverMean) << move.voxels << " voxels";
        EXPECT_GT(differingPixels(moved->composite, first->composite), 0u);
        for (uint32_t l = 0; l < vct.levels; ++l) {
            const std::string at = "@" + std::to_string(l);
            const bool expectMoved = l < move.movedLevels;
            // A moved level of a static scene voxelizes only the slabs it newly covers.
            EXPECT_EQ(ran(*moved, "gi.voxel.voxelize" + at) || ran(*moved, "gi.voxel.voxelize.slab" + at), expectMoved)
                << move.voxels << " voxels, level " << l;
            EXPECT_EQ(ran(*moved, "gi.vct.light" + at), expectMoved) << move.voxels << " voxels, level " << l;
            EXPECT_EQ(ran(*moved, "gi.vct.shift" + at), expectMoved) << move.voxels << " voxels, level " << l;
            EXPECT_EQ(hasLeftOut(*moved, "gi.voxel.*" + at), !expectMoved) << move.voxels << " voxels, level " << l;
            EXPECT_EQ(hasLeftOut(*moved, "gi.vct.light" + at), !expectMoved) << move.voxels << " voxels, level " << l;
        }
    }
}

// A moved level keeps what its old and new boxes both cover and voxelizes only the slabs it newly
// covers ("gi.voxel.voxelize.slab", no full "gi.voxel.voxelize"), along one axis or several; it
// shifts its saved voxel light the same way ("gi.vct.shift") and lights only the new voxels. Each
// move stays within the moved-level tolerance of a new system rendering at the new camera, and a
// light change after the moves relights every level whole: then the image equals the new
// system's bit for bit (the shifted records of what each level stores are exact).
TEST_F(VctClipmap, MovedLevelsUpdateOnlyTheNewSlabsAndStayNearAFreshSystem) {
    for (uint32_t bounces : {1u, 2u, 3u}) {
        Scene scene = test::builtinScene("hall");
        VctSettings vct = clipmapSettings();
        vct.levels = 3;
        vct.bounces = bounces;
        GiSettings settings = vctSettings(vct);
        const double boundRelMse = bounces == 1 ? kExactRelMse : kKeptBounceRelMse;
        const double boundMax = bounces == 1 ? kExactMaxOverMean : kKeptBounceMaxOverMean;
        const float v0 = vctFinestVoxel(vct);
        Camera camera = onBlockCentre(scene.cameraOrDefault(), v0);
        FrameRequest request;
        request.indirect = true;
        auto system = test::systemWithScene(ctx(), settings, scene);
        ASSERT_TRUE(system.ok()) << system.error().message;
        ASSERT_TRUE((*system)->renderFrame(camera, kSize, kSize, request).ok());
        // Level l's corner (clipCell in vct_technique.cpp), in 2-voxel blocks of that level.
        auto corner = [&](glm::vec3 p, uint32_t l) { return glm::floor(p / (2.0f * v0 * float(1u << l)) + 0.5f); };
        // One finest voxel along x (level 0 moves 2 voxels), then back along x and z at once, then
        // 5 voxels along all three axes (coarser levels move too).
        for (glm::vec3 step :
             {glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(-2.0f, 0.0f, -2.0f), glm::vec3(5.0f, 5.0f, 5.0f)}) {
            const glm::vec3 before = camera.position;
            camera.position += step * v0;
            auto moved = (*system)->renderFrame(camera, kSize, kSize, request);
            ASSERT_TRUE(moved.ok()) << moved.error().message;
            EXPECT_NE(corner(before, 0), corner(camera.position, 0)) << "every step moves level 0";
            for (uint32_t l = 0; l < vct.levels; ++l) {
                const std::string at = "@" + std::to_string(l);
                const bool levelMoved = corner(before, l) != corner(camera.position, l);
                EXPECT_EQ(ran(*moved, "gi.voxel.voxelize.slab" + at), levelMoved)
                    << step.x << " " << step.y << " " << l;
                EXPECT_EQ(ran(*moved, "gi.voxel.mark" + at), levelMoved) << step.x << " " << step.y << " " << l;
                EXPECT_FALSE(ran(*moved, "gi.voxel.voxelize" + at)) << "level " << l << " re-voxelized whole";
                EXPECT_EQ(ran(*moved, "gi.vct.shift" + at), levelMoved) << step.x << " " << step.y << " " << l;
                EXPECT_FALSE(ran(*moved, "gi.vct.list.stale" + at)) << "level " << l;
            }
            auto fresh = test::renderOnce(ctx(), settings, scene, camera, kSize, kSize, request);
            ASSERT_TRUE(fresh.ok()) << fresh.error().message;
            const Gap gap = indirectGap(*moved, *fresh);
            EXPECT_LE(gap.relMse, boundRelMse) << bounces << " bounces, " << step.x << " " << step.y << " " << step.z;
            EXPECT_LE(gap.maxOverMean, boundMax) << bounces << " bounces, " << step.x << " " << step.y << " " << step.z;
        }
        scene.lights[0].intensity *= 1.5f;
        ASSERT_TRUE((*system)->updateScene(scene).ok());
        auto relit = (*system)->renderFrame(camera, kSize, kSize, request);
        ASSERT_TRUE(relit.ok()) << relit.error().message;
        for (uint32_t l = 0; l < vct.levels; ++l) {
            EXPECT_TRUE(ran(*relit, "gi.vct.light@" + std::to_string(l)));
            EXPECT_FALSE(ran(*relit, "gi.vct.shift@" + std::to_string(l)));
            // The third bounce gathers over this level's two-bounce radiance.
            EXPECT_EQ(ran(*relit, "gi.vct.clip.lit3@" + std::to_string(l)), bounces == 3);
            EXPECT_EQ(ran(*relit, "gi.vct.bounce3.blocks@" + std::to_string(l)), bounces == 3);
        }
        auto fresh = test::renderOnce(ctx(), settings, scene, camera, kSize, kSize, request);
        ASSERT_TRUE(fresh.ok()) << fresh.error().message;
        EXPECT_EQ(differingPixels(relit->composite, fresh->composite), 0u) << bounces << " bounces";
    }
}

// With a dynamic object the static bake is shifted the same way (its own touched list, the grid's
// volumes as scratch) and the dynamic draws are voxelized and merged as on every frame. A move
// alone keeps the kept voxels' light (within the moved-level tolerance of a fresh system); a
// move in the frame the object moves relights the levels whole, which then equal a fresh
// system bit for bit; the next move keeps light again.
TEST_F(VctClipmap, MovedLevelsWithADynamicObjectShiftTheStaticBakeAndStayNearAFreshSystem) {
    Scene scene = test::builtinScene("hall");
    scene.instances.back().dynamic = true;
    VctSettings vct = clipmapSettings();
    vct.levels = 2;
    GiSettings settings = vctSettings(vct);
    const float v0 = vctFinestVoxel(vct);
    Camera camera = onBlockCentre(scene.cameraOrDefault(), v0);
    FrameRequest request;
    request.indirect = true;
    auto system = test::systemWithScene(ctx(), settings, scene);
    ASSERT_TRUE(system.ok()) << system.error().message;
    ASSERT_TRUE((*system)->renderFrame(camera, kSize, kSize, request).ok());
    // The second step also moves the dynamic object.
    for (glm::vec3 step : {glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(-2.0f, 0.0f, -2.0f), glm::vec3(2.0f, 0.0f, 1.0f)}) {
        camera.position += step * v0;
        const bool objectMoved = step.x < 0.0f;
        if (objectMoved) {
            scene.instances.back().transform[3].x += 0.05f;
            ASSERT_TRUE((*system)->updateScene(scene).ok());
        }
        auto moved = (*system)->renderFrame(camera, kSize, kSize, request);
        ASSERT_TRUE(moved.ok()) << moved.error().message;
        EXPECT_TRUE(ran(*moved, "gi.voxel.voxelize.slab.static@0"));
        EXPECT_FALSE(ran(*moved, "gi.voxel.voxelize.static@0"));
        EXPECT_TRUE(ran(*moved, "gi.voxel.merge@0"));
        EXPECT_EQ(ran(*moved, "gi.vct.shift@0"), !objectMoved);
        auto fresh = test::renderOnce(ctx(), settings, scene, camera, kSize, kSize, request);
        ASSERT_TRUE(fresh.ok()) << fresh.error().message;
        if (objectMoved) {
            EXPECT_EQ(differingPixels(moved->composite, fresh->composite), 0u) << step.x << " " << step.z;
            continue;
        }
        const Gap gap = indirectGap(*moved, *fresh);
        EXPECT_LE(gap.relMse, kKeptBounceRelMse) << step.x << " " << step.z;
        EXPECT_LE(gap.maxOverMean, kKeptBounceMaxOverMean) << step.x << " " << step.z;
    }
}

// Prints (does not assert: timings are the bench's) the GPU time of a frame after a one-voxel
// camera move against a frame whose move re-voxelizes every level, medians of 5 each.
TEST_F(VctClipmap, OneVoxelMoveCostsLessThanAFullUpdate) {
    Scene scene = test::builtinScene("hall_world");
    VctSettings vct = clipmapSettings();
    GiSettings settings = vctSettings(vct);
    const float v0 = vctFinestVoxel(vct);
    Camera camera = scene.cameraOrDefault();
    camera.position.x = (2.0f * std::round(camera.position.x / (2.0f * v0)) + 0.5f) * v0;
    const glm::vec3 home = camera.position;
    auto system = test::systemWithScene(ctx(), settings, scene);
    ASSERT_TRUE(system.ok()) << system.error().message;
    FrameRequest request;
    ASSERT_TRUE((*system)->renderFrame(camera, kSize, kSize, request).ok()); // shaders compiled
    std::vector<double> full, oneVoxel;
    for (int i = 0; i < 5; ++i) {
        // Far enough that every level's corner moves, then back home, then one voxel on.
        camera.position = home + glm::vec3(0.0f, 0.0f, float(i % 2 == 0 ? 1 : -1) * 80.0f);
        ASSERT_TRUE((*system)->renderFrame(camera, kSize, kSize, request).ok());
        camera.position = home;
        auto f = (*system)->renderFrame(camera, kSize, kSize, request);
        ASSERT_TRUE(f.ok()) << f.error().message;
        EXPECT_FALSE(hasLeftOut(*f, "gi.voxel.*@3"));
        full.push_back(f->totalMs);
        camera.position.x += v0;
        auto m = (*system)->renderFrame(camera, kSize, kSize, request);
        ASSERT_TRUE(m.ok()) << m.error().message;
        EXPECT_TRUE(hasLeftOut(*m, "gi.voxel.*@1"));
        oneVoxel.push_back(m->totalMs);
    }
    std::sort(full.begin(), full.end());
    std::sort(oneVoxel.begin(), oneVoxel.end());
    std::printf("hall_world, 4 levels of 32^3, 64^2: frame after a one-voxel move %.1f ms, after a move of every "
                "level %.1f ms (ratio %.2f)\n",
                oneVoxel[2], full[2], oneVoxel[2] / full[2]);
}


// levels = 0 (the default) picks the clipmap for a viewer inside a level much larger than the
// view and the fitted grid otherwise: the hall (fitted voxels 0.25 m, finer than the clipmap's
// coarsest 4 m) keeps its grid, the hall in the 400 m world gets 4 levels of 32^3, and the same
// Cornell box scaled up a thousandfold, seen from its camera outside it, keeps its grid.
TEST(VctSettings, AutomaticLevelsPickTheClipmapOnlyForAViewerInsideALargeWorld) {
    const VctSettings automatic;
    ASSERT_EQ(automatic.levels, 0u);
    auto resolved = [&](const Scene& scene) { return resolveVctLevels(automatic, scene.bounds(), scene.cameraOrDefault()); };
    const VctSettings hall = resolved(test::builtinScene("hall"));
    EXPECT_EQ(hall.levels, 1u);
    EXPECT_EQ(hall.gridResolution, automatic.gridResolution);
    const VctSettings world = resolved(test::builtinScene("hall_world"));
    EXPECT_EQ(world.levels, kVctAutoLevels);
    EXPECT_EQ(world.gridResolution, kVctAutoLevelResolution);
    EXPECT_TRUE(validateVctSettings(world).ok());
    Scene big = test::builtinScene("cornell");
    for (Mesh& m : big.meshes)
        for (glm::vec3& p : m.positions)
            p *= 1000.0f;
    big.camera->position *= 1000.0f;
    EXPECT_EQ(resolved(big).levels, 1u) << "a camera outside the bounds sees all of the scene";
    VctSettings soft = automatic;
    soft.softShadows = true;
    EXPECT_EQ(resolveVctLevels(soft, test::builtinScene("hall_world").bounds(), *test::builtinScene("hall_world").camera).levels,
              1u)
        << "soft shadows read one grid";
}
