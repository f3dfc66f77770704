// vkgi-render as a user runs it: bad arguments give exit code 2 and one line naming the
// problem, an unreadable scene exit code 1, and a small render writes a readable EXR and JSON.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/image_io.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_env.hpp"

namespace fs = std::filesystem;

namespace {

// The test executable lives in <build>/tests, the app in <build>/apps.
fs::path renderBinary() { return fs::read_symlink("/proc/self/exe").parent_path().parent_path() / "apps" / "vkgi-render"; }

struct CliRun {
    int exitCode = -1;
    std::string err; // stderr
};

// `env`: extra "NAME=value" assignments for the run.
CliRun run(const std::string& args, const std::string& env = "") {
    CliRun r;
    // With the validation layers on, as in every GPU test: a message makes vkgi-render exit 3.
    std::string cmd = "VKGI_VALIDATION=1 " + env + " " + renderBinary().string() + " " + args + " 2>&1 1>/dev/null";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p)
        return r;
    char buf[512];
    while (fgets(buf, sizeof(buf), p))
        r.err += buf;
    int status = pclose(p);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

size_t lines(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(renderBinary()))
            GTEST_SKIP() << "vkgi-render not built (GI_BUILD_APPS=OFF)";
    }
};

} // namespace

TEST_F(Cli, BadArgumentsExitTwoWithOneLine) {
    struct Case {
        const char* args;
        const char* mentions;
    } cases[] = {{"--bogus", "--bogus"},          {"--size 0x64", "--size"},     {"--size 64", "--size"},
                 {"--size 99999x64", "--size"},   {"--size", "needs a value"}, {"--spp nan", "--spp"},
                 {"--spp -3", "--spp"},           {"--bounces 1.5", "--bounces"}, {"--technique magic", "magic"},
                 {"--out image.jpg", "image.jpg"}, {"--json", "needs a value"},
                 {"--out-indirect x.tif", "--out-indirect"},
                 {"--technique reference --size 8x8 --out-glossy g.png", "--out-glossy"},
                 // Each knob in its own range, the settings still wrong as a whole: a bad argument too.
                 {"--technique vct --vct.grid 100", "gridResolution 100"},
                 {"--technique vpl --vpl.visibility_grid 100", "visibilityGrid 100"},
                 {"--camera 1,2", "--camera"},                {"--camera 1,2,3:1,2,3", "apart"},
                 {"--camera 1,2,3:4,5,6:30:1", "--camera"},
                 {"--camera 0,0,0:0,0,1:180", "field of view"}, {"--light lamp:0,0,0:1", "--light"},
                 {"--light point:0,0,0:-1", "above 0"},      {"--light sun:0,0,0:100", "not zero"},
                 {"--light spot:0,1,0:0,-1,0:5:95", "OUTER"}, {"--light point:0,nan,0:1", "--light"},
                 {"--light spot:0,1,0:0,-1,0:5:30:40", "INNER"}, {"--light point:0,1,0:5:0,0,0", "not black"},
                 {"--light sun:0,-1,0:100:1,-1,1", "R,G,B"}};
    for (const Case& c : cases) {
        CliRun r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args;
        EXPECT_EQ(lines(r.err), 1u) << c.args << ": " << r.err;
        EXPECT_NE(r.err.find(c.mentions), std::string::npos) << c.args << ": " << r.err;
    }
}

