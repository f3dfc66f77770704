#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/scene.hpp"

using namespace vkgi;

namespace {

struct WorldTri {
    glm::vec3 a, b, c;
    glm::vec3 na, nb, nc; // vertex normals (world)
    uint32_t mesh;
};

std::vector<WorldTri> worldTriangles(const Scene& s) {
    std::vector<WorldTri> out;
    for (const Instance& inst : s.instances) {
        const Mesh& m = s.meshes[inst.mesh];
        glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(inst.transform)));
        for (size_t i = 0; i + 2 < m.indices.size(); i += 3) {
            WorldTri t;
            glm::vec3* p[3] = {&t.a, &t.b, &t.c};
            glm::vec3* n[3] = {&t.na, &t.nb, &t.nc};
            for (int k = 0; k < 3; ++k) {
                uint32_t v = m.indices[i + k];
                *p[k] = glm::vec3(inst.transform * glm::vec4(m.positions[v], 1.0f));
                *n[k] = m.normals.empty() ? glm::vec3(0) : glm::normalize(nm * m.normals[v]);
            }
            t.mesh = inst.mesh;
            out.push_back(t);
        }
    }
    return out;
}

// A mesh is closed and consistently oriented when, after welding positions (1e-5 m grid), every
// directed edge a->b is matched by exactly one b->a and by no other a->b.
bool closedAndOriented(const std::vector<WorldTri>& tris, std::string* why) {
    std::map<std::tuple<long, long, long>, int> ids;
    auto id = [&](const glm::vec3& p) {
        auto key = std::make_tuple(std::lround(p.x * 1e5), std::lround(p.y * 1e5), std::lround(p.z * 1e5));
        return ids.emplace(key, int(ids.size())).first->second;
    };
    std::map<std::pair<int, int>, int> directed;
    for (const WorldTri& t : tris) {
        int v[3] = {id(t.a), id(t.b), id(t.c)};
        for (int k = 0; k < 3; ++k)
            directed[{v[k], v[(k + 1) % 3]}]++;
    }
    for (const auto& [e, n] : directed) {
        auto rev = directed.find({e.second, e.first});
        if (n != 1 || rev == directed.end() || rev->second != 1) {
            *why = "edge " + std::to_string(e.first) + "->" + std::to_string(e.second) + " used " + std::to_string(n) +
                   " times, reverse " + std::to_string(rev == directed.end() ? 0 : rev->second);
            return false;
        }
    }
    return true;
}

Scene make(const std::string& name, const BuiltinSceneParams& p = {}) {
    Result<Scene> r = makeBuiltinScene(name, p);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(r).value() : Scene{};
}

glm::vec3 faceNormal(const WorldTri& t) { return glm::normalize(glm::cross(t.b - t.a, t.c - t.a)); }
glm::vec3 centroid(const WorldTri& t) { return (t.a + t.b + t.c) / 3.0f; }

} // namespace

TEST(BuiltinScenes, EveryBuiltinValidatesAndIsSane) {
    std::vector<std::string> names = builtinSceneNames();
    ASSERT_FALSE(names.empty());
    EXPECT_EQ(names.front(), "cornell");
    for (const std::string& name : names) {
        SCOPED_TRACE(name);
        Scene s = make(name);
        EXPECT_EQ(s.name, name);
        EXPECT_TRUE(validateScene(s).ok());
        EXPECT_TRUE(s.camera.has_value());
        EXPECT_GT(s.triangleCount(), 0u);
        EXPECT_TRUE(!s.lights.empty() || s.hasEmission()) << "scene is unlit";
        for (const Light& l : s.lights)
            EXPECT_GT(l.intensity, 0.0f);
        // Winding agrees with the stored normals (CCW seen from the side the normal points to),
        // and no triangle is degenerate.
        for (const WorldTri& t : worldTriangles(s)) {
            glm::vec3 c = glm::cross(t.b - t.a, t.c - t.a);
            ASSERT_GT(glm::length(c), 1e-10f) << "degenerate triangle in mesh " << t.mesh;
            glm::vec3 n = glm::normalize(c);
            ASSERT_GT(glm::dot(n, t.na), 0.0f) << "mesh " << t.mesh;
            ASSERT_GT(glm::dot(n, t.nb), 0.0f) << "mesh " << t.mesh;
            ASSERT_GT(glm::dot(n, t.nc), 0.0f) << "mesh " << t.mesh;
        }
        // The camera is inside the scene bounds or in front of them, and looks at geometry.
        Aabb b = s.bounds();
        ASSERT_TRUE(b.valid());
        EXPECT_TRUE(std::isfinite(b.extent().x + b.extent().y + b.extent().z));
    }
}

