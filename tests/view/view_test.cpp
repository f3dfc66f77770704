// vkgi-view end to end, under xvfb-run (tests/CMakeLists.txt runs this binary through it): a
// scripted run must exit 0 with validation + synchronization validation on and silent, and its
// screenshot (linear radiance, before tone mapping) must match vkgi-render's image of the
// same scene, technique, size and camera.
//
// Tolerance: both programs render through the same GiSystem passes, on the same device, with
// the same camera (the scripted orbit and the --animate loops return exactly to the start at
// the last frame), and no vkgi shader reads the frame counter. The images are therefore
// expected to be bit-identical, and the test allows only float noise (max |a - b| <= 1e-5 x
// the reference's peak, a few ulps of the largest value): any real difference (a wrong camera,
// an off-by-one in the readback, a missed scene update, a stale shadow atlas) is far larger.
// VCT is the exception: the viewer marks the object it can move as dynamic, and VCT voxelizes
// dynamic instances into their own volume, which changes the order of the voxel sums: measured
// max |a - b| = 1.0-1.1e-3 x peak, relMSE 4.7-4.8e-6 (cornell 64^2, vct.grid 32). Its bound is 5e-3 x
// peak, still far below a wrong camera or a missing object.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>

#include <gtest/gtest.h>

#include "vkgi/image_io.hpp"
#include "vkgi/image_metrics.hpp"
#include "support/test_env.hpp"

namespace vkgi::test {
namespace {

struct RunResult {
    int code = -1;
    std::string out; // stdout + stderr
};

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s)
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// Runs `exe args` through the shell (`env` = "NAME=value ..." prefix), output to a log file.
RunResult run(const std::string& exe, const std::string& args, const std::string& tag, const std::string& env = "") {
    std::filesystem::path log = outputDir() / ("view-" + tag + ".log");
    std::string cmd = env + " " + quote(exe) + " " + args + " > " + quote(log.string()) + " 2>&1";
    int status = std::system(cmd.c_str());
    RunResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    r.out = ss.str();
    return r;
}

// Renders `technique` on cornell (96x96 unless given) with both programs and compares the
// EXRs. `knobs` go to both, `viewArgs` to vkgi-view only.
void expectViewMatchesRender(const std::string& technique, const std::string& knobs, const std::string& viewArgs,
                             float tolerance = 1e-5f, const std::string& size = "96x96") {
    // One folder per test: ctest runs the cases in parallel.
    std::string tag = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::filesystem::path dir = outputDir() / ("view-" + tag);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    std::string common = "--scene cornell --technique " + technique + " --size " + size + " " + knobs;
    RunResult render = run(VKGI_RENDER_EXE, common + " --out " + quote((dir / "render.exr").string()), tag + "-render");
    ASSERT_EQ(render.code, 0) << render.out;
    RunResult view = run(VKGI_VIEW_EXE,
                         common + " --validation --frames 8 --exit --screenshot " + quote((dir / "view.exr").string()) +
                             " " + viewArgs,
                         tag + "-view");
    ASSERT_EQ(view.code, 0) << view.out;
    EXPECT_EQ(view.out.find("validation"), std::string::npos) << view.out;
    EXPECT_TRUE(std::filesystem::exists(dir / "view.png"));

    auto a = readExr(dir / "view.exr");
    auto b = readExr(dir / "render.exr");
    ASSERT_TRUE(a) << a.error().message;
    ASSERT_TRUE(b) << b.error().message;
    ASSERT_EQ(a->width, b->width);
    ASSERT_EQ(a->height, b->height);
    float peak = 0.0f, maxDiff = 0.0f;
    for (size_t i = 0; i < b->pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            peak = std::max(peak, std::abs(b->pixels[i][c]));
            maxDiff = std::max(maxDiff, std::abs(a->pixels[i][c] - b->pixels[i][c]));
        }
    EXPECT_GT(peak, 0.0f) << "the reference image is black";
    EXPECT_LE(maxDiff, tolerance * peak) << technique << ": max |view - render| " << maxDiff << " nits, peak " << peak;
    auto metrics = compareImages(*a, *b);
    ASSERT_TRUE(metrics) << metrics.error().message;
    EXPECT_EQ(metrics->nonFinite, 0u);
    std::printf("%s: max |view - render| = %g nits (peak %g), relMSE %g\n", technique.c_str(), maxDiff, peak,
                metrics->relMse);
}

// Starts smaller and is resized to 96x96 at frame 2: the swapchain is recreated mid-run.
TEST(View, ScriptedDirectOnlyWithResizeMatchesRender) {
    expectViewMatchesRender("none", "", "--camera-script orbit --animate --size 64x48 --resize-at 2:96x96");
}

TEST(View, ScriptedVplMatchesRender) {
    expectViewMatchesRender("vpl", "", "--camera-script orbit --animate");
}

TEST(View, ScriptedLpvMatchesRender) {
    expectViewMatchesRender("lpv", "--lpv.grid 16", "--camera-script orbit --animate");
}

// The viewer's movable object is dynamic, and VCT voxelizes dynamic instances into their own
// volume, merged under the static voxels: the grids differ where the two share voxels. Since
// the cones read level 0 near their own surface (no coarse footprint reaching back onto it)
// one voxel's difference shows more: measured 2.2e-2 x peak at one pixel, relMSE 1.5e-5
// (before: 1.1e-3 x peak, relMSE 4.8e-6).
TEST(View, ScriptedVctMatchesRenderUpToTheDynamicVolume) {
    expectViewMatchesRender("vct", "--vct.grid 32", "--camera-script orbit --animate", 4e-2f, "64x64");
}

// Starts with LPV and switches to VPL at frame 3 (the GiSystem is rebuilt mid-run).
TEST(View, TechniqueSwitchMatchesRenderOfTheNewTechnique) {
    expectViewMatchesRender("vpl", "", "--camera-script still --technique lpv --lpv.grid 16 --switch-at 3:vpl");
}

// A keyframe file really moves the camera: its view of cornell differs from the scene camera's.
TEST(View, CameraScriptFileMovesTheCamera) {
    std::filesystem::path dir = outputDir() / "view-keyframes";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "path.txt") << "# px py pz  tx ty tz  yfov\n0.1 0.3 1.0  0.2 0.25 0.0  50\n";
    std::string common = "--scene cornell --size 64x64";
    RunResult render = run(VKGI_RENDER_EXE, common + " --out " + quote((dir / "render.exr").string()), "keys-render");
    ASSERT_EQ(render.code, 0) << render.out;
    RunResult view = run(VKGI_VIEW_EXE,
                         common + " --validation --no-ui --frames 2 --exit --camera-script " +
                             quote((dir / "path.txt").string()) + " --screenshot " + quote((dir / "view.exr").string()),
                         "keys-view");
    ASSERT_EQ(view.code, 0) << view.out;
    auto a = readExr(dir / "view.exr");
    auto b = readExr(dir / "render.exr");
    ASSERT_TRUE(a && b);
    auto metrics = compareImages(*a, *b);
    ASSERT_TRUE(metrics) << metrics.error().message;
    EXPECT_GT(metrics->relMse, 0.01);
}

