// LPV placement: a grid fitted to the lit region with one cell of margin, the lit region of
// ranged point/spot lights, and camera-following cascades snapped to whole cells.
#include <cmath>
#include <algorithm>
#include <limits>

#include <gtest/gtest.h>

#include "lpv/lpv_grid.hpp"
#include "support/test_scenes.hpp"

using namespace vkgi;
using namespace vkgi::gi::lpv;

namespace {
using test::box;
} // namespace

TEST(LpvGrid, FitLeavesOneCellOfMarginAroundTheLongestSide) {
    auto g = fitLpvGrid(box({-1, 0, -2}, {1, 3, 2}), 34); // longest side 4 m over 32 cells
    ASSERT_TRUE(g) << g.error().message;
    EXPECT_FLOAT_EQ(g->origin.w, 0.125f);
    EXPECT_EQ(g->size, glm::ivec4(34, 34, 34, 0));
    glm::vec3 lo(g->origin), hi = lo + 34.0f * g->origin.w;
    EXPECT_FLOAT_EQ(lo.z, -2.0f - 0.125f); // exactly one cell of margin on the longest axis
    EXPECT_FLOAT_EQ(hi.z, 2.0f + 0.125f);
    EXPECT_FLOAT_EQ(0.5f * (lo.y + hi.y), 1.5f); // centred on the others
}

TEST(LpvGrid, DegenerateRegionsAreErrorsOrStillUsable) {
    EXPECT_FALSE(fitLpvGrid(Aabb{}, 32));
    EXPECT_FALSE(fitLpvGrid(box({0, 0, 0}, {std::numeric_limits<float>::infinity(), 1, 1}), 32));
    auto point = fitLpvGrid(box({1, 1, 1}, {1, 1, 1}), 1); // a 1^3 grid around a point
    ASSERT_TRUE(point);
    EXPECT_GT(point->origin.w, 0.0f);
    EXPECT_EQ(point->size.x, 1);
}

TEST(LpvGrid, RangedLightsOnlyLightTheirRange) {
    Aabb scene = box({-10, -10, -10}, {10, 10, 10});
    Light spot;
    spot.type = LightType::Spot;
    spot.position = {8, 0, 0};
    spot.range = 4.0f;
    Aabb lit = litRegion(scene, {spot});
    EXPECT_EQ(lit.min, glm::vec3(4, -4, -4));
    EXPECT_EQ(lit.max, glm::vec3(10, 4, 4)); // clipped to the scene
    Light sun;
    sun.type = LightType::Directional;
    EXPECT_EQ(litRegion(scene, {spot, sun}).min, scene.min); // a sun lights everything
    Light unbounded;
    unbounded.range = 0.0f; // glTF: 0 = infinite
    EXPECT_EQ(litRegion(scene, {unbounded}).max, scene.max);
    spot.position = {30, 0, 0};
    EXPECT_FALSE(litRegion(scene, {spot}).valid()); // the light reaches no geometry
}

TEST(LpvGrid, CascadesNestAndSnapToWholeCells) {
    const glm::vec3 forward(0.0f, 0.0f, -1.0f);
    auto c = fitCascades({0.3f, 1.7f, -2.2f}, forward, 0.25f, 32, 3);
    ASSERT_EQ(c.size(), 3u);
    for (size_t k = 0; k < c.size(); ++k) {
        float cell = c[k].origin.w;
        EXPECT_FLOAT_EQ(cell, 0.25f * float(1 << k));
        for (int a = 0; a < 3; ++a) {
            float o = c[k].origin[a] / cell;
            EXPECT_FLOAT_EQ(o, std::round(o)) << "level " << k << " axis " << a;
            // each level is centred a quarter of its extent (8 cells) ahead of the eye, to a cell
            glm::vec3 centre = glm::vec3(0.3f, 1.7f, -2.2f) + forward * (8.0f * cell);
            EXPECT_NEAR(c[k].origin[a] + 16.0f * cell, centre[a], cell);
        }
        if (k > 0) { // each level contains the finer one
            for (int a = 0; a < 3; ++a) {
                EXPECT_LE(c[k].origin[a], c[k - 1].origin[a]);
                EXPECT_GE(c[k].origin[a] + 32.0f * c[k].origin.w, c[k - 1].origin[a] + 32.0f * c[k - 1].origin.w);
            }
        }
    }
    // Moving the eye by less than a cell keeps the finest grid where it was.
    auto moved = fitCascades({0.31f, 1.7f, -2.2f}, forward, 0.25f, 32, 1);
    EXPECT_EQ(moved[0].origin, c[0].origin);
}

TEST(LpvGrid, CascadeWeightsSumToOneInsideTheCoarsest) {
    // Lookup weights: w_k = fade_k * prod over finer j of (1 - fade_j), fade from lpvBorderFade
    // (shared with lookup.comp). Inside the coarsest level's interior they telescope to 1.
    const glm::vec3 eye(0.3f, 1.7f, -2.2f);
    auto c = fitCascades(eye, glm::vec3(1.0f, 0.0f, 0.0f), 0.25f, 16, 3);
    double worst = 0.0;
    int interior = 0;
    for (int i = 0; i < 2000; ++i) {
        // deterministic points spread over the coarsest grid
        glm::vec3 t(std::fmod(i * 0.6180339f, 1.0f), std::fmod(i * 0.4142135f, 1.0f), std::fmod(i * 0.7320508f, 1.0f));
        glm::vec3 p = glm::vec3(c[2].origin) + t * (16.0f * c[2].origin.w);
        if (gpu::lpvBorderFade(c[2], p) < 1.0f)
            continue;
        ++interior;
        double sum = 0.0, remaining = 1.0;
        for (const auto& g : c) {
            float f = gpu::lpvBorderFade(g, p);
            sum += remaining * f;
            remaining *= 1.0 - f;
        }
        worst = std::max(worst, std::abs(sum - 1.0));
    }
    EXPECT_GT(interior, 400); // (10/16)^3 = 24% of the points lie in the interior
    EXPECT_LT(worst, 1e-6);
    // The fade is 0 in a grid's outermost cell and 1 three cells in.
    EXPECT_EQ(gpu::lpvBorderFade(c[0], glm::vec3(c[0].origin) + glm::vec3(0.5f * c[0].origin.w, 8.0f * c[0].origin.w,
                                                                           8.0f * c[0].origin.w)),
              0.0f);
    EXPECT_EQ(gpu::lpvBorderFade(c[0], glm::vec3(c[0].origin) + 8.0f * c[0].origin.w), 1.0f);
}