TEST(BuiltinScenes, UnknownNameListsValidNames) {
    Result<Scene> r = makeBuiltinScene("cornel");
    ASSERT_FALSE(r.ok());
    for (const std::string& n : builtinSceneNames())
        EXPECT_NE(r.error().message.find(n), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("cornel'"), std::string::npos);
    EXPECT_EQ(r.error().message.find('\n'), std::string::npos);
}

TEST(BuiltinScenes, BadParametersAreRejected) {
    BuiltinSceneParams p;
    p.furnaceAlbedo = 1.0f; // Le / (1 - albedo) diverges
    EXPECT_FALSE(makeBuiltinScene("furnace", p).ok());
    p = {};
    p.sphereLightIntensity = std::nanf("");
    EXPECT_FALSE(makeBuiltinScene("sphere", p).ok());
    p = {};
    p.furnaceEmission = -1.0f;
    EXPECT_FALSE(makeBuiltinScene("furnace", p).ok());
}

TEST(BuiltinScenes, CornellMatchesPublishedData) {
    Scene s = make("cornell");
    Aabb b = s.bounds();
    // Published extremes (mm): x 0..556 (ceiling/left wall top), y 0..548.8, z 0..559.2.
    EXPECT_NEAR(b.min.x, 0.0f, 1e-3f);
    EXPECT_NEAR(b.max.x, 0.556f, 1e-3f);
    EXPECT_NEAR(b.min.y, 0.0f, 1e-3f);
    EXPECT_NEAR(b.max.y, 0.5488f, 1e-3f);
    EXPECT_NEAR(b.min.z, 0.0f, 1e-3f);
    EXPECT_NEAR(b.max.z, 0.5592f, 1e-3f);
    // Block heights and a published corner of each block and of the floor.
    auto hasVertex = [&](const glm::vec3& p) {
        for (const WorldTri& t : worldTriangles(s))
            for (const glm::vec3& q : {t.a, t.b, t.c})
                if (glm::length(q - p) < 1e-3f)
                    return true;
        return false;
    };
    EXPECT_TRUE(hasVertex({0.5496f, 0.0f, 0.5592f}));  // floor, back left
    EXPECT_TRUE(hasVertex({0.290f, 0.165f, 0.114f}));  // short block top
    EXPECT_TRUE(hasVertex({0.472f, 0.330f, 0.406f}));  // tall block top
    EXPECT_TRUE(hasVertex({0.423f, 0.0f, 0.247f}));    // tall block foot
    EXPECT_FALSE(hasVertex({0.278f, 0.273f, 0.0f}));   // the front stays open: no wall at z = 0
    // 5 walls x 2 + 2 blocks x (4 sides + top) x 2 triangles.
    EXPECT_EQ(s.triangleCount(), 10u + 20u);
    // Camera: published position, +z, vfov 2 atan(12.5 / 35).
    ASSERT_TRUE(s.camera);
    EXPECT_NEAR(glm::length(s.camera->position - glm::vec3(0.278f, 0.273f, -0.8f)), 0.0f, 1e-6f);
    EXPECT_NEAR(s.camera->forward.z, 1.0f, 1e-6f);
    EXPECT_NEAR(s.camera->yfov, 39.31f * 3.14159265f / 180.0f, 1e-4f);
    // Light: a downward spot just under the centre of the published light rectangle.
    ASSERT_EQ(s.lights.size(), 1u);
    const Light& l = s.lights[0];
    EXPECT_EQ(l.type, LightType::Spot);
    EXPECT_NEAR(l.position.x, 0.278f, 1e-4f);
    EXPECT_NEAR(l.position.z, 0.2795f, 1e-4f);
    EXPECT_LT(l.position.y, 0.5488f);
    EXPECT_GT(l.position.y, 0.5288f);
    EXPECT_NEAR(l.direction.y, -1.0f, 1e-6f);
    // Reflectances documented in the header: white/red/green.
    bool sawRed = false, sawGreen = false;
    for (const Material& m : s.materials) {
        sawRed |= glm::length(glm::vec3(m.baseColor) - glm::vec3(0.63f, 0.065f, 0.05f)) < 1e-6f;
        sawGreen |= glm::length(glm::vec3(m.baseColor) - glm::vec3(0.14f, 0.45f, 0.091f)) < 1e-6f;
    }
    EXPECT_TRUE(sawRed && sawGreen);
}

