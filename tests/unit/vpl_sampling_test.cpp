// VPL placement math (gi/vpl.h, vkgi/vpl.hpp): Halton values, uniformity on the sphere, the
// paper's "first N inside the cone" rule, determinism, the spot frame and its smoothness.
#include <array>
#include <cmath>
#include <limits>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gi/vpl.h"
#include "vkgi/vpl.hpp"
#include "vpl/vpl_technique_module.hpp"
#include "voxel/scene_voxel_grid.hpp"

using namespace vkgi;
using namespace vkgi::gi;

TEST(VplSampling, RadicalInverseHasExactValues) {
    EXPECT_EQ(gpu::vplRadicalInverse(0, 2), 0.0f);
    EXPECT_EQ(gpu::vplRadicalInverse(1, 2), 0.5f);
    EXPECT_EQ(gpu::vplRadicalInverse(2, 2), 0.25f);
    EXPECT_EQ(gpu::vplRadicalInverse(3, 2), 0.75f);
    EXPECT_EQ(gpu::vplRadicalInverse(5, 2), 0.625f);
    EXPECT_EQ(gpu::vplRadicalInverse(6, 2), 0.375f);
    // Base 3: 1/3, 2/3, 1/9, 4/9, 7/9 are not binary fractions; within float rounding (4 ULP).
    EXPECT_FLOAT_EQ(gpu::vplRadicalInverse(1, 3), 1.0f / 3.0f);
    EXPECT_FLOAT_EQ(gpu::vplRadicalInverse(2, 3), 2.0f / 3.0f);
    EXPECT_FLOAT_EQ(gpu::vplRadicalInverse(3, 3), 1.0f / 9.0f);
    EXPECT_FLOAT_EQ(gpu::vplRadicalInverse(4, 3), 4.0f / 9.0f);
    EXPECT_FLOAT_EQ(gpu::vplRadicalInverse(5, 3), 7.0f / 9.0f);
    EXPECT_FLOAT_EQ(gpu::vplRadicalInverse(13, 3), 1.0f / 3.0f + 1.0f / 9.0f + 1.0f / 27.0f); // 111 in base 3
    // Every value of the first 3^8 base-3 indices is a distinct multiple of 3^-8 in [0, 1).
    std::vector<int> hits(6561, 0);
    for (uint32_t i = 0; i < 6561; ++i) {
        float x = gpu::vplRadicalInverse(i, 3) * 6561.0f;
        int k = int(std::lround(x));
        ASSERT_NEAR(x, float(k), 1e-2f) << i;
        ASSERT_GE(k, 0);
        ASSERT_LT(k, 6561);
        ++hits[size_t(k)];
    }
    for (int h : hits)
        EXPECT_EQ(h, 1);
}

TEST(VplSampling, HaltonSpherePointsAreUnitAndUniform) {
    constexpr uint32_t kN = 4096;
    uint32_t caps[4] = {};
    const float capCos[4] = {0.9f, 0.5f, 0.0f, -0.5f};
    uint32_t octants[8] = {};
    for (uint32_t i = 1; i <= kN; ++i) {
        glm::vec3 p = gpu::vplHaltonSphere(i);
        ASSERT_NEAR(glm::length(p), 1.0f, 1e-6f) << i;
        for (int c = 0; c < 4; ++c)
            caps[c] += p.z >= capCos[c];
        octants[(p.x > 0) + 2 * (p.y > 0) + 4 * (p.z > 0)]++;
    }
    // A cap z >= c has area fraction (1 - c) / 2 (Archimedes) and is an interval of the base-2
    // coordinate; the van der Corput discrepancy is below (log2 N + 1) / N = 13 / 4096.
    for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(double(caps[c]) / kN, (1.0 - capCos[c]) / 2.0, 13.0 / kN) << "cap " << capCos[c];
    // An octant is a rectangle [u0, u0 + 1/2) x [v0, v0 + 1/4) of the Halton square; the error of
    // such a box is at most (#base-2 digits) * (#base-3 digits) / N = 13 * 8 / 4096.
    for (int o = 0; o < 8; ++o)
        EXPECT_NEAR(double(octants[o]) / kN, 0.125, 104.0 / kN) << "octant " << o;
}

