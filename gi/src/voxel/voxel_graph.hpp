#pragma once
// The voxel grid and VCT passes as render-graph passes. The grid's volumes are persistent
// resources imported into every frame's graph; passes only run when their content changes.
// Other techniques (LPV multi-bounce) get the grid from the blackboard as VoxelGridData.
#include <cstdint>
#include <vector>

#include "engine/rg/render_graph.hpp"
#include "gi/vct.hpp"
#include "voxel/vct_passes.hpp"
#include "voxel/voxel_grid.hpp"

namespace vkgi::gi {

// Blackboard entry: the shared voxel grid of this frame (layouts in gi/voxel_grid.h). Read the
// images with ComputeStorageRead or ComputeSampledRead; `params` maps world space to voxels.
struct VoxelGridData {
    rg::ImageHandle albedo;   // RGBA8: mean albedo, a = occupancy
    rg::ImageHandle normal;   // RGBA8: voxelNormalEncode(mean normal), a = occupancy
    rg::ImageHandle emission; // RGBA16F: emission * radianceScale
    rg::ImageHandle faces;    // R32UI: voxelFacesPack, the coverage of the six facing directions
    gpu::VoxelGridParams params{};
    bool changed = false; // this frame re-voxelized the grid (occupancy may differ from the last frame)
    // Touched-voxel lists (gi/voxel_passes.h) whose union is the occupied voxels: the whole
    // scene's (static scenes) or the static draws' list, and in scenes with dynamic draws the
    // dynamic draws' list (else invalid). Read with IndirectRead / ComputeStorageRead.
    rg::BufferHandle touched, touchedDynamic;
};

// The GPU scene as graph handles (engine/scene_types.h layouts) plus its draws.
struct VoxelSceneHandles {
    rg::BufferHandle vertices;
    rg::BufferHandle indices;
    rg::BufferHandle instances;
    rg::BufferHandle materials;
    std::vector<VoxelDraw> draws;
};

// What must be re-voxelized this frame.
enum class VoxelUpdate {
    None,    // nothing moved: the grid from the last frame is reused (no pass)
    Dynamic, // dynamic draws moved: clear + re-voxelize them, merge under the static voxels
             // (nothing to do in a scene without dynamic draws)
    Full,    // first frame or new scene: bake the static draws once, then as Dynamic (a scene
             // without dynamic draws is voxelized straight into the grid)
};

// Imports the grid and adds "gi.voxel.*" passes for `update`.
VoxelGridData addVoxelGridPasses(rg::RenderGraph& graph, VoxelGrid& grid, const VoxelSceneHandles& scene,
                                 VoxelUpdate update);

// Per-pixel inputs of the trace (frame_data.hpp G-buffer layouts).
struct VctGBufferHandles {
    rg::ImageHandle position; // RGBA32F
    rg::ImageHandle normal;   // RGBA16F, w = roughness
    rg::ImageHandle albedo;   // RGBA16F, w = metallic
    rg::ImageHandle emission; // RGBA32F (read by the soft-shadow pass only)
    uint32_t width = 0;
    uint32_t height = 0;
    glm::vec3 eye{0.0f};
};

struct VctOutputs {
    // The packed directional volume the trace read (vct_passes.h): level 0 the voxels' own
    // six views, levels 1.. the mips (after the bounce when bounces = 2).
    rg::ImageHandle directional;
    rg::ImageHandle indirect; // RGBA32F: rgb indirect radiance (nits), a = AO (invalid without a G-buffer)
    rg::ImageHandle glossy;   // RGBA32F: glossy cone radiance (nits)
    // RGBA32F direct light with cone-traced shadows ("gi.vct.shadow"; VctSettings::softShadows
    // with a G-buffer that has emission, else invalid): replaces the deferred pass's image.
    rg::ImageHandle direct;
};

// "gi.vct.light", "gi.vct.mip[k]", optionally "gi.vct.bounce" + "gi.vct.bounce.mip[k]", and
// "gi.vct.trace" when `gbuffer` is given. `lights` holds `lightCount` GpuLight records.
struct VctPassOptions {
    // false: only the trace is added; it reads the radiance and mips the volumes kept from the
    // last relit frame (valid while neither the grid nor the lights changed).
    bool relight = true;
    // false: the voxel light leaves out the emission volume (the scene has no emissive material).
    bool emission = true;
    // VctOcclusion::ShadowMap reads this shadow atlas (ShadowData of gi/frame_data.hpp); without
    // one (graphs built by hand, no direct-light passes) the voxel light ray-marches hard shadows.
    rg::ImageHandle shadowAtlas;
    rg::BufferHandle shadowViews, lightShadows;
    VkSampler shadowSampler = VK_NULL_HANDLE;
    // false: the glossy image is not asked for; the trace passes leave it unwritten (the
    // indirect image holds the glossy cone's share either way).
    bool glossyImage = true;
};
VctOutputs addVctPasses(rg::RenderGraph& graph, VctVolumes& volumes, const VoxelGridData& grid,
                        rg::BufferHandle lights, uint32_t lightCount, const VctSettings& settings,
                        const VctGBufferHandles* gbuffer, VctPassOptions options = {});

} // namespace vkgi::gi
