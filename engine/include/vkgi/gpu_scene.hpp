#pragma once
// The CPU Scene uploaded to device buffers (one vertex/index buffer for all meshes, instance,
// material and light tables, base-colour textures in one 2D array) — the single GPU scene
// every rasterising pass, the voxelizer and the RSM read. A failed Vulkan call throws
// std::runtime_error naming the call and the VkResult (bad scene data is a Result error).
#include <vector>

#include "vkgi/resources.hpp"
#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"

namespace vkgi {

struct GpuDraw {
    uint32_t instance = 0; // index into the instance table
    uint32_t firstIndex = 0;
    uint32_t indexCount = 0;
    int32_t vertexOffset = 0;
    bool dynamic = false;
};

struct GpuScene {
    Buffer vertices;  // GpuVertex[]
    Buffer indices;   // uint32[]
    Buffer instances; // GpuInstance[]
    Buffer materials; // GpuMaterial[]
    Buffer lights;    // GpuLight[] (at least one element; lightCount may be 0)
    Image textures;   // RGBA8 sRGB 2D array, GI_SCENE_TEXTURE_SIZE^2 per layer (>= 1 layer)
    VkSampler textureSampler = VK_NULL_HANDLE;
    std::vector<GpuDraw> draws;       // one per Scene::instances entry, same order
    std::vector<uint32_t> meshOfDraw; // Scene mesh index of each draw (to detect topology changes)
    uint32_t lightCount = 0;
    uint64_t triangleCount = 0;
    Aabb bounds;
    VkDeviceSize bytes() const;
};

// Uploads `scene` (which must pass validateScene). Textures are resampled to the array size.
Result<GpuScene> uploadScene(Context& ctx, const Scene& scene);
// Rewrites the instance and light tables (moved objects or lights). Geometry, materials and the
// number of instances and lights must be unchanged since uploadScene (else an error says so).
Result<void> updateSceneTransforms(Context& ctx, GpuScene& gpu, const Scene& scene);
void destroyScene(Context& ctx, GpuScene& gpu);

} // namespace vkgi