TEST(VplSampling, KeepsTheFirstNHaltonPointsInsideTheCone) {
    const float cosOuter = std::cos(0.5f); // ~28.6 degrees half-angle
    auto dirs = spotSampleDirections(100, cosOuter);
    ASSERT_TRUE(dirs) << dirs.error().message;
    ASSERT_EQ(dirs->size(), 100u);
    // Rebuild the list independently: walk the indices, keep what is inside, stop at 100.
    std::vector<glm::vec3> expected;
    uint32_t lastIndex = 0;
    for (uint32_t i = 1; expected.size() < 100; ++i) {
        glm::vec3 p = gpu::vplHaltonSphere(i);
        if (p.z >= cosOuter) {
            expected.push_back(p);
            lastIndex = i;
        }
    }
    for (size_t k = 0; k < 100; ++k) {
        EXPECT_GE((*dirs)[k].z, cosOuter);
        EXPECT_EQ((*dirs)[k], expected[k]) << k;
    }
    // The cone holds (1 - cos) / 2 of the sphere, so ~100 / that indices were walked.
    double expectedIndices = 100.0 / ((1.0 - cosOuter) / 2.0);
    EXPECT_NEAR(double(lastIndex), expectedIndices, 0.1 * expectedIndices);
}

TEST(VplSampling, IsDeterministic) {
    auto a = spotSampleDirections(400, 0.7f);
    auto b = spotSampleDirections(400, 0.7f);
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->size(), b->size());
    EXPECT_EQ(std::memcmp(a->data(), b->data(), a->size() * sizeof(glm::vec3)), 0);
    // Asking for fewer VPLs gives a prefix: raising the count adds VPLs, never moves them.
    auto c = spotSampleDirections(50, 0.7f);
    ASSERT_TRUE(c);
    EXPECT_EQ(std::memcmp(a->data(), c->data(), c->size() * sizeof(glm::vec3)), 0);
}

TEST(VplSampling, BadRequestsAreErrors) {
    auto tooMany = spotSampleDirections(kMaxVplsPerLight + 1, 0.5f);
    ASSERT_FALSE(tooMany);
    EXPECT_NE(tooMany.error().message.find("maximum"), std::string::npos) << tooMany.error().message;
    // Half-angle 0.5 degrees: (1 - cos) / 2 ~ 1.9e-5, so 4096 points need ~2e8 indices.
    auto narrow = spotSampleDirections(kMaxVplsPerLight, std::cos(0.5f * 3.14159265f / 180.0f));
    ASSERT_FALSE(narrow);
    EXPECT_NE(narrow.error().message.find("too narrow"), std::string::npos) << narrow.error().message;
    EXPECT_FALSE(spotSampleDirections(10, 1.0f));
    EXPECT_FALSE(spotSampleDirections(10, std::nanf("")));
    auto none = spotSampleDirections(0, 0.5f);
    ASSERT_TRUE(none);
    EXPECT_TRUE(none->empty());
}