TEST(BuiltinScenes, CornellNormalsFaceTheViewer) {
    Scene s = make("cornell");
    const glm::vec3 boxCentre(0.278f, 0.2744f, 0.2796f);
    for (const Instance& inst : s.instances) {
        const Mesh& m = s.meshes[inst.mesh];
        bool block = m.name.find("block") != std::string::npos;
        glm::vec3 blockCentre(0.0f);
        for (const glm::vec3& p : m.positions)
            blockCentre += p / float(m.positions.size());
        for (size_t i = 0; i < m.indices.size(); i += 3) {
            glm::vec3 a = m.positions[m.indices[i]], bb = m.positions[m.indices[i + 1]], c = m.positions[m.indices[i + 2]];
            glm::vec3 n = glm::normalize(glm::cross(bb - a, c - a));
            glm::vec3 mid = (a + bb + c) / 3.0f;
            if (block) // blocks face out of themselves
                EXPECT_GT(glm::dot(n, mid - blockCentre), 0.0f) << m.name;
            else // walls face into the box
                EXPECT_GT(glm::dot(n, boxCentre - mid), 0.0f) << m.name;
        }
    }
}

TEST(BuiltinScenes, CornellEmissiveHasDownwardLightQuad) {
    Scene s = make("cornell_emissive");
    EXPECT_TRUE(s.lights.empty());
    ASSERT_TRUE(s.hasEmission());
    float emissiveArea = 0.0f;
    for (const WorldTri& t : worldTriangles(s)) {
        const Material& m = s.materials[s.meshes[t.mesh].material];
        if (m.emission.x <= 0.0f)
            continue;
        emissiveArea += 0.5f * glm::length(glm::cross(t.b - t.a, t.c - t.a));
        EXPECT_NEAR(faceNormal(t).y, -1.0f, 1e-6f);
        EXPECT_NEAR(t.a.y, 0.5487f, 1e-6f);
    }
    EXPECT_NEAR(emissiveArea, 0.130f * 0.105f, 1e-6f); // published 130 x 105 mm
}

TEST(BuiltinScenes, FurnaceIsClosedAndFacesInward) {
    BuiltinSceneParams p;
    p.furnaceAlbedo = 0.3f;
    p.furnaceEmission = 2.0f;
    Scene s = make("furnace", p);
    EXPECT_TRUE(s.lights.empty());
    std::vector<WorldTri> tris = worldTriangles(s);
    std::string why;
    EXPECT_TRUE(closedAndOriented(tris, &why)) << why;
    glm::vec3 centre = s.bounds().centre();
    for (const WorldTri& t : tris) {
        EXPECT_GT(glm::dot(faceNormal(t), centre - centroid(t)), 0.0f);
        const Material& m = s.materials[s.meshes[t.mesh].material];
        EXPECT_EQ(m.baseColor, glm::vec4(0.3f, 0.3f, 0.3f, 1.0f));
        EXPECT_EQ(m.emission, glm::vec3(2.0f));
    }
    Aabb b = s.bounds();
    ASSERT_TRUE(s.camera);
    EXPECT_TRUE(glm::all(glm::greaterThan(s.camera->position, b.min)) &&
                glm::all(glm::lessThan(s.camera->position, b.max)));
}

