#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "mesh_builder.hpp"
#include "vkgi/camera.hpp"
#include "vkgi/builtin_scenes.hpp"
#include "vkgi/scene.hpp"

using namespace vkgi;

// The path tracer's pixel ray and the rasteriser's view-projection must agree: a point on
// the ray through a pixel centre projects back to exactly that pixel centre.
TEST(Camera, PixelRayReprojectsToPixelCentre) {
    Camera cam;
    cam.position = {0.278f, 0.273f, -0.8f};
    cam.forward = {0.0f, 0.0f, 1.0f};
    cam.yfov = 2.0f * std::atan(12.5f / 35.0f);
    const uint32_t w = 64, h = 48;
    glm::mat4 vp = cam.projection(float(w) / float(h)) * cam.view();
    for (uint32_t y : {0u, 7u, 47u})
        for (uint32_t x : {0u, 31u, 63u}) {
            glm::vec3 p = cam.position + 2.5f * cam.pixelRayDirection(x, y, w, h);
            glm::vec4 clip = vp * glm::vec4(p, 1.0f);
            glm::vec2 ndc = glm::vec2(clip) / clip.w;
            EXPECT_NEAR((ndc.x * 0.5f + 0.5f) * w, x + 0.5f, 1e-3f);
            EXPECT_NEAR((ndc.y * 0.5f + 0.5f) * h, y + 0.5f, 1e-3f);
            float depth = clip.z / clip.w;
            EXPECT_GT(depth, 0.0f);
            EXPECT_LT(depth, 1.0f);
        }
}

TEST(Camera, FramingCameraSeesTheWholeBox) {
    glm::vec3 bmin(-1.0f, 0.0f, -2.0f), bmax(3.0f, 2.0f, 1.0f);
    Camera cam = framingCamera(bmin, bmax);
    glm::mat4 vp = cam.projection(1.0f) * cam.view();
    for (int i = 0; i < 8; ++i) {
        glm::vec3 c((i & 1) ? bmax.x : bmin.x, (i & 2) ? bmax.y : bmin.y, (i & 4) ? bmax.z : bmin.z);
        glm::vec4 clip = vp * glm::vec4(c, 1.0f);
        ASSERT_GT(clip.w, 0.0f);
        glm::vec3 ndc = glm::vec3(clip) / clip.w;
        EXPECT_LE(std::abs(ndc.x), 1.0f) << i;
        EXPECT_LE(std::abs(ndc.y), 1.0f) << i;
        EXPECT_GT(ndc.z, 0.0f) << i;
        EXPECT_LT(ndc.z, 1.0f) << i;
    }
}

namespace {

Scene oneMeshScene(MeshBuilder& b) {
    Scene s;
    s.materials.push_back({});
    s.meshes.push_back(b.take("m", 0));
    s.instances.push_back({});
    return s;
}

} // namespace

// A hall (walls facing in, 20 x 6 x 8 m, a door in one wall) gets a camera inside, looking down
// its long axis; a closed object (walls facing out) and an open box keep the outside view.
TEST(Camera, DefaultCameraStandsInsideInteriors) {
    MeshBuilder hall;
    hall.addBox({-10.0f, 0.0f, -4.0f}, {10.0f, 6.0f, 4.0f}, Facing::Inward, 4);
    Scene interior = oneMeshScene(hall);
    std::optional<Camera> inside = interiorCamera(interior);
    ASSERT_TRUE(inside);
    Aabb b = interior.bounds();
    for (int k = 0; k < 3; ++k) {
        EXPECT_GT(inside->position[k], b.min[k]);
        EXPECT_LT(inside->position[k], b.max[k]);
    }
    EXPECT_NEAR(inside->forward.x, 1.0f, 1e-6f); // the long axis
    EXPECT_LT(inside->position.x, -5.0f);        // backed off towards one end
    Camera viaDefault = interior.cameraOrDefault();
    EXPECT_EQ(viaDefault.position, inside->position);

    // The same box facing out is an object: seen from outside, as before.
    MeshBuilder object;
    object.addBox({-10.0f, 0.0f, -4.0f}, {10.0f, 6.0f, 4.0f}, Facing::Outward, 4);
    Scene closedObject = oneMeshScene(object);
    EXPECT_FALSE(interiorCamera(closedObject));
    EXPECT_LT(closedObject.cameraOrDefault().position.z, -4.0f);

    // A box open on two sides (a stage): too many rays escape.
    MeshBuilder stage;
    stage.addQuad({-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1});    // floor, facing up
    stage.addQuad({-1, 2, 1}, {1, 2, 1}, {1, 2, -1}, {-1, 2, -1});    // ceiling, facing down
    stage.addQuad({-1, 0, 1}, {1, 0, 1}, {1, 2, 1}, {-1, 2, 1});      // back wall, facing -z
    EXPECT_FALSE(interiorCamera(oneMeshScene(stage)));
}

// The built-in interiors, stripped of their cameras, get one inside: the hall, the sun-lit room
// (its window lets a few probe rays out) and the atrium (open to the sky). The Cornell box is
// open at the front.
TEST(Camera, BuiltinInteriorsGetACameraInside) {
    for (const char* name : {"hall", "room", "atrium", "cornell"}) {
        auto scene = makeBuiltinScene(name);
        ASSERT_TRUE(scene) << scene.error().message;
        scene->camera.reset();
        std::optional<Camera> inside = interiorCamera(*scene);
        const bool open = std::string(name) == "cornell";
        EXPECT_EQ(inside.has_value(), !open) << name;
        if (!inside)
            continue;
        Aabb b = scene->bounds();
        for (int k = 0; k < 3; ++k) {
            EXPECT_GT(inside->position[k], b.min[k]) << name;
            EXPECT_LT(inside->position[k], b.max[k]) << name;
        }
    }
}
