// The GPU scene: every table read back from the device equals what the CPU scene says,
// bit for bit, and updates of moved objects/lights land in the same places.
#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/gpu_scene.hpp"
#include "engine/scene_types.h"
#include "vk_check.hpp"
#include "support/gi_render.hpp"
#include "support/gpu_fixture.hpp"

using namespace vkgi;

namespace {

class GpuSceneTest : public test::GpuTest {};

template <typename T> std::vector<T> readTable(Context& ctx, const Buffer& b) {
    auto bytes = readbackBuffer(ctx, b);
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
    return out;
}

bool sameBits(const void* a, const void* b, size_t n) { return std::memcmp(a, b, n) == 0; }

} // namespace

TEST_F(GpuSceneTest, CornellTablesMatchTheCpuSceneExactly) {
    Scene scene = test::builtinScene("cornell");
    auto uploaded = uploadScene(ctx(), scene);
    ASSERT_TRUE(uploaded) << uploaded.error().message;
    GpuScene& g = *uploaded;
    ASSERT_EQ(g.draws.size(), scene.instances.size());
    EXPECT_EQ(g.triangleCount, scene.triangleCount());
    EXPECT_EQ(g.lightCount, scene.lights.size());

    auto vertices = readTable<gpu::GpuVertex>(ctx(), g.vertices);
    auto indices = readTable<uint32_t>(ctx(), g.indices);
    auto instances = readTable<gpu::GpuInstance>(ctx(), g.instances);
    auto materials = readTable<gpu::GpuMaterial>(ctx(), g.materials);
    auto lights = readTable<gpu::GpuLight>(ctx(), g.lights);
    ASSERT_EQ(instances.size(), scene.instances.size());
    ASSERT_EQ(materials.size(), scene.materials.size());
    ASSERT_EQ(lights.size(), scene.lights.size());

    uint32_t wrong = 0;
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const Mesh& mesh = scene.meshes[inst.mesh];
        const GpuDraw& d = g.draws[i];
        ASSERT_EQ(d.indexCount, mesh.indices.size());
        EXPECT_TRUE(sameBits(&instances[i].model, &inst.transform, sizeof(glm::mat4))) << i;
        EXPECT_EQ(instances[i].info.x, mesh.material);
        // Every index, resolved through the draw's offsets, gives back the mesh's own vertex.
        for (uint32_t k = 0; k < d.indexCount; ++k) {
            uint32_t local = mesh.indices[k];
            ASSERT_EQ(indices[d.firstIndex + k], local);
            const gpu::GpuVertex& v = vertices[size_t(d.vertexOffset) + local];
            wrong += !sameBits(&v.positionU, &mesh.positions[local], sizeof(glm::vec3));
            if (!mesh.normals.empty())
                wrong += !sameBits(&v.normalV, &mesh.normals[local], sizeof(glm::vec3));
        }
        glm::mat4 normalModel = glm::transpose(glm::inverse(inst.transform));
        EXPECT_TRUE(sameBits(&instances[i].normalModel, &normalModel, sizeof(glm::mat4))) << i;
    }
    EXPECT_EQ(wrong, 0u);
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        EXPECT_EQ(materials[i].baseColor, m.baseColor);
        EXPECT_EQ(glm::vec3(materials[i].emission), m.emission);
        EXPECT_EQ(materials[i].params, glm::vec4(m.metallic, m.roughness, float(m.baseColorTexture),
                                                 m.doubleSided ? 1.0f : 0.0f));
    }
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        EXPECT_EQ(lights[i].positionType, glm::vec4(l.position, float(uint32_t(l.type))));
        EXPECT_EQ(lights[i].colorIntensity, glm::vec4(l.color, l.intensity));
        EXPECT_EQ(lights[i].cone.x, std::cos(l.innerConeAngle));
        EXPECT_EQ(lights[i].cone.y, std::cos(l.outerConeAngle));
    }
    Aabb b = scene.bounds();
    EXPECT_EQ(g.bounds.min, b.min);
    EXPECT_EQ(g.bounds.max, b.max);
    EXPECT_GT(g.bytes(), vertices.size() * sizeof(gpu::GpuVertex));
    destroyScene(ctx(), g);
}

TEST_F(GpuSceneTest, TextureIsResampledIntoTheArray) {
    Scene scene = test::builtinScene("cornell");
    // A 2x2 checker: box filtering to 256^2 must keep each quadrant's exact colour.
    Texture t;
    t.name = "checker";
    t.width = t.height = 2;
    t.rgba8 = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 10, 20, 30, 255};
    scene.textures.push_back(t);
    scene.materials[0].baseColorTexture = 0;
    auto uploaded = uploadScene(ctx(), scene);
    ASSERT_TRUE(uploaded) << uploaded.error().message;
    auto texels = readbackImage(ctx(), uploaded->textures, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    const uint32_t n = GI_SCENE_TEXTURE_SIZE;
    ASSERT_EQ(texels.size(), size_t(n) * n * 4);
    auto texel = [&](uint32_t x, uint32_t y) { return &texels[(size_t(y) * n + x) * 4]; };
    EXPECT_EQ(texel(0, 0)[0], 255);
    EXPECT_EQ(texel(n - 1, 0)[1], 255);
    EXPECT_EQ(texel(0, n - 1)[2], 255);
    EXPECT_EQ(texel(n - 1, n - 1)[0], 10);
    EXPECT_EQ(texel(n - 1, n - 1)[1], 20);
    EXPECT_EQ(texel(n - 1, n - 1)[2], 30);
    destroyScene(ctx(), *uploaded);
}

TEST_F(GpuSceneTest, UpdateMovesLightsAndInstances) {
    Scene scene = test::builtinScene("cornell");
    auto uploaded = uploadScene(ctx(), scene);
    ASSERT_TRUE(uploaded) << uploaded.error().message;
    scene.lights[0].position += glm::vec3(0.01f, -0.02f, 0.03f);
    scene.instances.back().transform = glm::translate(scene.instances.back().transform, glm::vec3(0.1f, 0, 0));
    ASSERT_TRUE(updateSceneTransforms(ctx(), *uploaded, scene));
    auto lights = readTable<gpu::GpuLight>(ctx(), uploaded->lights);
    auto instances = readTable<gpu::GpuInstance>(ctx(), uploaded->instances);
    EXPECT_EQ(glm::vec3(lights[0].positionType), scene.lights[0].position);
    EXPECT_TRUE(sameBits(&instances.back().model, &scene.instances.back().transform, sizeof(glm::mat4)));

    Scene more = scene;
    more.lights.push_back(more.lights[0]);
    auto changed = updateSceneTransforms(ctx(), *uploaded, more);
    ASSERT_FALSE(changed);
    EXPECT_NE(changed.error().message.find("light count changed"), std::string::npos) << changed.error().message;
    destroyScene(ctx(), *uploaded);
}

TEST_F(GpuSceneTest, InvalidSceneIsRejected) {
    Scene scene = test::builtinScene("cornell");
    scene.meshes[0].indices[0] = 1u << 30;
    auto uploaded = uploadScene(ctx(), scene);
    ASSERT_FALSE(uploaded);
    EXPECT_FALSE(uploaded.error().message.empty());
}