TEST(BuiltinScenes, IntegratingSphereIsClosedInwardAndRound) {
    Scene s = make("sphere");
    std::vector<WorldTri> tris = worldTriangles(s);
    EXPECT_EQ(tris.size(), 5120u); // 20 * 4^4
    std::string why;
    EXPECT_TRUE(closedAndOriented(tris, &why)) << why;
    float minCentroidRadius = 1.0f;
    for (const WorldTri& t : tris) {
        for (const glm::vec3& p : {t.a, t.b, t.c})
            EXPECT_NEAR(glm::length(p), 1.0f, 1e-5f);
        EXPECT_LT(glm::dot(faceNormal(t), centroid(t)), 0.0f); // inward
        EXPECT_LT(glm::dot(t.na, t.a), 0.0f);
        minCentroidRadius = std::min(minCentroidRadius, glm::length(centroid(t)));
    }
    // The facets sag below the true sphere by at most 0.12% of r (documented in the header).
    EXPECT_GT(minCentroidRadius, 0.9988f);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Point);
    EXPECT_EQ(s.lights[0].position, glm::vec3(0.0f));
    ASSERT_TRUE(s.camera);
    EXPECT_LT(glm::length(s.camera->position), 0.9f);
}

namespace {

// Möller-Trumbore; returns the hit distance or a negative value.
float intersect(const glm::vec3& o, const glm::vec3& d, const WorldTri& t) {
    glm::vec3 e1 = t.b - t.a, e2 = t.c - t.a, p = glm::cross(d, e2);
    float det = glm::dot(e1, p);
    if (std::abs(det) < 1e-12f)
        return -1.0f;
    float inv = 1.0f / det;
    glm::vec3 s = o - t.a;
    float u = glm::dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f)
        return -1.0f;
    glm::vec3 q = glm::cross(s, e1);
    float v = glm::dot(d, q) * inv;
    if (v < 0.0f || u + v > 1.0f)
        return -1.0f;
    return glm::dot(e2, q) * inv;
}

bool occluded(const std::vector<WorldTri>& tris, const glm::vec3& o, const glm::vec3& d) {
    for (const WorldTri& t : tris)
        if (intersect(o, d, t) > 1e-4f)
            return true;
    return false;
}

} // namespace

TEST(BuiltinScenes, RoomSunEntersOnlyThroughTheWindowsOntoTheFloor) {
    Scene s = make("room");
    ASSERT_EQ(s.lights.size(), 1u);
    const Light& sun = s.lights[0];
    ASSERT_EQ(sun.type, LightType::Directional);
    std::vector<WorldTri> tris = worldTriangles(s);
    const glm::vec3 toSun = -sun.direction;
    // Trace back from the centre of each window opening (x = 0, y = 1.6, z = 1.5 / 3.5) along
    // the sun direction: the ray must reach the floor, and that floor point must see the sun.
    int litFloorSamples = 0;
    for (float zw : {1.5f, 3.5f}) {
        glm::vec3 w(0.0f, 1.6f, zw);
        float tFloor = -w.y / sun.direction.y;
        glm::vec3 hit = w + tFloor * sun.direction;
        EXPECT_GT(hit.x, 0.5f); // inside the room, in front of the window wall
        EXPECT_LT(hit.x, 5.5f); // and before the far wall: the patch is on the floor
        glm::vec3 p = hit + glm::vec3(0, 1e-3f, 0);
        EXPECT_FALSE(occluded(tris, p, toSun)) << "window patch at " << hit.x << ", " << hit.z << " is shadowed";
        litFloorSamples += !occluded(tris, p, toSun);
    }
    EXPECT_EQ(litFloorSamples, 2);
    // Everywhere else on a coarse grid the floor, walls and ceiling are in shadow: most of the
    // room is lit indirectly (the point of the scene).
    int lit = 0, total = 0;
    for (float x = 0.25f; x < 6.0f; x += 0.5f)
        for (float z = 0.25f; z < 5.0f; z += 0.5f) {
            glm::vec3 floorP(x, 1e-3f, z), ceilP(x, 3.0f - 1e-3f, z);
            lit += !occluded(tris, floorP, toSun);
            EXPECT_TRUE(occluded(tris, ceilP, toSun)) << x << ", " << z;
            total += 1;
        }
    for (float y = 0.25f; y < 3.0f; y += 0.5f)
        for (float z = 0.25f; z < 5.0f; z += 0.5f)
            EXPECT_TRUE(occluded(tris, {6.0f - 1e-3f, y, z}, toSun)) << "far wall " << y << ", " << z;
    EXPECT_GT(lit, 0);
    EXPECT_LT(lit, total / 5) << "sun patches should cover a small part of the floor";
}