TEST(VplSampling, SettingsValidation) {
    EXPECT_TRUE(validateVplSettings({}));
    VplSettings s;
    s.vplCount = 0;
    auto r = validateVplSettings(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("vplCount 0"), std::string::npos) << r.error().message;
    s = {};
    s.vplCount = kMaxVplsPerLight + 1;
    EXPECT_FALSE(validateVplSettings(s));
    s = {};
    s.negativeVplCount = kMaxNegativeVpls + 1;
    EXPECT_FALSE(validateVplSettings(s));
    s = {};
    s.lowResFactor = 3;
    EXPECT_FALSE(validateVplSettings(s));
    s = {};
    s.clampDistance = 0.0f;
    EXPECT_FALSE(validateVplSettings(s));
    s.clampDistance = 16.5f;
    EXPECT_FALSE(validateVplSettings(s));
    s = {};
    s.focusRadius = 0.009f; // the knob's range, 0.01..1e5 m
    EXPECT_FALSE(validateVplSettings(s));
    s.focusRadius = 0.01f;
    EXPECT_TRUE(validateVplSettings(s));
    s.focusRadius = 2e5f;
    EXPECT_FALSE(validateVplSettings(s));
    s = {};
    s.candidates = 0; // the lattice points themselves
    EXPECT_TRUE(validateVplSettings(s));
    s.candidates = kMaxVplCandidates + 1;
    r = validateVplSettings(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("candidates 17"), std::string::npos) << r.error().message;
    s = {};
    s.refineThreshold = std::nanf("");
    EXPECT_FALSE(validateVplSettings(s));
    s = {};
    s.interleave = 0;
    EXPECT_FALSE(validateVplSettings(s));
    s.interleave = kMaxVplInterleave + 1;
    r = validateVplSettings(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("interleave 5"), std::string::npos) << r.error().message;
    s = {};
    s.interleaveTolerance = std::numeric_limits<float>::infinity();
    EXPECT_FALSE(validateVplSettings(s));
    s = {};
    s.visibilityGrid = 100; // not a power of two
    r = validateVplSettings(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("visibilityGrid 100"), std::string::npos) << r.error().message;
    s.visibilityGrid = 512;
    EXPECT_FALSE(validateVplSettings(s));
    s = {};
    s.vplCount = kMaxVplsPerLight;
    s.negativeVplCount = kMaxNegativeVpls;
    s.lowResFactor = 4;
    s.interleave = kMaxVplInterleave;
    s.visibility = VplVisibilityMode::On;
    s.visibilityGrid = 256;
    s.bounces = kMaxVplBounces;
    EXPECT_TRUE(validateVplSettings(s));
    s = {};
    s.bounces = kMaxVplBounces + 1;
    r = validateVplSettings(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("bounces 5"), std::string::npos) << r.error().message;
}

// The automatic rule: visibility marched per receiver (and with it a second bounce) where a
// directional light or emission shines, the visibility maps (and the second bounce) with a point
// light, the paper's setting (no visibility, one bounce) with spotlights only; explicit values
// are kept.
TEST(VplSampling, AutomaticSettingsFollowTheKindOfLight) {
    const VplSettings automatic;
    EXPECT_EQ(automatic.visibility, VplVisibilityMode::Auto);
    EXPECT_EQ(automatic.bounces, 0u);
    const VplSettings sun = resolveVplSettings(automatic, VplLighting::SunOrEmission),
                      lamp = resolveVplSettings(automatic, VplLighting::PointLights),
                      spot = resolveVplSettings(automatic, VplLighting::Spots);
    EXPECT_EQ(sun.visibility, VplVisibilityMode::On);
    EXPECT_EQ(sun.bounces, 2u);
    EXPECT_EQ(lamp.visibility, VplVisibilityMode::Maps);
    EXPECT_EQ(lamp.bounces, 2u);
    EXPECT_EQ(spot.visibility, VplVisibilityMode::Off);
    EXPECT_EQ(spot.bounces, 1u);
    VplSettings fixed;
    fixed.visibility = VplVisibilityMode::Off;
    fixed.bounces = 3;
    for (VplLighting l : {VplLighting::Spots, VplLighting::PointLights, VplLighting::SunOrEmission})
        EXPECT_EQ(resolveVplSettings(fixed, l), fixed);
    fixed.visibility = VplVisibilityMode::On;
    fixed.bounces = 0;
    EXPECT_EQ(resolveVplSettings(fixed, VplLighting::Spots).bounces, 2u);
    fixed.visibility = VplVisibilityMode::Maps; // kept with a sun too
    EXPECT_EQ(resolveVplSettings(fixed, VplLighting::SunOrEmission).visibility, VplVisibilityMode::Maps);
    EXPECT_EQ(resolveVplSettings(fixed, VplLighting::SunOrEmission).bounces, 2u);
    fixed.visibility = VplVisibilityMode::Off;
    fixed.bounces = 0;
    EXPECT_EQ(resolveVplSettings(fixed, VplLighting::PointLights).bounces, 1u);
}

// Which kind of lighting a scene's lights and emission make (the automatic rule's input): a sun or
// emission wins over lamps, a point light over spotlights.
TEST(VplSampling, LightingKindFollowsTheStrongestNeed) {
    auto light = [](LightType type) {
        Light l;
        l.type = type;
        return l;
    };
    using enum LightType;
    EXPECT_EQ(gi::vplLighting({}, false), VplLighting::Spots);
    EXPECT_EQ(gi::vplLighting({light(Spot)}, false), VplLighting::Spots);
    EXPECT_EQ(gi::vplLighting({light(Spot), light(Point)}, false), VplLighting::PointLights);
    EXPECT_EQ(gi::vplLighting({light(Point), light(Directional)}, false), VplLighting::SunOrEmission);
    EXPECT_EQ(gi::vplLighting({light(Point)}, true), VplLighting::SunOrEmission);
    EXPECT_EQ(gi::vplLighting({}, true), VplLighting::SunOrEmission);
}

