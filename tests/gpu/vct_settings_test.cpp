// VctSettings validation and grid fitting (CPU only; lives with the VCT tests).
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "vkgi/vct.hpp"
#include "voxel/voxel_grid.hpp"

using namespace vkgi;
using namespace vkgi::gi;

TEST(VctSettings, DefaultsAreValid) { EXPECT_TRUE(validateVctSettings({}).ok()); }

TEST(VctSettings, BadValuesAreReadableErrors) {
    auto expectError = [](VctSettings s, const char* word) {
        auto r = validateVctSettings(s);
        ASSERT_FALSE(r.ok());
        EXPECT_NE(r.error().message.find(word), std::string::npos) << r.error().message;
    };
    VctSettings s;
    s.gridResolution = 0;
    expectError(s, "gridResolution 0");
    s.gridResolution = 48;
    expectError(s, "power of two");
    s.gridResolution = 512;
    expectError(s, "gridResolution 512");
    s = {};
    s.diffuseCones = 0;
    expectError(s, "diffuseCones 0");
    s = {};
    s.diffuseAperture = std::numeric_limits<float>::quiet_NaN();
    expectError(s, "diffuseAperture");
    s.diffuseAperture = 0.5236f; // 30 degrees: the level cap would make it read what 18.4 degrees reads
    expectError(s, "diffuseAperture 0.523");
    s = {};
    s.stepFactor = 0.0f;
    expectError(s, "stepFactor");
    s = {};
    s.bounces = 4;
    expectError(s, "bounces 4");
    s = {};
    s.shadowAperture = std::numeric_limits<float>::infinity();
    expectError(s, "shadowAperture");
    s = {};
    s.lowResFactor = 3;
    expectError(s, "lowResFactor 3");
    s = {};
    s.filter = 0;
    expectError(s, "filter 0");
    s.filter = kVctMaxFilter + 1;
    expectError(s, ("filter " + std::to_string(kVctMaxFilter + 1)).c_str());
    s = {};
    s.refineThreshold = std::numeric_limits<float>::quiet_NaN();
    expectError(s, "refineThreshold");
    s = {};
    s.occlusion = VctOcclusion(7);
    expectError(s, "occlusion 7");
    s = {};
    s.prefilter = VctPrefilter(3);
    expectError(s, "prefilter 3");
}

TEST(VoxelGridFit, LongestSideSpansNMinusOneVoxelsCentred) {
    Aabb box;
    box.extend({-1.0f, 0.0f, 2.0f});
    box.extend({3.0f, 1.0f, 2.5f});
    auto p = fitVoxelGrid(box, 32, 1.0f);
    ASSERT_TRUE(p.ok()) << p.error().message;
    float voxel = p->originSize.w;
    EXPECT_FLOAT_EQ(voxel, 4.0f / 31.0f);
    // The box's min x lies on the centre of voxel 0: origin.x + voxel / 2.
    EXPECT_NEAR(p->originSize.x + 0.5f * voxel, -1.0f, 1e-6f);
    // Other axes centred: grid centre = box centre.
    EXPECT_NEAR(p->originSize.y + 16.0f * voxel, 0.5f, 1e-6f);
    EXPECT_NEAR(p->originSize.z + 16.0f * voxel, 2.25f, 1e-6f);
    EXPECT_EQ(p->dims.x, 32u);
    EXPECT_EQ(p->dims.y, 5u);
    EXPECT_FALSE(fitVoxelGrid(Aabb{}, 32, 1.0f).ok());
    EXPECT_FALSE(fitVoxelGrid(box, 24, 1.0f).ok());
}

TEST(VoxelGridFit, RadianceScaleIsAPowerOfTwoMappingTheMaximumToTheTarget) {
    for (float l : {1e-6f, 0.3f, 1.0f, 5.0f, 1e9f}) {
        float s = chooseRadianceScale(l);
        int e;
        EXPECT_EQ(std::frexp(s, &e), 0.5f) << l; // exact power of two
        EXPECT_LE(l * s, GI_VOXEL_RADIANCE_TARGET) << l;
        EXPECT_GT(l * s, 0.5 * GI_VOXEL_RADIANCE_TARGET) << l;
    }
    EXPECT_EQ(chooseRadianceScale(0.0f), 1.0f);
    EXPECT_EQ(chooseRadianceScale(std::numeric_limits<float>::quiet_NaN()), 1.0f);
}
