#pragma once
// The persistent state of voxel cone tracing on top of the shared VoxelGrid: the directional
// volume, the occupied-voxel list, the second bounce's buffers, and the pipelines and samplers
// of the passes that vct_passes.hpp adds to a render graph (voxel direct light into the six
// level-0 views, its mips, the per-voxel second bounce, the per-pixel trace).
// Volume layouts: shaders/include/gi/vct_passes.h.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>

#include "vkgi/pipeline.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/result.hpp"
#include "vkgi/vct.hpp"
#include "gi/vct_passes.h"
#include "voxel/voxel_grid.hpp"

namespace vkgi::gi {

class VctVolumes {
public:
    static Result<std::unique_ptr<VctVolumes>> create(Context& ctx, const VoxelGrid& grid);
    ~VctVolumes();
    VctVolumes(const VctVolumes&) = delete;
    VctVolumes& operator=(const VctVolumes&) = delete;

    // The +X, -X, +Y, -Y, +Z, -Z views as one 2D array (vct_passes.h), levels N^3 (the voxels) .. 1^3.
    const Image& directional() const { return m_directional.image; }
    // Persistent state for the graph import.
    rg::PersistentImage& directionalState() { return m_directional; }
    // Occupied-voxel list + its indirect dispatch header (vct_passes.h); `listBuilt` says
    // whether it holds the current grid's voxels (cleared when the grid is re-voxelized).
    rg::PersistentBuffer& listState() { return m_list; }
    // The second bounce's job and result buffers (gi/vct_passes.h), created at the first call.
    rg::PersistentBuffer& bounceJobsState();
    rg::PersistentBuffer& bounceResultsState();
    bool listBuilt() const { return m_listBuilt; }
    void setListBuilt(bool built) { m_listBuilt = built; }
    // What levels 0 and 1 of the directional volume hold from the last voxelizations (gi/vct_passes.h,
    // "written", "written bits"); `writtenKnown` says whether they describe them (false until the
    // first voxelization cleared both levels and these).
    rg::PersistentImage& writtenState() { return m_written; }
    rg::PersistentBuffer& writtenBitsState() { return m_writtenBits; }
    bool writtenKnown() const { return m_writtenKnown; }
    void setWrittenKnown(bool known) { m_writtenKnown = known; }
    // Clipmap levels: level 0 of the directional volume as the voxel light left it, before the
    // second bounce joins it (one mip, same layout; created at the first call). A moved level
    // shifts it back in and relights only the voxels it newly covers (docs/vct.md "Clipmap").
    // `litKnown` says whether it holds the last relight of the grid's voxels.
    rg::PersistentImage& litState();
    bool litKnown() const { return m_litKnown; }
    void setLitKnown(bool known) { m_litKnown = known; }
    // Clipmap levels: each listed voxel's second bounce (RGBA32UI N^3: rgb float bits, or one
    // rgb9e5 per side of a voxel without a normal, voxel_bounce_apply.comp) from the last relight
    // (created at the first call); a moved level's kept voxels keep it. `bounceKnown` says whether
    // it holds the last relight's.
    rg::PersistentImage& bounceState();
    // A 1^3 RGBA32UI image the bounce apply binds as the kept bounce when no voxel is kept (the
    // binding's format is the bounce volume's; never read then).
    rg::PersistentImage& keptStandIn();
    bool bounceKnown() const { return m_bounceKnown; }
    void setBounceKnown(bool known) { m_bounceKnown = known; }
    const VoxelGrid& grid() const { return m_grid; }
    uint32_t directionalLevels() const { return m_levels; }
    // First level of the mip tail (mipTail builds it and all coarser ones in one dispatch):
    // the first with at most 8 texels a side, at least 2 (level 1 runs over the occupied blocks).
    uint32_t mipTailLevel() const { return std::max(2u, m_levels - 1 > 2 ? m_levels - 3 : 0u); }
    VkDeviceSize bytes() const;

    // The cone parameters of `settings` for this grid (AO decay in 1/voxels).
    gpu::ConeParams coneParams(const VctSettings& settings, uint32_t width, uint32_t height) const;