// The shared grid's placement rule (docs/vpl.md, "Visibility"): camera-centred only where the
// camera is inside the bounds and the fitted voxel would be more than twice the camera grid's
// (64 m / N, or the lamp span's 32 m / N); the corner snaps to quarter-grid steps and keeps the camera at least N/4 voxels
// from every face.
TEST(VplSampling, SharedGridFollowsTheCameraOnlyInLargeScenes) {
    auto box = [](glm::vec3 lo, glm::vec3 hi) {
        Aabb b;
        b.extend(lo);
        b.extend(hi);
        return b;
    };
    const Aabb atrium = box({-7.3f, -0.2f, -14.3f}, {7.3f, 9.6f, 14.3f});
    const Aabb world = box({-200.0f, -0.2f, -200.0f}, {200.0f, 20.0f, 200.0f});
    const glm::vec3 eye(0.0f, 1.7f, -12.5f);
    EXPECT_FALSE(sharedGridFollowsCamera(atrium, 64, eye)); // 0.45 m fitted voxels
    EXPECT_TRUE(sharedGridFollowsCamera(world, 64, eye));   // 6.3 m against 1 m
    EXPECT_FALSE(sharedGridFollowsCamera(world, 64, glm::vec3(0.0f, 50.0f, 0.0f))) << "camera outside";
    EXPECT_FALSE(sharedGridFollowsCamera(Aabb{}, 64, eye));
    // 2 x 64 m / N against 400 m / (N - 1): the switch sits between N = 64 and N = 256 at any N
    // for the world; a 100 m scene (1.6 m fitted voxels at 64^3) keeps its fitted grid.
    EXPECT_TRUE(sharedGridFollowsCamera(world, 256, eye));
    EXPECT_FALSE(sharedGridFollowsCamera(box({-50.0f, 0.0f, -50.0f}, {50.0f, 10.0f, 50.0f}), 64, eye));
    // With the lamp span (32 m) the switch is at 1 m fitted voxels: the 100 m scene follows the
    // camera, the 16 m hall (0.25 m) keeps its fitted grid.
    EXPECT_TRUE(sharedGridFollowsCamera(box({-50.0f, 0.0f, -50.0f}, {50.0f, 10.0f, 50.0f}), 64, eye,
                                        kSharedGridLampSpan));
    EXPECT_FALSE(sharedGridFollowsCamera(box({-8.0f, 0.0f, -5.0f}, {8.0f, 6.0f, 5.0f}), 64, glm::vec3(0.0f, 1.7f, 0.0f),
                                         kSharedGridLampSpan));
    const uint32_t n = 64;
    const float voxel = kSharedGridSpan / float(n);
    for (glm::vec3 p : {eye, glm::vec3(7.9f, 0.0f, -8.1f), glm::vec3(-123.4f, 5.0f, 77.7f)}) {
        const glm::ivec3 cell = sharedGridCell(p, voxel, n);
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(((cell[a] + int(n / 2)) % int(n / 4) + int(n / 4)) % int(n / 4), 0) << "quarter-grid steps";
            EXPECT_GE(p[a] - float(cell[a]) * voxel, float(n / 4) * voxel - 1e-3f);
            EXPECT_LE(p[a] - float(cell[a]) * voxel, float(3 * n / 4) * voxel + 1e-3f);
        }
    }
    // Within a step the corner stays; across one it moves by a step.
    EXPECT_EQ(sharedGridCell(eye, voxel, n), sharedGridCell(eye + glm::vec3(0.0f, 0.0f, 4.0f), voxel, n));
    EXPECT_EQ(sharedGridCell(eye + glm::vec3(0.0f, 0.0f, 7.0f), voxel, n).z,
              sharedGridCell(eye, voxel, n).z + int(n / 4));
}

