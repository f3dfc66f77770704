#pragma once
// Voxel cone tracing passes on top of the shared VoxelGrid: voxel direct light into the six
// level-0 views, anisotropic radiance mips (one pass per level), the per-voxel second bounce
// and the per-pixel trace.
// Pass bodies only record dispatches; the render graph orders them and places the barriers.
// Volume layouts: shaders/include/gi/vct_passes.h.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>

#include "engine/pipeline.hpp"
#include "engine/resources.hpp"
#include "engine/result.hpp"
#include "gi/vct.hpp"
#include "gi/vct_passes.h"
#include "voxel/voxel_grid.hpp"

namespace vkgi::gi {

// The G-buffer images the trace reads (frame_data.hpp layouts) and the images it writes.
struct VctTraceTargets {
    const Image* position = nullptr; // RGBA32F, w = 1 on geometry
    const Image* normal = nullptr;   // RGBA16F, w = roughness
    const Image* albedo = nullptr;   // RGBA16F, w = metallic
    const Image* indirect = nullptr; // RGBA32F out: rgb indirect radiance (nits), a = AO
    const Image* glossy = nullptr;   // RGBA32F out: glossy cone radiance (nits)
    VkBuffer refineList = VK_NULL_HANDLE; // the pixels the refine traces (upsample's list; trace zeroes its header)
    const Image* emission = nullptr; // RGBA32F G-buffer emission (soft shadows)
    const Image* direct = nullptr;   // RGBA32F out: direct light with cone-traced shadows (soft shadows)
};

// Which pixels a trace dispatch covers.
enum class VctTraceMode {
    Grid,   // every f-th pixel into the 1/f-resolution targets (f = push.lowRes.x; 1 = all)
    Refine, // the pixels of targets.refineList into the full-resolution targets
};

// The direct-light shadow atlas for VctOcclusion::ShadowMap (gi/direct_types.h layouts).
struct VctShadowInputs {
    VkBuffer lightShadows = VK_NULL_HANDLE; // GpuLightShadow[light]
    VkBuffer views = VK_NULL_HANDLE;        // GpuShadowView[layer]
    const Image* atlas = nullptr;           // depth 2D array, sampled with `compareSampler`
    VkSampler compareSampler = VK_NULL_HANDLE;
    VkImageLayout atlasLayout = VK_IMAGE_LAYOUT_UNDEFINED;
};

class VctVolumes {
public:
    static Result<std::unique_ptr<VctVolumes>> create(Context& ctx, const VoxelGrid& grid);
    ~VctVolumes();
    VctVolumes(const VctVolumes&) = delete;
    VctVolumes& operator=(const VctVolumes&) = delete;

    // The +X, -X, +Y, -Y, +Z, -Z views as one 2D array (vct_passes.h), levels N^3 (the voxels) .. 1^3.
    const Image& aniso() const { return m_aniso.image; }
    // Persistent state for the graph import.
    rg::PersistentImage& anisoState() { return m_aniso; }
    // Occupied-voxel list + its indirect dispatch header (vct_passes.h); `listBuilt` says
    // whether it holds the current grid's voxels (cleared when the grid is re-voxelized).
    rg::PersistentBuffer& listState() { return m_list; }
    // The second bounce's job and result buffers (gi/vct_passes.h), created at the first call.
    rg::PersistentBuffer& bounceJobsState();
    rg::PersistentBuffer& bounceResultsState();
    bool listBuilt() const { return m_listBuilt; }
    void setListBuilt(bool built) { m_listBuilt = built; }
    // What levels 0 and 1 of aniso() hold from the last voxelizations (gi/vct_passes.h,
    // "written", "written bits"); `writtenKnown` says whether they describe them (false until the
    // first voxelization cleared both levels and these).
    rg::PersistentImage& writtenState() { return m_written; }
    rg::PersistentBuffer& writtenBitsState() { return m_writtenBits; }
    bool writtenKnown() const { return m_writtenKnown; }
    void setWrittenKnown(bool known) { m_writtenKnown = known; }
    const VoxelGrid& grid() const { return m_grid; }
    uint32_t anisoLevels() const { return m_levels; }
    // First level of the mip tail (recordMip builds it and all coarser ones in one dispatch):
    // the first with at most 8 texels a side, at least 2 (level 1 runs over the occupied blocks).
    uint32_t mipTailLevel() const { return std::max(2u, m_levels - 1 > 2 ? m_levels - 3 : 0u); }
    VkSampler sampler() const { return m_sampler; }
    VkDeviceSize bytes() const;

    // The cone parameters of `settings` for this grid (AO decay in 1/voxels).
    gpu::ConeParams coneParams(const VctSettings& settings, uint32_t width, uint32_t height) const;