    // The passes' pipelines (vct_passes.cpp declares and dispatches them).
    struct Pipelines {
        Pipeline compact;        // voxel_compact.comp: a touched list -> the occupied list's bits and entries
        Pipeline listAppend;     // voxel_list_append.comp: the occupied list's bits -> its entries, grid order
        Pipeline listStale;      // voxel_list_stale.comp: zeroes the views of voxels and blocks no longer listed
        Pipeline light;          // voxel_light.comp: voxel direct light, hard ray march
        Pipeline lightSoft;      // voxel_light_soft.comp: soft (cone) march through the filtered occupancy
        Pipeline lightShadowMap; // voxel_light_shadow_map.comp: the direct-light shadow atlas
        Pipeline mip;            // voxel_mip.comp: one level from the one below
        Pipeline mipList;        // voxel_mip_list.comp: level 1 at the listed blocks
        Pipeline mipListJobs;    // voxel_mip_list_jobs.comp: level 1 and the second bounce's jobs
        Pipeline mipTail;        // voxel_mip_tail.comp: the levels from mipTailLevel() on, one work group
        Pipeline bounce;         // voxel_bounce.comp: one diffuse gather per (block, class) job
        Pipeline bounceMisfits;  // voxel_bounce_misfits.comp: the misfit voxels' own gathers
        Pipeline bounceApply;    // voxel_bounce_apply.comp: the second bounce joins level 0
        Pipeline trace;          // vct_trace.comp: per-pixel cones (every f-th pixel)
        Pipeline traceRefine;    // vct_trace_refine.comp: the refine list's pixels at full resolution
        Pipeline upsample;       // vct_upsample.comp: low resolution -> full, refine list appended
        Pipeline filter;         // vct_filter.comp: one axis of the incoming diffuse light's tent
        Pipeline softShadow;     // vct_soft_shadow.comp: direct light with cone-traced visibility
        Pipeline traceClip;      // vct_trace_clip.comp: the trace through the clipmap (levels > 1)
        Pipeline traceRefineClip; // vct_trace_refine_clip.comp: the refine through the clipmap
        Pipeline bounceClip;        // voxel_bounce_clip.comp: a clipmap level's gathers through the clipmap
        Pipeline bounceMisfitsClip; // voxel_bounce_misfits_clip.comp: its misfits' gathers through the clipmap
    };
    const Pipelines& pipelines() const { return m_pipelines; }
    // The occupied-voxel list as R32_UINT texels (the hard voxel-light march reads its bits).
    VkBufferView listWords() const { return m_listWords; }
    // Samplers of the directional volume (clamp to edge: sampleDirectional, voxel_cone.glsl) and of
    // the grid's occupancy in the soft voxel-light march (transparent border).
    VkSampler sampler() const { return m_sampler; }
    VkSampler occupancySampler() const { return m_occupancySampler; }

private:
    VctVolumes(Context& ctx, const VoxelGrid& grid) : m_ctx(ctx), m_grid(grid) {}
    Context& m_ctx;
    const VoxelGrid& m_grid;
    rg::PersistentImage m_directional;
    rg::PersistentBuffer m_list;
    VkBufferView m_listWords = VK_NULL_HANDLE; // m_list as R32_UINT texels (the hard voxel-light march)
    rg::PersistentBuffer m_jobBuffer, m_resultBuffer;
    rg::PersistentImage m_written;
    rg::PersistentBuffer m_writtenBits;
    rg::PersistentImage m_lit;
    rg::PersistentImage m_bounce;
    rg::PersistentImage m_keptStandIn;
    bool m_bounceKnown = false;
    bool m_listBuilt = false;
    bool m_writtenKnown = false;
    bool m_litKnown = false;
    uint32_t m_levels = 0;
    VkSampler m_sampler = VK_NULL_HANDLE;          // directional volume: clamp to edge (sampleDirectional)
    VkSampler m_occupancySampler = VK_NULL_HANDLE; // soft voxel-light march: transparent border
    Pipelines m_pipelines;
};

} // namespace vkgi::gi