// Halton cosine-lobe bounce directions: unit, in the upper hemisphere, mean cosine 2/3 (the
// cosine-weighted mean of cos), different from one generation to the next.
TEST(VplSampling, BounceDirectionsAreCosineDistributed) {
    for (uint32_t g : {1u, 2u, 3u}) {
        const std::vector<glm::vec3> d = bounceSampleDirections(1024, g);
        ASSERT_EQ(d.size(), 1024u);
        double meanCos = 0.0;
        for (const glm::vec3& v : d) {
            EXPECT_NEAR(glm::length(v), 1.0f, 1e-5f);
            EXPECT_GE(v.z, 0.0f);
            meanCos += v.z;
        }
        EXPECT_NEAR(meanCos / 1024.0, 2.0 / 3.0, 0.01) << g;
    }
    EXPECT_NE(bounceSampleDirections(4, 1)[1], bounceSampleDirections(4, 2)[1]);
}

namespace {
float maxColumnDiff(const glm::mat3& a, const glm::mat3& b) {
    float m = 0.0f;
    for (int c = 0; c < 3; ++c)
        m = std::max(m, glm::length(a[c] - b[c]));
    return m;
}
} // namespace

TEST(VplSampling, SpotFrameIsOrthonormalAndFollowsTheAxis) {
    glm::mat3 down = spotFrame({0.0f, -1.0f, 0.0f});
    EXPECT_EQ(maxColumnDiff(down, glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, -1, 0))), 0.0f);
    for (uint32_t i = 1; i <= 500; ++i) {
        glm::vec3 d = gpu::vplHaltonSphere(i);
        glm::mat3 f = spotFrame(d);
        EXPECT_NEAR(glm::length(f[2] - d), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(f[0], f[1]), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(f[0], f[2]), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(f[1], f[2]), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::length(f[0]), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::length(f[1]), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::determinant(f), 1.0f, 1e-5f); // right-handed
    }
    glm::mat3 up = spotFrame({0.0f, 1.0f, 0.0f}); // the documented singular direction still gives a frame
    EXPECT_NEAR(glm::determinant(up), 1.0f, 1e-6f);
    EXPECT_NEAR(up[2].y, 1.0f, 1e-6f);
}

// Moving the light moves its VPL directions smoothly: turning the spot axis by a small angle
// delta moves every frame axis (hence every VPL direction frame * local) by at most
// delta * (1 + tan(theta / 2)), theta = angle between -Y and the axis (the twist rate of the
// smallest rotation). Checked for axes at least 30 degrees away from the singular +Y.
TEST(VplSampling, SpotFrameTurnsSmoothlyWithTheLight) {
    const float delta = 1e-3f;
    uint32_t checked = 0;
    for (uint32_t i = 1; i <= 2000; ++i) {
        glm::vec3 d = gpu::vplHaltonSphere(i);
        float theta = std::acos(glm::clamp(-d.y, -1.0f, 1.0f));
        if (theta > glm::radians(150.0f))
            continue;
        glm::vec3 t = glm::normalize(glm::cross(d, gpu::vplHaltonSphere(i + 7919))); // some perpendicular
        glm::vec3 d2 = glm::normalize(d * std::cos(delta) + t * std::sin(delta));
        float bound = delta * (1.0f + std::tan(0.5f * theta)) * 1.01f + 2e-6f; // + float rounding
        EXPECT_LE(maxColumnDiff(spotFrame(d), spotFrame(d2)), bound) << "axis " << i;
        ++checked;
    }
    EXPECT_GT(checked, 1500u);
}

namespace {

// A sun's orthographic window, as the shadow plan builds it: a view looking along the light
// and a box of half-size `half` metres around `centre` on the plane across it.
glm::mat4 sunWindow(glm::vec3 dir, glm::vec2 centre, float half) {
    const glm::mat4 view = glm::lookAtRH(glm::vec3(0.0f), glm::normalize(dir), glm::vec3(0.0f, 0.0f, 1.0f));
    return glm::orthoRH_ZO(centre.x - half, centre.x + half, centre.y - half, centre.y + half, -1e4f, 1e4f) * view;
}

struct PlanePoint {
    glm::vec2 p;   // metres on the window's plane
    float share;   // m^2
    uint32_t slot; // index in the table
};

std::vector<PlanePoint> planePoints(const FocusedWindowSamples& s, glm::vec2 centre, float half) {
    std::vector<PlanePoint> out;
    for (uint32_t k = 0; k < s.samples.size(); ++k) {
        const glm::vec3& q = s.samples[k];
        if (std::abs(q.x) <= 1.0f && std::abs(q.y) <= 1.0f)
            out.push_back({centre + half * glm::vec2(q.x, q.y), q.z, k});
    }
    return out;
}

double focusCdfOf(double r, double R) {
    return r * r / (R * R + r * r);
}

} // namespace