    // Storage layouts are GENERAL; `sampledLayout` is the layout of the images read through a
    // sampler (GENERAL in hand-recorded tests, what the graph chose inside a pass).
    // The list's header and "listed" bits := 0 (transfer write; `list` is the buffer of listState()).
    void recordClearList(VkCommandBuffer cmd, VkBuffer list) const;
    // The voxels of a touched list of the grid (gi/voxel_passes.h; indirect over it) -> list,
    // each voxel and 2^3 block once (its header and bits cleared before).
    void recordCompact(VkCommandBuffer cmd, VkBuffer touched) const;
    // The list's bits (recordCompact) -> its voxel and block entries in grid order (storage read-write).
    void recordListAppend(VkCommandBuffer cmd) const;
    // Levels 0 and 1 of aniso() (in `layout`), the written image (in `writtenLayout`) and the
    // written bits := 0 (transfer writes), at the first voxelization: the voxel light and the
    // bounce apply write level 0, the level-1 mip level 1, at listed voxels / blocks only, and later
    // voxelizations zero only what went stale (recordListStale, recordLight).
    void recordClearLevels01(VkCommandBuffer cmd, VkImageLayout layout, VkImageLayout writtenLayout) const;
    // After recordListAppend: zeroes the level-0 views and level-1 views of the voxels and blocks
    // the last list held and the new one does not, and their written (storage read-write), and
    // keeps the new list's bits as the written bits.
    void recordListStale(VkCommandBuffer cmd) const;
    // grid volumes + lights (+ the emission volume when `emission`) -> the six level-0 views of
    // aniso() at the listed voxels (indirect dispatch over the list); reads and updates the
    // written image (storage read-write).
    // `shadow` (non-null) selects the shadow-atlas variant, else `occlusion` the ray march.
    void recordLight(VkCommandBuffer cmd, VkBuffer lights, uint32_t lightCount, VctOcclusion occlusion,
                     VkImageLayout sampledLayout, bool emission = true,
                     const VctShadowInputs* shadow = nullptr) const;
    // aniso level `level` (>= 1) from level - 1; level 1 at the listed occupied blocks only
    // (indirect over the list; the others keep their zeros: recordClearLevels01, recordListStale); from
    // mipTailLevel() on, that level and all coarser ones (one work group). With `jobs` (level 1
    // only, cleared by recordClearBounceJobs) it also lists the second bounce's jobs: the normal
    // classes of the listed blocks' voxels (storage read-write).
    void recordMip(VkCommandBuffer cmd, uint32_t level, VkBuffer jobs = VK_NULL_HANDLE) const;
    // Second bounce (gi/vct_passes.h, docs/vct.md); the gathers read aniso() (direct light
    // and its mips). `jobs` is the buffer of bounceJobsState(), its job list built by recordMip.
    // Clear: the job header, class masks and misfit bits before the level-1 mip (transfer writes).
    void recordClearBounceJobs(VkCommandBuffer cmd, VkBuffer jobs) const;
    // Blocks: one diffuse gather per job -> `results`, and the misfit list (indirect).
    void recordBounceBlocks(VkCommandBuffer cmd, const gpu::ConeParams& cones, VkBuffer jobs, VkBuffer results,
                            VkImageLayout sampledLayout) const;
    // Misfits: albedo * their own gather -> `bounce` (N^3 RGBA16F) at the misfit voxels (indirect).
    void recordBounceMisfits(VkCommandBuffer cmd, const gpu::ConeParams& cones, VkBuffer jobs, const Image& bounce,
                             VkImageLayout sampledLayout) const;
    // Apply, after the misfits: albedo * the gathers of its class (a misfit: `misfits` at it)
    // joins level 0 of aniso() at the listed voxels (storage read-write).
    void recordBounceApply(VkCommandBuffer cmd, VkBuffer jobs, VkBuffer results, const Image& misfits) const;
    // Per-pixel trace through aniso(). The grid mode also zeroes the header of targets.refineList
    // (the upsample's and the refine's list; a header-only buffer at f = 1).
    void recordTrace(VkCommandBuffer cmd, VctTraceMode mode, const gpu::VctTracePush& push,
                     const VctTraceTargets& targets, VkImageLayout sampledLayout) const;
    // Direct light of `lightCount` lights with cone-traced visibility (vct_soft_shadow.comp):
    // G-buffer position, normal, albedo, emission -> targets.direct, full resolution.
    void recordSoftShadow(VkCommandBuffer cmd, const gpu::VctShadowPush& push, VkBuffer lights,
                          const VctTraceTargets& targets, VkImageLayout sampledLayout) const;
    // Low-res indirect + glossy -> full resolution (targets.indirect/glossy), appending the
    // pixels across discontinuities to `refineList` (header zeroed by the trace). G-buffer position
    // and normal and the low-res images are read as storage images (GENERAL).
    void recordUpsample(VkCommandBuffer cmd, const gpu::VctTracePush& push, const Image& lowIndirect,
                        const Image& lowGlossy, const VctTraceTargets& targets) const;

private:
    VctVolumes(Context& ctx, const VoxelGrid& grid) : m_ctx(ctx), m_grid(grid) {}
    Context& m_ctx;
    const VoxelGrid& m_grid;
    rg::PersistentImage m_aniso;
    rg::PersistentBuffer m_list;
    VkBufferView m_listWords = VK_NULL_HANDLE; // m_list as R32_UINT texels (the hard voxel-light march)
    rg::PersistentBuffer m_jobBuffer, m_resultBuffer;
    rg::PersistentImage m_written;
    rg::PersistentBuffer m_writtenBits;
    bool m_listBuilt = false;
    bool m_writtenKnown = false;
    uint32_t m_levels = 0;
    VkSampler m_sampler = VK_NULL_HANDLE;          // directional volume: clamp to edge (sampleAniso)
    VkSampler m_occupancySampler = VK_NULL_HANDLE; // soft voxel-light march: transparent border
    Pipeline m_compact, m_listAppend, m_listStale, m_light, m_lightSoft, m_lightShadowMap, m_mip, m_mipList, m_mipTail, m_mipListJobs, m_bounce, m_bounceApply, m_bounceMisfits, m_trace, m_traceRefine,
        m_upsample, m_softShadow;
};

} // namespace vkgi::gi