TEST_F(Cli, HelpDocumentsEveryOption) {
    std::string cmd = renderBinary().string() + " --help";
    FILE* p = popen(cmd.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[512];
    while (fgets(buf, sizeof(buf), p))
        out += buf;
    EXPECT_EQ(pclose(p), 0);
    for (const char* opt : {"--scene", "--technique", "--size", "--out", "--out-direct", "--out-indirect", "--out-glossy",
                            "--out-ao", "--spp", "--bounces", "--compare", "--json"})
        EXPECT_NE(out.find(opt), std::string::npos) << opt;
}

TEST_F(Cli, UnreadableSceneExitsOneAndWritesNothing) {
    fs::path dir = vkgi::test::outputDir() / "cli_missing";
    fs::remove_all(dir);
    CliRun r = run("--scene /nonexistent/box.gltf --out " + (dir / "x.png").string());
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("box.gltf"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.png"));
}

// The check every run above relies on: a validation message fails the run (exit 3) and nothing
// is written. The layer's best-practices checks (enabled through its environment) always warn.
TEST_F(Cli, ValidationMessagesExitThreeAndWriteNothing) {
    fs::path dir = vkgi::test::outputDir() / "cli_validation";
    fs::remove_all(dir);
    CliRun r = run("--scene cornell --size 16x16 --out " + (dir / "x.png").string(),
                   "VK_LAYER_ENABLES=VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT");
    EXPECT_EQ(r.exitCode, 3) << r.err;
    EXPECT_NE(r.err.find("validation message(s)"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.png"));
}

// A light and a camera from the command line (asset packs ship neither): the light adds to the
// scene's (direct light only here, so exactly: the two runs differ by the added point light),
// and the camera replaces the scene's (the image differs from the default view's).
TEST_F(Cli, CameraAndLightsFromTheCommandLine) {
    fs::path dir = vkgi::test::outputDir() / "cli_overrides";
    fs::remove_all(dir);
    const std::string base = "--scene cornell --size 16x16 --out ";
    CliRun plain = run(base + (dir / "plain.exr").string());
    CliRun lit = run(base + (dir / "lit.exr").string() + " --light point:0.278,0.3,0.28:2");
    CliRun moved = run(base + (dir / "moved.exr").string() + " --camera 0.278,0.27,-0.6:0.278,0.2,0.3:45");
    ASSERT_EQ(plain.exitCode, 0) << plain.err;
    ASSERT_EQ(lit.exitCode, 0) << lit.err;
    ASSERT_EQ(moved.exitCode, 0) << moved.err;
    auto a = vkgi::readExr(dir / "plain.exr"), b = vkgi::readExr(dir / "lit.exr"), c = vkgi::readExr(dir / "moved.exr");
    ASSERT_TRUE(a && b && c);
    uint32_t brighter = 0, darker = 0, differ = 0;
    for (size_t i = 0; i < a->pixels.size(); ++i) {
        brighter += b->pixels[i].y > a->pixels[i].y * 1.01f;
        darker += b->pixels[i].y < a->pixels[i].y * (1.0f - 1e-5f);
        differ += c->pixels[i] != a->pixels[i];
    }
    EXPECT_GT(brighter, a->pixels.size() / 2) << "a 2 cd lamp in the box lights most of what the camera sees";
    EXPECT_EQ(darker, 0u) << "an added light takes nothing away";
    EXPECT_GT(differ, a->pixels.size() / 2);

    // The optional parts: a red lamp adds red only; an eye without a target looks at the centre
    // of the scene (here the same view as aiming at it explicitly).
    CliRun red = run(base + (dir / "red.exr").string() + " --light point:0.278,0.3,0.28:2:1,0,0");
    CliRun eyeOnly = run(base + (dir / "eye.exr").string() + " --camera 0.278,0.27,-0.6");
    ASSERT_EQ(red.exitCode, 0) << red.err;
    ASSERT_EQ(eyeOnly.exitCode, 0) << eyeOnly.err;
    auto r = vkgi::readExr(dir / "red.exr"), e = vkgi::readExr(dir / "eye.exr");
    ASSERT_TRUE(r && e);
    double addedRed = 0.0, addedBlue = 0.0;
    for (size_t i = 0; i < a->pixels.size(); ++i) {
        addedRed += r->pixels[i].x - a->pixels[i].x;
        addedBlue += std::abs(r->pixels[i].z - a->pixels[i].z);
    }
    EXPECT_GT(addedRed, 1e-3 * double(a->pixels.size()));
    EXPECT_LT(addedBlue, 1e-6 * addedRed) << "a red lamp adds no blue light";
    auto box = vkgi::makeBuiltinScene("cornell");
    ASSERT_TRUE(box);
    glm::vec3 centre = box->bounds().centre();
    char aimed[128];
    std::snprintf(aimed, sizeof aimed, "0.278,0.27,-0.6:%.9g,%.9g,%.9g", centre.x, centre.y, centre.z);
    CliRun aimedRun = run(base + (dir / "aimed.exr").string() + " --camera " + std::string(aimed));
    ASSERT_EQ(aimedRun.exitCode, 0) << aimedRun.err;
    auto t = vkgi::readExr(dir / "aimed.exr");
    ASSERT_TRUE(t);
    double largest = 0.0;
    for (size_t i = 0; i < e->pixels.size(); ++i)
        largest = std::max(largest, double(glm::length(e->pixels[i] - t->pixels[i])));
    EXPECT_EQ(largest, 0.0) << "eye-only camera = camera aimed at the bounds' centre";
}

TEST_F(Cli, SmallRenderWritesImageAndJson) {
    fs::path dir = vkgi::test::outputDir() / "cli_render";
    fs::remove_all(dir);
    CliRun r = run("--scene cornell_point --size 24x16 --out " + (dir / "img.exr").string() + " --json " +
                (dir / "report.json").string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto img = vkgi::readExr(dir / "img.exr");
    ASSERT_TRUE(img) << img.error().message;
    EXPECT_EQ(img->width, 24u);
    EXPECT_EQ(img->height, 16u);
    std::ifstream in(dir / "report.json");
    auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j["scene"], "cornell_point");
    EXPECT_EQ(j["technique"], "none");
    EXPECT_EQ(j["width"], 24);
    EXPECT_TRUE(j["error"].is_null());
    double sum = 0.0;
    ASSERT_FALSE(j["passes"].empty());
    for (const auto& p : j["passes"])
        sum += p["ms"].get<double>();
    // The frame's timestamp scope encloses every pass's scope (and the barriers between them).
    EXPECT_GE(j["total_ms"].get<double>(), sum - 1e-6 * (1.0 + sum));

    // Memory, counted by owner: two RGBA32F readback images of 24x16, the point light's six
    // 256^2 D32 shadow faces (default shadow.size), no technique volumes for `none`; every
    // transient is first used by exactly one pass.
    const auto& mem = j["memory"];
    ASSERT_TRUE(mem.is_object());
    EXPECT_EQ(mem["persistent"]["readback"].get<uint64_t>(), 2u * 24u * 16u * 16u);
    EXPECT_EQ(mem["persistent"]["shadows"].get<uint64_t>(), 6u * 256u * 256u * 4u);
    EXPECT_EQ(mem["persistent"]["technique"].get<uint64_t>(), 0u);
    EXPECT_GT(mem["persistent"]["scene"].get<uint64_t>(), 0u);
    uint64_t created = 0;
    for (const auto& p : mem["passes"])
        created += p["created_bytes"].get<uint64_t>();
    EXPECT_EQ(created, mem["transient_bytes"].get<uint64_t>());
    EXPECT_GT(created, 0u);
    uint64_t persistent = 0;
    for (const auto& [owner, bytes] : mem["persistent"].items())
        persistent += bytes.get<uint64_t>();
    EXPECT_EQ(mem["total_bytes"].get<uint64_t>(), persistent + created);
}

// The parts of one frame: with LPV the image is exactly direct + indirect (the files hold the
// readbacks' floats, and indirect is written as image - direct), the indirect part is light
// (the box's walls bounce the spot's light), and the default out/<scene>.png is not written
// when only parts are asked for.
TEST_F(Cli, WritesTheDirectAndIndirectParts) {
    fs::path dir = vkgi::test::outputDir() / "cli_parts";
    fs::remove_all(dir);
    fs::path cwd = fs::current_path();
    fs::create_directories(dir);
    fs::current_path(dir);
    CliRun r = run("--scene cornell --technique lpv --lpv.grid 8 --lpv.iterations 2 --size 16x16 --out img.exr "
                   "--out-direct direct.exr --out-indirect indirect.exr");
    CliRun partsOnly = run("--scene cornell --size 8x8 --out-direct only.exr");
    fs::current_path(cwd);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    ASSERT_EQ(partsOnly.exitCode, 0) << partsOnly.err;
    EXPECT_TRUE(fs::exists(dir / "only.exr"));
    EXPECT_FALSE(fs::exists(dir / "out"));
    auto img = vkgi::readExr(dir / "img.exr");
    auto direct = vkgi::readExr(dir / "direct.exr");
    auto indirect = vkgi::readExr(dir / "indirect.exr");
    ASSERT_TRUE(img && direct && indirect);
    ASSERT_EQ(img->pixels.size(), 256u);
    ASSERT_EQ(direct->pixels.size(), 256u);
    ASSERT_EQ(indirect->pixels.size(), 256u);
    double indirectSum = 0.0;
    for (size_t i = 0; i < img->pixels.size(); ++i) {
        EXPECT_EQ(indirect->pixels[i], img->pixels[i] - direct->pixels[i]) << i;
        indirectSum += double(indirect->pixels[i].x + indirect->pixels[i].y + indirect->pixels[i].z);
    }
    EXPECT_GT(indirectSum, 0.0);
}

TEST_F(Cli, JsonListsLeftOutPassesAndTheStaticFrame) {
    fs::path dir = vkgi::test::outputDir() / "cli_left_out";
    fs::remove_all(dir);
    CliRun r = run("--scene cornell --technique lpv --lpv.grid 8 --lpv.iterations 2 --size 16x16 --out " +
                   (dir / "img.exr").string() + " --json " + (dir / "report.json").string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::ifstream in(dir / "report.json");
    auto j = nlohmann::json::parse(in);
    std::map<std::string, std::string> leftOut;
    for (const auto& p : j["left_out"])
        leftOut[p["name"].get<std::string>()] = p["reason"].get<std::string>() + ": " + p["detail"].get<std::string>();
    EXPECT_EQ(leftOut["gi.light[*].point"], "not-needed: no point light in the scene");
    EXPECT_EQ(leftOut["gi.light[*].directional"], "not-needed: no directional light in the scene");
    EXPECT_EQ(leftOut.count("gi.lpv.propagate*"), 0u) << "the measured frame recomputes everything";
    // A third frame recomputing everything timed by the frame's scope alone: positive and finite
    // (not compared with total_ms: at 16x16 the difference is within the machine's noise).
    ASSERT_TRUE(j["unprofiled_ms"].is_number());
    EXPECT_GT(j["unprofiled_ms"].get<double>(), 0.0);
    EXPECT_TRUE(std::isfinite(j["unprofiled_ms"].get<double>()));
    // The static frame re-runs only the per-pixel work.
    ASSERT_TRUE(j["static_frame"].is_object());
    std::string passes;
    for (const auto& p : j["static_frame"]["passes"])
        passes += p["name"].get<std::string>() + " ";
    EXPECT_EQ(passes, "gi.gbuffer gi.shadow.setup gi.direct gi.lpv.lookup gi.composite gi.readback.composite "
                      "gi.readback.direct ");
    std::string reasons;
    for (const auto& p : j["static_frame"]["left_out"])
        reasons += p["name"].get<std::string>() + "=" + p["reason"].get<std::string>() + " ";
    EXPECT_EQ(reasons, "gi.light[*].directional=not-needed gi.light[*].point=not-needed gi.light[0].spot=not-dirty "
                       "gi.lpv.inject*=not-dirty gi.lpv.gv.*=not-dirty gi.lpv.propagate*=not-dirty "
                       "gi.lpv.lookup.sum=not-dirty ");
}
