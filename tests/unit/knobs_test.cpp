// The settings table behind the CLI flags and the bench sweeps: strict parsing, ranges, and
// that every knob really reaches its field of GiSettings.
#include <gtest/gtest.h>

#include <set>

#include "vkgi/knobs.hpp"

using namespace vkgi::gi;

TEST(Knobs, NamesAreUniqueAndDefaultsAreInRange) {
    std::set<std::string> names;
    GiSettings defaults;
    for (const Knob& k : knobs()) {
        EXPECT_TRUE(names.insert(k.name).second) << k.name;
        EXPECT_NE(k.name.find('.'), std::string::npos) << k.name << ": names are group.knob";
        if (k.kind == Knob::Kind::Enum) {
            EXPECT_EQ(k.max + 1.0, double(k.choices.size())) << k.name;
        } else if (k.kind != Knob::Kind::Bool) {
            double v = std::stod(k.get(defaults));
            EXPECT_GE(v, k.min) << k.name;
            EXPECT_LE(v, k.max) << k.name;
        }
        // Setting the default back must be accepted for every knob.
        EXPECT_TRUE(setKnob(defaults, k.name, k.get(defaults))) << k.name;
    }
}

TEST(Knobs, SetReachesTheField) {
    GiSettings s;
    ASSERT_TRUE(setKnob(s, "lpv.grid", "64"));
    EXPECT_EQ(s.lpv.gridSize, 64u);
    ASSERT_TRUE(applyKnob(s, "lpv.damping=0.25"));
    EXPECT_FLOAT_EQ(s.lpv.damping, 0.25f);
    ASSERT_TRUE(setKnob(s, "lpv.occlusion", "off"));
    EXPECT_FALSE(s.lpv.occlusion);
    ASSERT_TRUE(setKnob(s, "shadow.pcf", "2"));
    EXPECT_EQ(s.pcfRadius, 2u);
    ASSERT_TRUE(setKnob(s, "vct.occlusion", "soft"));
    EXPECT_EQ(s.vct.occlusion, VctOcclusion::RayMarchSoft);
    ASSERT_TRUE(setKnob(s, "vct.occlusion", "shadowmap"));
    EXPECT_EQ(s.vct.occlusion, VctOcclusion::ShadowMap);
    EXPECT_EQ(findKnob("vct.occlusion")->get(s), "shadowmap");
    s.technique = Technique::Lpv;
    EXPECT_EQ(describeKnobs(s),
              "grid=64 iterations=20 occlusion=off bounces=off damping=0.25 cascades=0 cell=1 fit_cell=0.3 half=on rsm_reduce=2");
}

TEST(Knobs, BadValuesAreOneLineErrorsNamingTheKnob) {
    GiSettings s;
    const GiSettings before = s;
    struct Case {
        const char *name, *value, *expect;
    } cases[] = {
        {"lpv.grid", "0", "out of range [1, 128]"},   {"lpv.grid", "129", "out of range"},
        {"lpv.grid", "-3", "not a whole number"},     {"lpv.grid", "32x", "not a whole number"},
        {"lpv.grid", "", "not a whole number"},       {"lpv.damping", "nan", "not finite"},
        {"lpv.damping", "inf", "not finite"},         {"lpv.damping", "1.5", "out of range"},
        {"lpv.damping", "0.5.1", "not a number"},     {"lpv.half", "maybe", "not on/off"},
        {"lpv.nope", "1", "unknown setting 'lpv.nope'"},
        {"vct.occlusion", "2", "not one of hard|soft|shadowmap"},
        {"vct.occlusion", "Hard", "not one of hard|soft|shadowmap"},
    };
    for (const Case& c : cases) {
        auto r = setKnob(s, c.name, c.value);
        ASSERT_FALSE(r) << c.name << "=" << c.value;
        EXPECT_NE(r.error().message.find(c.expect), std::string::npos) << r.error().message;
        EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
    }
    EXPECT_EQ(s.lpv.gridSize, before.lpv.gridSize) << "a rejected value must not change the settings";
    EXPECT_FALSE(applyKnob(s, "lpv.grid"));
}

TEST(Knobs, HelpListsEveryKnobWithItsDefault) {
    std::string help = knobHelp();
    for (const Knob& k : knobs())
        EXPECT_NE(help.find("--" + k.name), std::string::npos) << k.name;
    size_t grid = help.find("--lpv.grid");
    ASSERT_NE(grid, std::string::npos);
    std::string gridLine = help.substr(grid, help.find('\n', grid) - grid);
    EXPECT_NE(gridLine.find("(default " + std::to_string(LpvSettings{}.gridSize) + ")"), std::string::npos) << gridLine;
    EXPECT_NE(help.find("hard|soft|shadowmap"), std::string::npos);
    size_t occlusion = help.find("--vct.occlusion");
    ASSERT_NE(occlusion, std::string::npos);
    std::string occlusionLine = help.substr(occlusion, help.find('\n', occlusion) - occlusion);
    EXPECT_NE(occlusionLine.find("(default shadowmap)"), std::string::npos) << occlusionLine;
}

// The settings as a whole: the shared ones and the chosen technique's only.
TEST(Knobs, ValidateSettingsChecksTheSharedAndTheTechniquesSettings) {
    GiSettings s;
    EXPECT_TRUE(validateSettings(s));
    s.shadowMapSize = 8;
    auto r = validateSettings(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("shadowMapSize 8"), std::string::npos) << r.error().message;
    s = {};
    s.vct.gridResolution = 100; // another technique's bad value does not matter...
    EXPECT_TRUE(validateSettings(s));
    s.technique = Technique::Vct; // ...until that technique is chosen
    r = validateSettings(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("gridResolution 100"), std::string::npos) << r.error().message;
    s = {};
    s.technique = Technique::Vpl;
    s.vpl.interleave = 9;
    EXPECT_FALSE(validateSettings(s));
    s = {};
    s.technique = Technique::Lpv;
    s.lpv.gridSize = 1000;
    EXPECT_FALSE(validateSettings(s));
}
