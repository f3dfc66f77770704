// planEmissiveSurfels (gi/src/emissive): which emitting triangle sides get surfels, how many,
// and what share of their side's flux each carries.
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "emissive/emissive_surfels.hpp"

using namespace vkgi;
using namespace vkgi::gi;

namespace {

// Three triangles in one mesh per material: a one-sided emitter of area 2 (Le 1), a double-sided
// one of area 0.5 (Le 2), and a dark one that emits nothing.
Scene emitters() {
    Scene s;
    auto addTriangle = [&](float size, glm::vec3 emission, bool doubleSided) {
        Mesh m;
        m.positions = {{0, 0, 0}, {size, 0, 0}, {0, 0, size}};
        m.normals.assign(3, glm::vec3(0, 1, 0));
        m.indices = {0, 2, 1};
        Material mat;
        mat.emission = emission;
        mat.doubleSided = doubleSided;
        m.material = uint32_t(s.materials.size());
        s.materials.push_back(mat);
        s.meshes.push_back(m);
        Instance inst;
        inst.mesh = uint32_t(s.meshes.size() - 1);
        s.instances.push_back(inst);
    };
    addTriangle(2.0f, glm::vec3(1.0f), false);
    addTriangle(1.0f, glm::vec3(2.0f), true);
    addTriangle(1.0f, glm::vec3(0.0f), true);
    return s;
}

using SideKey = std::tuple<uint32_t, uint32_t, uint32_t>; // instance, triangle, side

std::map<SideKey, std::pair<uint32_t, double>> bySide(const std::vector<gpu::GpuEmissiveSurfel>& table) {
    std::map<SideKey, std::pair<uint32_t, double>> sides;
    for (const gpu::GpuEmissiveSurfel& s : table) {
        auto& e = sides[{s.triangle.x, s.triangle.y, s.triangle.z}];
        ++e.first;
        e.second += s.point.z;
        EXPECT_GE(s.point.x, 0.0f);
        EXPECT_LE(s.point.x, 1.0f);
        EXPECT_GE(s.point.y, 0.0f);
        EXPECT_LE(s.point.y, 1.0f);
    }
    return sides;
}

} // namespace

// 16 surfels over the sides of power 2 x 3 = 6 (one-sided) and 0.5 x 6 = 3 twice (both sides of
// the double-sided triangle): one each, the 13 others by power (6.5, 3.25, 3.25 -> 7, 3, 3 by
// largest remainders, ties in side order), and each side's weights sum to 1.
TEST(EmissiveSurfels, EverySideGetsSurfelsByPowerAndItsWholeFlux) {
    const auto table = planEmissiveSurfels(emitters(), 16);
    ASSERT_EQ(table.size(), 16u);
    const auto sides = bySide(table);
    ASSERT_EQ(sides.size(), 3u) << "the one-sided triangle, both sides of the double-sided one, not the dark one";
    const SideKey front0{0, 0, 0}, front1{1, 0, 0}, back1{1, 0, 1};
    ASSERT_TRUE(sides.count(front0) && sides.count(front1) && sides.count(back1));
    EXPECT_EQ(sides.at(front0).first, 8u);
    EXPECT_EQ(sides.at(front1).first + sides.at(back1).first, 8u);
    EXPECT_GE(sides.at(front1).first, 4u);
    EXPECT_GE(sides.at(back1).first, 4u);
    for (const auto& [key, side] : sides)
        EXPECT_NEAR(side.second, 1.0, 1e-6) << "weights of one side sum to 1";
}

// Fewer surfels than sides: every surfel carries count-th of the total power, so the weights x
// side powers sum to the total (here 2 surfels over 3 sides of power 6, 3, 3).
TEST(EmissiveSurfels, FewerSurfelsThanSidesCarryEqualShares) {
    const auto table = planEmissiveSurfels(emitters(), 2);
    ASSERT_EQ(table.size(), 2u);
    const double power[2][2] = {{6.0, 0.0}, {3.0, 3.0}};
    double total = 0.0;
    for (const gpu::GpuEmissiveSurfel& s : table) {
        const double p = power[s.triangle.x][s.triangle.z];
        EXPECT_NEAR(s.point.z * p, 6.0, 1e-5) << "each carries half of the total power 12";
        total += s.point.z * p;
    }
    EXPECT_NEAR(total, 12.0, 1e-5);
}

// Nothing emits, or no surfel is asked for: an empty table.
TEST(EmissiveSurfels, NoEmissionGivesNoSurfel) {
    Scene s = emitters();
    EXPECT_EQ(planEmissiveSurfels(s, 0).size(), 0u);
    for (Material& m : s.materials)
        m.emission = glm::vec3(0.0f);
    EXPECT_EQ(planEmissiveSurfels(s, 16).size(), 0u);
}