// The CI check itself: a validation message must turn into a failing exit code. The layer's
// best-practices checks (switched on through its environment) always warn on this run.
TEST(View, ValidationMessagesMakeTheExitCode3) {
    RunResult r = run(VKGI_VIEW_EXE, "--size 32x32 --frames 2 --exit --validation --no-ui", "validation-fails",
                      "VK_LAYER_ENABLES=VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT");
    EXPECT_EQ(r.code, 3) << r.out;
    EXPECT_NE(r.out.find("validation message(s)"), std::string::npos) << r.out;
}

TEST(View, CameraScriptFileErrorsNameTheLine) {
    std::filesystem::path file = outputDir() / "view-bad-script.txt";
    std::ofstream(file) << "# position target\n0 1 3  0 1 0\n0 1 x 0 0 0\n";
    RunResult r =
        run(VKGI_VIEW_EXE, "--size 32x32 --frames 2 --exit --camera-script " + quote(file.string()), "bad-script");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find(file.string() + ":3: 'x' is not a finite number"), std::string::npos) << r.out;
}

TEST(View, BadArgumentsExit2BeforeOpeningAWindow) {
    for (const char* args :
         {"--exit", "--screenshot out.png --frames 1", "--frames 0", "--technique nope", "--lpv.grid 0",
          "--technique vct --vct.grid 100", "--light lamp:0,0,0:1", "--camera 1,1,1:1,1,1",
          "--present vsync", "--frames 3 --resize-at 3:64x64", "--frames 3 --switch-at 1:nope"}) {
        RunResult r = run(VKGI_VIEW_EXE, args, "bad-args");
        EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
        EXPECT_NE(r.out.find("vkgi-view: "), std::string::npos) << args;
    }
}

} // namespace
} // namespace vkgi::test