// A window of 4 km with a focus radius of 16 m: a large sun window is focused, a small one not;
// the points around every camera place hold each ring's share of p(r) = 1 / (pi R^2 (1 +
// r^2/R^2)^2), the rings' areas within the lattices' discretisation, and never overfill the table.
TEST(VplSampling, FocusedWindowRingsHoldTheirShareOfTheDensity) {
    const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    const float half = 2000.0f, R = 16.0f;
    const glm::mat4 window = sunWindow(dir, glm::vec2(0.0f), half);
    EXPECT_TRUE(windowIsFocused(window, R));
    EXPECT_FALSE(windowIsFocused(sunWindow(dir, glm::vec2(0.0f), 0.7f * R), R));
    const glm::mat4 view = glm::lookAtRH(glm::vec3(0.0f), dir, glm::vec3(0.0f, 0.0f, 1.0f));
    const uint32_t N = 256;
    double worst = 0.0;
    for (int t = 0; t < 64; ++t) {
        const glm::vec3 camera(-700.0f + 23.3f * float(t), 40.0f + float(t % 5), 500.0f - 17.1f * float(t));
        const FocusedWindowSamples s = focusedWindowPoints(window, camera, R, N, 16);
        ASSERT_EQ(s.samples.size(), N);
        ASSERT_EQ(s.ids.size(), N);
        const std::vector<PlanePoint> points = planePoints(s, glm::vec2(0.0f), half);
        EXPECT_LE(points.size(), size_t(N));
        EXPECT_GE(points.size(), size_t(0.9 * N)) << "the lattices fill 97% of the table on average";
        // The camera's place on the plane, snapped to R/4 as the rings' centre is.
        const glm::vec2 place = glm::floor(glm::vec2(view * glm::vec4(camera, 1.0f)) / (0.25f * R) + 0.5f) * (0.25f * R);
        const double rings[] = {0.0, 0.5 * R, R, 2.0 * R};
        for (int k = 0; k < 3; ++k) {
            double share = 0.0;
            uint32_t count = 0;
            for (const PlanePoint& q : points) {
                const double r = glm::distance(q.p, place);
                if (r >= rings[k] && r < rings[k + 1]) {
                    share += q.share;
                    ++count;
                }
            }
            const double area = 3.14159265358979 * (rings[k + 1] * rings[k + 1] - rings[k] * rings[k]);
            worst = std::max(worst, std::abs(share / area - 1.0));
            // The ring's share of the density: 0.97 N (F(outer) - F(inner)) points.
            const double expected = 0.97 * N * (focusCdfOf(rings[k + 1], R) - focusCdfOf(rings[k], R));
            EXPECT_NEAR(double(count), expected, 0.1 * expected + 2.0) << "ring " << k;
        }
    }
    // Lattice points in a disc or ring of 50-70 of them: within 10% of its area (measured 9.4%).
    EXPECT_LT(worst, 0.10);
}

