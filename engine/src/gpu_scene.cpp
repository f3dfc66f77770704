#include "vkgi/gpu_scene.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vkgi/context.hpp"
#include "engine/scene_types.h"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi {

namespace {

using gpu::GpuInstance;
using gpu::GpuLight;
using gpu::GpuMaterial;
using gpu::GpuVertex;

template <typename T>
Buffer uploadArray(Context& ctx, const std::vector<T>& data, VkBufferUsageFlags usage, const char* name) {
    // Zero-length tables still get one element so descriptors stay valid.
    size_t count = std::max<size_t>(1, data.size());
    Buffer b = createBuffer(ctx, {count * sizeof(T), usage}, name);
    try {
        if (!data.empty())
            uploadBuffer(ctx, b, data.data(), data.size() * sizeof(T));
    } catch (...) { // a failed Vulkan call (VulkanError): nothing of the upload stays behind
        destroyBuffer(ctx, b);
        throw;
    }
    return b;
}

std::vector<GpuInstance> instanceTable(const Scene& scene, const std::vector<GpuDraw>& draws) {
    std::vector<GpuInstance> out;
    for (size_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        GpuInstance g{};
        g.model = inst.transform;
        g.normalModel = glm::transpose(glm::inverse(inst.transform));
        const GpuDraw& d = draws[i];
        g.info = glm::uvec4(scene.meshes[inst.mesh].material, d.firstIndex, d.indexCount, uint32_t(d.vertexOffset));
        out.push_back(g);
    }
    return out;
}

std::vector<GpuLight> lightTable(const Scene& scene) {
    std::vector<GpuLight> out;
    for (const Light& l : scene.lights) {
        GpuLight g{};
        g.positionType = glm::vec4(l.position, float(uint32_t(l.type)));
        g.directionRange = glm::vec4(glm::normalize(l.direction), l.range);
        g.colorIntensity = glm::vec4(l.color, l.intensity);
        g.cone = glm::vec4(std::cos(l.innerConeAngle), std::cos(l.outerConeAngle), 0.0f, 0.0f);
        out.push_back(g);
    }
    return out;
}

// Box-filtered resample of an RGBA8 texture to size x size (averaging in the stored encoding
// is a small error for sRGB data; the textures here are albedo maps, not lighting).
void resample(const Texture& t, uint32_t size, uint8_t* dst) {
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x) {
            uint32_t x0 = x * t.width / size, x1 = std::max(x0 + 1, (x + 1) * t.width / size);
            uint32_t y0 = y * t.height / size, y1 = std::max(y0 + 1, (y + 1) * t.height / size);
            uint32_t sum[4] = {0, 0, 0, 0}, n = 0;
            for (uint32_t sy = y0; sy < std::min(y1, t.height); ++sy)
                for (uint32_t sx = x0; sx < std::min(x1, t.width); ++sx, ++n)
                    for (int c = 0; c < 4; ++c)
                        sum[c] += t.rgba8[(size_t(sy) * t.width + sx) * 4 + c];
            for (int c = 0; c < 4; ++c)
                dst[(size_t(y) * size + x) * 4 + c] = uint8_t(n ? sum[c] / n : 255);
        }
}

} // namespace

VkDeviceSize GpuScene::bytes() const {
    return vertices.desc.size + indices.desc.size + instances.desc.size + materials.desc.size + lights.desc.size +
           (textures ? imageBytes(textures.desc) : 0);
}