TEST(BuiltinScenes, BunnyIsClosedAndStandsInTheBox) {
    Scene s = make("bunny_box");
    const Mesh* bunny = nullptr;
    for (const Mesh& m : s.meshes)
        if (m.name == "bunny")
            bunny = &m;
    ASSERT_NE(bunny, nullptr);
    EXPECT_GE(bunny->triangleCount(), 2000u);
    EXPECT_LE(bunny->triangleCount(), 10000u);
    std::vector<WorldTri> tris;
    for (const WorldTri& t : worldTriangles(s))
        if (&s.meshes[t.mesh] == bunny)
            tris.push_back(t);
    std::string why;
    EXPECT_TRUE(closedAndOriented(tris, &why)) << why;
    // Closed and outward: the divergence theorem gives a positive volume.
    double volume = 0.0;
    for (const WorldTri& t : tris)
        volume += glm::dot(t.a, glm::cross(t.b, t.c)) / 6.0;
    EXPECT_GT(volume, 0.0);
    Aabb b;
    for (const glm::vec3& p : bunny->positions)
        b.extend(p);
    EXPECT_NEAR(b.min.y, 0.0f, 1e-6f); // rests on the floor
    EXPECT_GT(b.min.x, 0.0f);
    EXPECT_LT(b.max.x, 0.5496f);
    EXPECT_GT(b.min.z, 0.0f);
    EXPECT_LT(b.max.z, 0.5592f);
    EXPECT_LT(b.max.y, 0.5488f);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Spot);
    // The spot axis passes over the bunny: aimed within its outer cone.
    glm::vec3 toBunny = glm::normalize(b.centre() - s.lights[0].position);
    EXPECT_GT(glm::dot(toBunny, s.lights[0].direction), std::cos(s.lights[0].outerConeAngle));
}

TEST(BuiltinScenes, AtriumSizeAndSun) {
    Scene s = make("atrium");
    EXPECT_GE(s.triangleCount(), 5000u);
    EXPECT_LE(s.triangleCount(), 30000u);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_EQ(s.lights[0].type, LightType::Directional);
    EXPECT_LT(s.lights[0].direction.y, -0.5f);
    Aabb b = s.bounds();
    ASSERT_TRUE(s.camera);
    const glm::vec3& c = s.camera->position;
    EXPECT_TRUE(c.x > b.min.x && c.x < b.max.x && c.z > b.min.z && c.z < b.max.z);
    EXPECT_LT(c.y, 2.0f); // ground level
    std::set<std::string> banners;
    for (const Mesh& m : s.meshes)
        if (m.name.rfind("atrium_banner", 0) == 0)
            banners.insert(s.materials[m.material].name);
    EXPECT_EQ(banners.size(), 3u); // red, green and blue
    // The courtyard centre sees the sun; the gallery floor under the roof does not.
    std::vector<WorldTri> tris = worldTriangles(s);
    EXPECT_FALSE(occluded(tris, {0.0f, 1e-3f, 0.0f}, -s.lights[0].direction));
    EXPECT_TRUE(occluded(tris, {6.0f, 1e-3f, 0.0f}, -s.lights[0].direction));
}