TEST(LpvGrid, AutomaticCascadesOnlyForACameraInsideARegionTooLargeForOneGrid) {
    // Explicit counts are kept whatever the region.
    EXPECT_EQ(cascadeCount(1, 1.0f, 100.0f, true), 1u);
    EXPECT_EQ(cascadeCount(2, 1.0f, 0.01f, false), 2u);
    // Automatic, 1 m finest cell: the coarsest of kAutoCascades levels has 4 m cells.
    const float coarsest = std::ldexp(1.0f, int(kAutoCascades) - 1);
    EXPECT_EQ(cascadeCount(0, 1.0f, 0.04f, true), 1u);       // inside a Cornell box
    EXPECT_EQ(cascadeCount(0, 1.0f, coarsest, true), 1u);    // at the bound: still the fitted grid
    EXPECT_EQ(cascadeCount(0, 1.0f, 1.01f * coarsest, true), kAutoCascades);
    EXPECT_EQ(cascadeCount(0, 1.0f, 28.0f, true), kAutoCascades); // inside a 400 m level over 14 cells
    // A camera outside the lit region sees all of it: the fitted grid, whatever its size.
    EXPECT_EQ(cascadeCount(0, 1.0f, 28.0f, false), 1u);
    // The bound follows the cell size in metres, not the region.
    EXPECT_EQ(cascadeCount(0, 0.1f, 1.0f, true), kAutoCascades);
    EXPECT_EQ(cascadeCount(0, 10.0f, 28.0f, true), 1u);
}

TEST(LpvGrid, FittedCellsFollowACellEdgeInMetresUpToTheCap) {
    // The longest side spans cells - 2 cells (fitLpvGrid), so cells = ceil(longest / maxCell) + 2.
    const Aabb cornell = box({0, 0, 0}, {0.556f, 0.549f, 0.559f});
    const Aabb room = box({-0.2f, -0.2f, -0.2f}, {6.2f, 3.2f, 5.2f}); // the room with its 0.2 m walls
    EXPECT_EQ(fittedCells(cornell, 16, 0.3f), 16u);                  // 4 cells would do: the minimum
    EXPECT_EQ(fittedCells(room, 16, 0.3f), 24u);                     // ceil(6.4 / 0.3) + 2
    auto g = fitLpvGrid(room, fittedCells(room, 16, 0.3f));
    ASSERT_TRUE(g);
    EXPECT_LE(g->origin.w, 0.3f);
    EXPECT_GT(g->origin.w, 0.29f); // 6.4 / 22
    EXPECT_EQ(fittedCells(room, 16, 0.4f), 18u);                     // ceil(16) + 2
    // 22 cells of 0.3 m span 6.6 m: a longer region cannot get 0.3 m cells and keeps the minimum.
    EXPECT_EQ(fittedCells(box({0, 0, 0}, {6.5f, 1, 1}), 16, 0.3f), kMaxFittedCells);
    EXPECT_EQ(fittedCells(box({0, 0, 0}, {6.7f, 1, 1}), 16, 0.3f), 16u);
    EXPECT_EQ(fittedCells(box({0, 0, 0}, {16, 6, 10}), 16, 0.3f), 16u); // the hall
    EXPECT_EQ(fittedCells(box({0, 0, 0}, {4e5f, 1, 1}), 16, 0.3f), 16u);
    // Off, a minimum above the cap, and regions without a size keep the minimum.
    EXPECT_EQ(fittedCells(room, 16, 0.0f), 16u);
    EXPECT_EQ(fittedCells(room, 32, 0.3f), 32u);
    EXPECT_EQ(fittedCells(room, 1, 0.3f), 24u);
    EXPECT_EQ(fittedCells(Aabb{}, 16, 0.3f), 16u);
    EXPECT_EQ(fittedCells(box({0, 0, 0}, {std::numeric_limits<float>::infinity(), 1, 1}), 16, 0.3f), 16u);
    EXPECT_EQ(fittedCells(box({1, 1, 1}, {1, 1, 1}), 16, 0.3f), 16u); // a point
}

TEST(LpvGrid, FittedIterationsKeepTheShareOfTheGridLightCrosses) {
    EXPECT_EQ(fittedIterations(20, 16, 16), 20u);
    EXPECT_EQ(fittedIterations(20, 16, 24), 30u);
    EXPECT_EQ(fittedIterations(20, 16, 18), 23u); // 22.5 rounded
    EXPECT_EQ(fittedIterations(7, 16, 16), 7u);
    EXPECT_EQ(fittedIterations(0, 16, 24), 0u);
    EXPECT_EQ(fittedIterations(4096, 1, 24), kMaxFittedIterations); // no more than the settings accept
    EXPECT_EQ(fittedIterations(300, 1, 24), kMaxFittedIterations);
}