namespace {

// The device side of uploadScene: buffers, the texture array and its sampler, into `g`. Throws
// VulkanError part-way when a Vulkan call fails; the caller frees what is in `g` by then.
void uploadResources(Context& ctx, const Scene& scene, GpuScene& g, const std::vector<GpuVertex>& vertices,
                     const std::vector<uint32_t>& indices, const std::vector<GpuMaterial>& materials) {
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    g.vertices = uploadArray(ctx, vertices, storage | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, "scene.vertices");
    g.indices = uploadArray(ctx, indices, storage | VK_BUFFER_USAGE_INDEX_BUFFER_BIT, "scene.indices");
    g.instances = uploadArray(ctx, instanceTable(scene, g.draws), storage, "scene.instances");
    g.materials = uploadArray(ctx, materials, storage, "scene.materials");
    g.lights = uploadArray(ctx, lightTable(scene), storage, "scene.lights");
    g.lightCount = uint32_t(scene.lights.size());

    const uint32_t size = GI_SCENE_TEXTURE_SIZE;
    uint32_t layers = std::max<uint32_t>(1, uint32_t(scene.textures.size()));
    std::vector<uint8_t> texels(size_t(size) * size * 4 * layers, 255);
    for (size_t i = 0; i < scene.textures.size(); ++i)
        resample(scene.textures[i], size, texels.data() + i * size * size * 4);
    ImageDesc td;
    td.format = VK_FORMAT_R8G8B8A8_SRGB;
    td.width = td.height = size;
    td.arrayLayers = layers;
    td.usage = VK_IMAGE_USAGE_SAMPLED_BIT;
    td.arrayView = true; // shaders bind a sampler2DArray, also when there is one layer
    g.textures = createImage(ctx, td, "scene.textures");
    uploadImage(ctx, g.textures, texels.data(), texels.size(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    SamplerDesc sd;
    sd.address = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    g.textureSampler = createSampler(ctx, sd);
}

} // namespace

Result<GpuScene> uploadScene(Context& ctx, const Scene& scene) {
    if (auto ok = validateScene(scene); !ok)
        return ok.error();
    GpuScene g;
    std::vector<GpuVertex> vertices;
    std::vector<uint32_t> indices;
    std::vector<uint32_t> meshFirstIndex, meshVertexOffset;
    for (const Mesh& m : scene.meshes) {
        meshFirstIndex.push_back(uint32_t(indices.size()));
        meshVertexOffset.push_back(uint32_t(vertices.size()));
        for (size_t i = 0; i < m.positions.size(); ++i) {
            glm::vec2 uv = i < m.uvs.size() ? m.uvs[i] : glm::vec2(0.0f);
            glm::vec3 n = i < m.normals.size() ? m.normals[i] : glm::vec3(0.0f, 1.0f, 0.0f);
            vertices.push_back({glm::vec4(m.positions[i], uv.x), glm::vec4(n, uv.y)});
        }
        indices.insert(indices.end(), m.indices.begin(), m.indices.end());
    }
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        const Mesh& m = scene.meshes[inst.mesh];
        g.draws.push_back({i, meshFirstIndex[inst.mesh], uint32_t(m.indices.size()),
                           int32_t(meshVertexOffset[inst.mesh]), inst.dynamic});
        g.meshOfDraw.push_back(inst.mesh);
        g.triangleCount += m.triangleCount();
    }
    std::vector<GpuMaterial> materials;
    for (const Material& m : scene.materials) {
        GpuMaterial gm{};
        gm.baseColor = m.baseColor;
        gm.emission = glm::vec4(m.emission, 0.0f);
        gm.params = glm::vec4(m.metallic, m.roughness, float(m.baseColorTexture), m.doubleSided ? 1.0f : 0.0f);
        materials.push_back(gm);
    }
    try {
        uploadResources(ctx, scene, g, vertices, indices, materials);
    } catch (...) { // a failed Vulkan call part-way: free what was made, then report it
        destroyScene(ctx, g);
        throw;
    }
    g.bounds = scene.bounds();
    return g;
}

Result<void> updateSceneTransforms(Context& ctx, GpuScene& g, const Scene& scene) {
    if (auto ok = validateScene(scene); !ok)
        return ok.error();
    if (scene.instances.size() != g.draws.size() || scene.lights.size() != g.lightCount)
        return makeError("scene '" + scene.name + "': instance or light count changed since the upload (" +
                         std::to_string(g.draws.size()) + " instances, " + std::to_string(g.lightCount) +
                         " lights uploaded); upload the scene again");
    for (size_t i = 0; i < g.draws.size(); ++i)
        if (scene.instances[i].mesh != g.meshOfDraw[i])
            return makeError("scene '" + scene.name + "': instance " + std::to_string(i) +
                             " now uses another mesh; upload the scene again");
    auto inst = instanceTable(scene, g.draws);
    if (!inst.empty())
        uploadBuffer(ctx, g.instances, inst.data(), inst.size() * sizeof(GpuInstance));
    auto lights = lightTable(scene);
    if (!lights.empty())
        uploadBuffer(ctx, g.lights, lights.data(), lights.size() * sizeof(GpuLight));
    for (size_t i = 0; i < g.draws.size(); ++i)
        g.draws[i].dynamic = scene.instances[i].dynamic;
    g.bounds = scene.bounds();
    return {};
}

void destroyScene(Context& ctx, GpuScene& g) {
    destroyBuffer(ctx, g.vertices);
    destroyBuffer(ctx, g.indices);
    destroyBuffer(ctx, g.instances);
    destroyBuffer(ctx, g.materials);
    destroyBuffer(ctx, g.lights);
    destroyImage(ctx, g.textures);
    if (g.textureSampler)
        vkDestroySampler(ctx.device(), g.textureSampler, nullptr);
    g = GpuScene{};
}

} // namespace vkgi
