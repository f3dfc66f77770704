// planEmissiveSurfels (gi/src/emissive): which emitting triangle sides get surfels, how many,
// and what share of their side's flux each carries.
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "vkgi/builtin_scenes.hpp"
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

// The LPV's emitter proxies (docs/lpv.md, "Emissive surfaces"): Lambertian point sources on the
// planned surfels, whose fluxes sum to the emitters' pi Le A exactly: pi (2 x 1) for the
// one-sided triangle plus pi (0.5 x 2) for each side of the double-sided one, 4 pi per channel,
// with one surfel per side or more (4), and with fewer surfels than sides (2: grey emission
// makes the equal power shares exact per channel). Each lies on its triangle (y = 0, x, z >= 0,
// x + z <= the triangle's legs) with its side's normal: +y for fronts (the winding 0, 2, 1), -y
// for the back.
TEST(EmissiveSurfels, PointSourcesCarryTheEmittersWholeFlux) {
    const Scene scene = emitters();
    const float legs[2] = {2.0f, 1.0f};
    for (uint32_t count : {4u, 2u, 16u}) {
        const auto table = planEmissiveSurfels(scene, count);
        const auto sources = emitterPointSources(scene, count);
        ASSERT_EQ(sources.size(), table.size()) << count;
        glm::dvec3 flux(0.0);
        for (size_t k = 0; k < sources.size(); ++k) {
            const EmitterPointSource& p = sources[k];
            flux += glm::dvec3(p.flux);
            EXPECT_NEAR(p.position.y, 0.0f, 1e-6f);
            EXPECT_GE(p.position.x, -1e-6f);
            EXPECT_GE(p.position.z, -1e-6f);
            EXPECT_LE(p.position.x + p.position.z, legs[table[k].triangle.x] + 1e-5f);
            EXPECT_NEAR(p.normal.y, table[k].triangle.z == 0 ? 1.0f : -1.0f, 1e-6f) << count << " " << k;
        }
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(flux[c], 4.0 * 3.14159265358979, 1e-5) << count;
    }
}

// The emissive Cornell box: its ceiling quad (130 x 105 mm, facing down, 0.1 mm under the
// ceiling) becomes 4 sources 0.5487 m up, facing -y, inside the quad, carrying pi Le A.
TEST(EmissiveSurfels, CornellQuadBecomesDownwardPointSourcesOfItsFlux) {
    auto scene = makeBuiltinScene("cornell_emissive");
    ASSERT_TRUE(scene) << scene.error().message;
    glm::vec3 le(0.0f);
    for (const Material& m : scene->materials)
        le = glm::max(le, m.emission);
    ASSERT_GT(le.r, 0.0f);
    const auto sources = emitterPointSources(*scene, 4);
    ASSERT_EQ(sources.size(), 4u);
    glm::dvec3 flux(0.0);
    for (const EmitterPointSource& p : sources) {
        flux += glm::dvec3(p.flux);
        EXPECT_NEAR(p.position.y, 0.5487f, 1e-5f);
        EXPECT_GT(p.position.x, 0.213f);
        EXPECT_LT(p.position.x, 0.343f);
        EXPECT_GT(p.position.z, 0.227f);
        EXPECT_LT(p.position.z, 0.332f);
        EXPECT_NEAR(p.normal.y, -1.0f, 1e-6f);
    }
    const double area = 0.130 * 0.105;
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(flux[c], 3.14159265358979 * double(le[c]) * area, 1e-6 * flux[c]);
}
