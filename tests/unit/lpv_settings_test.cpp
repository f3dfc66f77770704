// LpvSettings validation: defaults are valid, out-of-range knobs are readable errors.
#include <limits>

#include <gtest/gtest.h>

#include "vkgi/lpv.hpp"

using vkgi::gi::LpvSettings;

TEST(LpvSettings, DefaultsAndLimitsAreValid) {
    EXPECT_TRUE(validate(LpvSettings{}));
    for (uint32_t grid : {1u, 16u, 32u, 64u, 128u}) {
        LpvSettings s;
        s.gridSize = grid;
        EXPECT_TRUE(validate(s)) << grid;
    }
    LpvSettings s;
    s.iterations = 0;
    EXPECT_TRUE(validate(s));
    s.iterations = 1000;
    EXPECT_TRUE(validate(s));
}

TEST(LpvSettings, OutOfRangeNamesTheField) {
    LpvSettings s;
    s.gridSize = 0;
    auto r = validate(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("gridSize = 0"), std::string::npos) << r.error().message;
    s.gridSize = 129;
    EXPECT_FALSE(validate(s));
    s = LpvSettings{};
    s.iterations = 5000;
    r = validate(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("iterations"), std::string::npos) << r.error().message;
    s = LpvSettings{};
    s.damping = -0.5f;
    EXPECT_FALSE(validate(s));
    s.damping = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(validate(s));
    s = LpvSettings{};
    s.cascades = 5;
    r = validate(s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("cascades"), std::string::npos) << r.error().message;
    for (uint32_t n : {0u, 1u, 4u}) {
        s.cascades = n;
        EXPECT_TRUE(validate(s)) << n;
    }
    s = LpvSettings{};
    for (float cell : {-0.1f, 2e4f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        s.fittedCell = cell;
        r = validate(s);
        ASSERT_FALSE(r) << cell;
        EXPECT_NE(r.error().message.find("fittedCell"), std::string::npos) << r.error().message;
    }
    for (float cell : {0.0f, 0.3f, 1e4f}) { // 0: gridSize cells
        s.fittedCell = cell;
        EXPECT_TRUE(validate(s)) << cell;
    }
    s = LpvSettings{};
    for (float cell : {0.0f, -1.0f, 2e4f, std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity()}) {
        s.cellSize = cell;
        r = validate(s);
        ASSERT_FALSE(r) << cell;
        EXPECT_NE(r.error().message.find("cellSize"), std::string::npos) << r.error().message;
    }
}
