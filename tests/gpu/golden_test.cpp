// Golden images: every built-in scene's direct image and the VPL, LPV and VCT composites of
// two scenes each at 64x64, compared with EXRs in tests/golden/. The other tests pin the physics
// (closed forms, the path tracer); these catch any unintended change of the pictures, in a pass
// no closed-form test looks at (a flipped texel, a shifted shadow, a changed bias).
//
// A golden changes only with an intended change of the picture: render the new ones with
//     VKGI_UPDATE_GOLDENS=1 build/tests/vkgi_gpu_tests --gtest_filter='Golden*'
// (the test then writes tests/golden/<name>.exr and is skipped), look at the difference, and
// say in the commit message why the picture changed. CI never sets the variable.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/image_io.hpp"
#include "vkgi/gi.hpp"
#include "vkgi/knobs.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_env.hpp"

using namespace vkgi;

namespace {

struct GoldenCase {
    std::string scene;
    std::string technique; // "none" = direct light only
    std::string knobs;     // space-separated name=value
    std::string name() const { return scene + "-" + technique; }
};
void PrintTo(const GoldenCase& c, std::ostream* os) { *os << c.name() << " [" << c.knobs << "]"; }

std::vector<GoldenCase> cases() {
    std::vector<GoldenCase> c;
    for (const std::string& s : builtinSceneNames())
        c.push_back({s, "none", ""});
    // Halton VPLs are deterministic; the defaults (an interleaved gather, filtered and refined)
    // and a full gather at half resolution with refine.
    c.push_back({"cornell", "vpl", ""});
    c.push_back({"bunny_box", "vpl", "vpl.count=64 vpl.lowres=2 vpl.interleave=1"});
    // LPV and VCT at their defaults on a spot-lit box and a sun-lit room (VCT's voxelization
    // sums in fixed point and LPV's injection gathers, so both are deterministic).
    c.push_back({"cornell", "lpv", ""});
    c.push_back({"room", "lpv", ""});
    c.push_back({"cornell", "vct", ""});
    c.push_back({"room", "vct", ""});
    return c;
}

bool updating() {
    const char* v = std::getenv("VKGI_UPDATE_GOLDENS");
    return v && std::string(v) == "1";
}

class Golden : public test::GpuTest, public ::testing::WithParamInterface<GoldenCase> {};

} // namespace

TEST_P(Golden, MatchesTheStoredImage) {
    const GoldenCase& c = GetParam();
    auto scene = makeBuiltinScene(c.scene);
    ASSERT_TRUE(scene) << scene.error().message;
    gi::GiSettings settings;
    auto technique = gi::parseTechnique(c.technique);
    ASSERT_TRUE(technique) << technique.error().message;
    settings.technique = *technique;
    std::stringstream in(c.knobs);
    for (std::string kv; in >> kv;) {
        auto ok = gi::applyKnob(settings, kv);
        ASSERT_TRUE(ok) << ok.error().message;
    }
    gi::FrameRequest request;
    request.composite = true;
    auto frame = test::renderOnce(ctx(), settings, *scene, scene->cameraOrDefault(), 64, 64, request);
    ASSERT_TRUE(frame) << frame.error().message;
    const HdrImage& image = frame->composite;
    ASSERT_EQ(image.width, 64u);

    const std::filesystem::path golden = test::sourceDir() / "tests" / "golden" / (c.name() + ".exr");
    if (updating()) {
        auto w = writeExr(golden, image);
        ASSERT_TRUE(w) << w.error().message;
        GTEST_SKIP() << "wrote " << golden.string();
    }
    auto expected = readExr(golden);
    ASSERT_TRUE(expected) << expected.error().message << " (render it with VKGI_UPDATE_GOLDENS=1, see the file comment)";
    ASSERT_EQ(expected->width, image.width);
    ASSERT_EQ(expected->height, image.height);

    // Lavapipe JIT-compiles for the host CPU, so another CPU may round differently (FMA
    // contraction, vector width): each channel may differ by 1e-4 of itself plus 1e-6 of the
    // image's peak, about 50x float32 epsilon accumulated over a few hundred operations. Any
    // real change of the picture is orders of magnitude larger.
    float peak = 0.0f;
    for (const glm::vec3& p : expected->pixels)
        peak = std::max({peak, p.r, p.g, p.b});
    ASSERT_GT(peak, 0.0f) << "a black golden tests nothing";
    size_t bad = 0, worst = 0;
    double worstExcess = 0.0;
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int ch = 0; ch < 3; ++ch) {
            double a = image.pixels[i][ch], e = expected->pixels[i][ch];
            double tol = 1e-4 * std::abs(e) + 1e-6 * peak;
            double excess = std::isfinite(a) ? std::abs(a - e) / tol : INFINITY;
            if (excess > 1.0) {
                ++bad;
                if (excess > worstExcess)
                    worstExcess = excess, worst = i;
            }
        }
    if (bad > 0) {
        std::filesystem::path actual = test::outputDir() / ("golden-" + c.name() + ".exr");
        (void)writeExr(actual, image);
        ADD_FAILURE() << bad << " channel values differ from " << golden.string() << "; worst at pixel ("
                      << worst % 64 << ", " << worst / 64 << "): " << image.pixels[worst].r << ", "
                      << image.pixels[worst].g << ", " << image.pixels[worst].b << " vs "
                      << expected->pixels[worst].r << ", " << expected->pixels[worst].g << ", "
                      << expected->pixels[worst].b << " (" << worstExcess << "x the tolerance); image written to "
                      << actual.string();
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Golden, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<GoldenCase>& p) {
                             std::string n = p.param.name();
                             for (char& ch : n)
                                 ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                             return n;
                         });
