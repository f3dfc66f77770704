#pragma once
// Helpers shared by the voxel and VCT GPU tests: a tiny GPU scene in the engine/scene_types.h
// layouts, uploads and the unit voxel grid (support/gpu_util.hpp has the barriers that
// hand-recorded tests need; the engine gets them from the render graph).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "vkgi/context.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "engine/scene_types.h"
#include "support/gpu_util.hpp"
#include "voxel/voxel_graph.hpp"
#include "voxel/voxel_grid.hpp"

namespace vkgi::test {

using gi::VoxelDraw;

// engine/scene_types.h layouts (GpuVertex, GpuInstance, GpuMaterial), written by hand here so
// the test also pins the byte layout the voxelizer reads.
struct Vertex {
    glm::vec4 positionU;
    glm::vec4 normalV;
};
struct InstanceRecord {
    glm::mat4 model;
    glm::mat4 normalModel;
    glm::uvec4 info;
};
struct MaterialRecord {
    glm::vec4 baseColor;
    glm::vec4 emission;
    glm::vec4 params;
};
static_assert(sizeof(Vertex) == sizeof(gpu::GpuVertex) && sizeof(InstanceRecord) == sizeof(gpu::GpuInstance) &&
              sizeof(MaterialRecord) == sizeof(gpu::GpuMaterial));

struct Tri {
    glm::vec3 a, b, c;
};

// A tiny GPU scene: one draw (and one instance) per triangle list.
struct TestScene {
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;
    std::vector<InstanceRecord> instances;
    std::vector<MaterialRecord> materials;
    std::vector<VoxelDraw> draws;

    uint32_t addMaterial(glm::vec3 albedo, glm::vec3 emission = glm::vec3(0.0f)) {
        materials.push_back({glm::vec4(albedo, 1.0f), glm::vec4(emission, 0.0f), glm::vec4(0.0f, 1.0f, -1.0f, 0.0f)});
        return uint32_t(materials.size() - 1);
    }
    void addDraw(const std::vector<Tri>& tris, uint32_t material, bool dynamic = false,
                 glm::mat4 model = glm::mat4(1.0f)) {
        VoxelDraw d;
        d.instance = uint32_t(instances.size());
        d.firstIndex = uint32_t(indices.size());
        d.triangleCount = uint32_t(tris.size());
        d.vertexOffset = int32_t(vertices.size());
        d.dynamic = dynamic;
        uint32_t local = 0;
        for (const Tri& t : tris) {
            glm::vec3 n = glm::cross(t.b - t.a, t.c - t.a);
            n = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f, 1.0f, 0.0f);
            for (glm::vec3 p : {t.a, t.b, t.c}) {
                vertices.push_back({glm::vec4(p, 0.0f), glm::vec4(n, 0.0f)});
                indices.push_back(local++);
            }
        }
        instances.push_back({model, glm::transpose(glm::inverse(model)), glm::uvec4(material, 0, 0, 0)});
        draws.push_back(d);
    }
};

struct GpuBuffers {
    Buffer vertices, indices, instances, materials;
};

inline Buffer uploaded(Context& ctx, const void* data, size_t bytes, const char* name) {
    Buffer b = createBuffer(ctx, {std::max<VkDeviceSize>(bytes, 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT},
                            name);
    uploadBuffer(ctx, b, data, bytes);
    return b;
}

// The scene's vertex, index, instance and material tables in device buffers.
inline GpuBuffers uploadTestScene(Context& ctx, const TestScene& scene) {
    GpuBuffers b;
    b.vertices = uploaded(ctx, scene.vertices.data(), scene.vertices.size() * sizeof(Vertex), "t.vertices");
    b.indices = uploaded(ctx, scene.indices.data(), scene.indices.size() * 4, "t.indices");
    b.instances = uploaded(ctx, scene.instances.data(), scene.instances.size() * sizeof(InstanceRecord), "t.instances");
    b.materials = uploaded(ctx, scene.materials.data(), scene.materials.size() * sizeof(MaterialRecord), "t.materials");
    return b;
}

// Builds, compiles and executes one render graph (submit + wait); any graph error fails the test.
template <typename Build> void runGraph(Context& ctx, rg::TransientPool& pool, Build&& build) {
    rg::RenderGraph graph;
    build(graph);
    auto compiled = graph.compile();
    ASSERT_TRUE(compiled.ok()) << compiled.error().message;
    ctx.submitAndWait([&](VkCommandBuffer cmd) { graph.execute(cmd, ctx, pool, nullptr); });
}

// The test scene's buffers as graph imports (last written by an upload).
inline gi::VoxelSceneHandles importScene(rg::RenderGraph& graph, const GpuBuffers& b,
                                         const std::vector<VoxelDraw>& draws) {
    return {graph.importBuffer("t.vertices", b.vertices, rg::Access::TransferWrite),
            graph.importBuffer("t.indices", b.indices, rg::Access::TransferWrite),
            graph.importBuffer("t.instances", b.instances, rg::Access::TransferWrite),
            graph.importBuffer("t.materials", b.materials, rg::Access::TransferWrite), draws};
}

// Leaves the grid volumes in GENERAL layout for readbackImage.
inline void exportGrid(rg::RenderGraph& graph, const gi::VoxelGridData& d) {
    for (rg::ImageHandle h : {d.albedo, d.normal, d.emission})
        graph.exportImage(h, rg::Access::ComputeStorageRead);
}


// A grid of n^3 unit voxels at the origin: scene coordinates are voxel coordinates. Voxel
// radiance is stored times `radianceScale`.
inline gpu::VoxelGridParams unitGrid(uint32_t n, float radianceScale = 1.0f) {
    gpu::VoxelGridParams p{};
    p.originSize = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    p.scales = glm::vec4(1.0f, radianceScale, 1.0f / radianceScale, 0.0f);
    p.dims = glm::uvec4(n, uint32_t(std::log2(n)), 0, 0);
    return p;
}


// GpuLight of engine/scene_types.h.
struct LightRecord {
    glm::vec4 positionType;
    glm::vec4 directionRange;
    glm::vec4 colorIntensity;
    glm::vec4 cone;
};
static_assert(sizeof(LightRecord) == sizeof(gpu::GpuLight));

inline float halfToFloat(uint16_t h) {
    uint32_t sign = uint32_t(h >> 15) << 31, exp = (h >> 10) & 31u, man = h & 1023u;
    if (exp == 0)
        return (sign ? -1.0f : 1.0f) * std::ldexp(float(man), -24);
    uint32_t bits = sign | ((exp == 31 ? 255u : exp + 112u) << 23) | (man << 13);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

inline uint16_t floatToHalf(float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    uint32_t sign = (bits >> 16) & 0x8000u;
    int exp = int((bits >> 23) & 255u) - 127 + 15;
    uint32_t man = bits & 0x7fffffu;
    if (exp <= 0) // the tests only upload normal-range values or zero
        return uint16_t(sign);
    if (exp >= 31)
        return uint16_t(sign | 0x7c00u);
    uint32_t h = sign | (uint32_t(exp) << 10) | (man >> 13);
    return uint16_t(h + ((man >> 12) & 1u)); // round half up
}

} // namespace vkgi::test
