#pragma once
// The voxel cone tracing passes in a render graph, on top of the voxel grid's
// (voxel/voxel_graph.hpp); the persistent state they use is VctVolumes (vct_volumes.hpp).
#include <cstdint>

#include "vkgi/rg/render_graph.hpp"
#include "vkgi/vct.hpp"
#include "vct/vct_volumes.hpp"
#include "voxel/voxel_graph.hpp"

namespace vkgi::gi {

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

// What addVctPasses produces (also on the blackboard, for tests and tools).
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

// What addVctPasses adds beyond the settings.
struct VctPassOptions {
    // false: only the trace is added; it reads the radiance and mips the volumes kept from the
    // last relit frame (valid while neither the grid nor the lights changed).
    bool relight = true;
    // false: the voxel light leaves out the emission volume (the scene has no emissive material).
    bool emission = true;
    // VctOcclusion::ShadowMap reads this shadow atlas (ShadowData of vkgi/frame_data.hpp); without
    // one (graphs built by hand, no direct-light passes) the voxel light ray-marches hard shadows.
    rg::ImageHandle shadowAtlas;
    rg::BufferHandle shadowViews, lightShadows;
    VkSampler shadowSampler = VK_NULL_HANDLE;
    // Which shadow window (TechniqueModule::shadowWindows) of each directional light fits this
    // grid's box; ~0u: none, the voxel light reads the light's own layer.
    uint32_t shadowWindow = ~0u;
    // false: the glossy image is not asked for; the trace passes leave it unwritten (the
    // indirect image holds the glossy cone's share either way).
    bool glossyImage = true;
    // Clipmap levels: keep level 0 as the voxel light wrote it (VctVolumes::litState), so that
    // a later move can shift it ("gi.vct.lit.save").
    bool saveLit = false;
    // `shifted`: the grid's corner moved by `shift` voxels (|shift| < N) since its last relight,
    // which saved level 0, and no light or object changed: the saved level 0 is shifted in
    // ("gi.vct.shift") and the voxel light keeps the kept voxels whose marches the move cannot
    // change, lighting the others; the mips and the second bounce are rebuilt whole
    // (docs/vct.md "Clipmap").
    bool shifted = false;
    glm::ivec3 shift{0};
    // Clipmap levels with two bounces (`clipmap` set): once the level's first bounce and its
    // mips are built, "gi.vct.clip.lit" copies them into the level's layers of *clipmap (the
    // handle advances), and the second bounce's gathers trace through the clipmap (`clipParams`)
    // from level `clipLevel` on, so that cones leaving the level's box go on in the coarser levels.
    rg::ImageHandle* clipmap = nullptr;
    rg::BufferHandle clipParams;
    uint32_t clipLevel = 0;
};
// "gi.vct.list*" (once per voxelization), "gi.vct.light", "gi.vct.mip[k]", optionally
// "gi.vct.bounce*" + "gi.vct.bounce.mip[k]", "gi.vct.shadow" with soft shadows, and "gi.vct.trace"
// (+ upsample, refine) when `gbuffer` is given. `lights` holds `lightCount` GpuLight records.
VctOutputs addVctPasses(rg::RenderGraph& graph, VctVolumes& volumes, const VoxelGridData& grid, rg::BufferHandle lights,
                        uint32_t lightCount, const VctSettings& settings, const VctGBufferHandles* gbuffer,
                        VctPassOptions options = {});

// "gi.vct.filter.rows", "gi.vct.filter.columns" (vct_filter.comp, docs/vct.md "Filter"): the
// geometry-aware tent of side `side` (VctSettings::filter > 1) over `light`, the trace's incoming
// diffuse light (a = AO) at 1/f of the G-buffer's resolution. Returns the filtered incoming light
// at f > 1 (the upsample applies the albedo); at f = 1 the indirect radiance, the albedo and
// metallic applied with the unfiltered incoming glossy light `glossy`.
rg::ImageHandle addVctFilterPasses(rg::RenderGraph& graph, const Pipeline& pipeline, const VctGBufferHandles& g,
                                   rg::ImageHandle light, rg::ImageHandle glossy, uint32_t f, uint32_t side);

// The clipmap (VctSettings::levels > 1, vct_passes.h): the levels' directional volumes stacked
// in one volume, and its parameters.
struct VctClipmapHandles {
    rg::ImageHandle volume;  // RGBA16F 2D array, N x N, GI_VCT_DIRECTIONS N levels layers, the directional mips
    rg::BufferHandle params; // VctClipmapParams (uniform)
    // Levels 0 and 1's normal volumes, whose alpha holds the half-voxel bits (gi/voxel_grid.h) the
    // trace's skipped segments read (vct_trace_body.glsl).
    rg::ImageHandle occupancy[2];
};

// "gi.vct.clip.params": a transient uniform buffer holding `params`.
rg::BufferHandle addClipmapParamsPass(rg::RenderGraph& graph, const gpu::VctClipmapParams& params);

// `name` (default "gi.vct.clip.copy"): `level`'s directional volume (all mips) into its layers of
// `clipmap` (returned: the new version). `n` = the levels' resolution, `mips` their mip count.
rg::ImageHandle addClipmapCopyPass(rg::RenderGraph& graph, rg::ImageHandle directional, rg::ImageHandle clipmap,
                                   uint32_t level, uint32_t n, uint32_t mips, const char* name = "gi.vct.clip.copy");

// The per-pixel passes ("gi.vct.trace", and at low resolution the upsample and refine) through the
// clipmap; `level0` (the finest level) gives the grid parameters and the pipelines.
VctOutputs addVctClipmapTracePasses(rg::RenderGraph& graph, const VctVolumes& level0, const VctClipmapHandles& clip,
                                    const VctSettings& settings, const VctGBufferHandles& gbuffer, bool glossyImage);

} // namespace vkgi::gi