// The points belong to the world: a camera that moves within R/4 changes nothing, a step of R/4
// changes only the points that cross a ring, and a point that stays keeps its interleaved
// subset (its slot's block) and its id (its children's bounce ray).
TEST(VplSampling, FocusedWindowPointsStayPutWhileTheCameraMoves) {
    const glm::vec3 dir = glm::normalize(glm::vec3(-0.4f, -1.0f, 0.1f));
    const float half = 200.0f, R = 16.0f;
    const glm::mat4 window = sunWindow(dir, glm::vec2(3.0f, -5.0f), half);
    const glm::mat4 view = glm::lookAtRH(glm::vec3(0.0f), dir, glm::vec3(0.0f, 0.0f, 1.0f));
    const glm::vec3 right = glm::vec3(glm::inverse(view) * glm::vec4(1.0f, 0.0f, 0.0f, 0.0f));
    const uint32_t N = 256, subsets = 16;
    // A camera place in the middle of its snap cell.
    glm::vec3 camera(10.0f, 30.0f, -20.0f);
    const glm::vec2 place = glm::vec2(view * glm::vec4(camera, 1.0f));
    camera += glm::vec3(glm::inverse(view) *
                        glm::vec4(glm::floor(place / 4.0f + 0.5f) * 4.0f - place, 0.0f, 0.0f));
    const FocusedWindowSamples a = focusedWindowPoints(window, camera, R, N, subsets);
    const FocusedWindowSamples same = focusedWindowPoints(window, camera + 1.9f * right, R, N, subsets);
    EXPECT_EQ(std::memcmp(a.samples.data(), same.samples.data(), N * sizeof(glm::vec3)), 0);
    EXPECT_EQ(a.ids, same.ids);
    const FocusedWindowSamples b = focusedWindowPoints(window, camera + 4.0f * right, R, N, subsets);
    const std::vector<PlanePoint> pa = planePoints(a, glm::vec2(3.0f, -5.0f), half);
    const std::vector<PlanePoint> pb = planePoints(b, glm::vec2(3.0f, -5.0f), half);
    uint32_t kept = 0, sameSubset = 0;
    for (const PlanePoint& p : pa)
        for (const PlanePoint& q : pb)
            if (glm::distance(p.p, q.p) < 1e-3f && p.share == q.share) {
                ++kept;
                sameSubset += p.slot / (N / subsets) == q.slot / (N / subsets);
                EXPECT_EQ(a.ids[p.slot], b.ids[q.slot]);
            }
    // One step of R/4 moves each ring's boundary by 4 m, the inner rings' points are its own
    // lattice's: measured 193 of 252 points kept, 179 of them in their subset (the others had
    // overflowed a full subset into the next with room, which depends on the other points).
    EXPECT_GT(kept, uint32_t(0.7 * double(pa.size()))) << kept << " of " << pa.size();
    EXPECT_GT(sameSubset, uint32_t(0.9 * double(kept))) << sameSubset << " of " << kept;
}

// Counts that are not a multiple of the interleave's subsets, or smaller than them: the points
// go into the subsets' blocks of gi/vpl.h's order (some of them empty), none is lost for want of
// a slot in its own subset.
TEST(VplSampling, FocusedWindowFillsUnevenSubsetBlocks) {
    const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    const glm::mat4 window = sunWindow(dir, glm::vec2(0.0f), 2000.0f);
    for (uint32_t count : {8u, 250u, 256u}) {
        const FocusedWindowSamples s = focusedWindowPoints(window, glm::vec3(3.0f, 20.0f, -7.0f), 16.0f, count, 16);
        ASSERT_EQ(s.samples.size(), count);
        uint32_t points = 0;
        for (const glm::vec3& q : s.samples)
            points += std::abs(q.x) <= 1.0f && std::abs(q.y) <= 1.0f;
        // The lattices' expected fill is 0.97 N over a window that holds all but p's far tail;
        // few points round to whole lattice points (measured 6 of 8, 244 of 250, 247 of 256).
        EXPECT_GE(points, uint32_t(0.7 * count)) << count;
        EXPECT_LE(points, count);
    }
}

// The candidates' keys (vplCandidateUniform, vpl_select.comp's priority sampling): in (0, 1], and
// uniform over consecutive and hashed lattice ids alike (each tenth within 3% of its share over
// 2^16 ids, the mean within 0.005 of 1/2), so that inclusion probabilities are what they claim.
TEST(VplSampling, CandidateKeysAreUniformInTheUnitInterval) {
    for (uint32_t stride : {1u, 73856093u}) {
        std::array<uint32_t, 10> tenths{};
        double mean = 0.0;
        const uint32_t count = 1u << 16;
        for (uint32_t k = 0; k < count; ++k) {
            const float u = gpu::vplCandidateUniform(k * stride);
            ASSERT_GT(u, 0.0f);
            ASSERT_LE(u, 1.0f);
            mean += u / double(count);
            ++tenths[std::min(9u, uint32_t(u * 10.0f))];
        }
        EXPECT_NEAR(mean, 0.5, 0.005) << "stride " << stride;
        for (uint32_t t : tenths)
            EXPECT_NEAR(double(t) / count, 0.1, 0.003) << "stride " << stride;
    }
}
