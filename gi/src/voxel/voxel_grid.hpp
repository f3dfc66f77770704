#pragma once
// The shared voxel grid: fitting, persistent volumes and the voxelization passes (clear,
// voxelize, resolve). Pass bodies only record dispatches; ordering and barriers come from the
// caller (the render graph). Layouts and encodings: shaders/include/gi/voxel_grid.h.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "engine/pipeline.hpp"
#include "engine/resources.hpp"
#include "engine/result.hpp"
#include "engine/rg/render_graph.hpp"
#include "engine/scene.hpp"
#include "gi/voxel_passes.h"

namespace vkgi::gi {

// Fits a cubic-voxel grid of `resolution`^3 around `box`: the box's longest side spans
// resolution - 1 voxels and is centred, so geometry on the box faces lies on voxel centres
// (a wall on the boundary is one voxel thick, not two). Errors on an empty or non-finite box.
Result<gpu::VoxelGridParams> fitVoxelGrid(const Aabb& box, uint32_t resolution, float radianceScale);

// Power of two that maps the brightest radiance the grid will hold into
// (GI_VOXEL_RADIANCE_TARGET / 2, GI_VOXEL_RADIANCE_TARGET], so that stored values stay within
// half-float range for any scene brightness (1e-6 .. 1e9 nits).
float chooseRadianceScale(float maxRadiance);

// Brightest radiance the voxel volumes can hold for `scene` with voxels of edge `voxelSize`:
// the largest emission, and for each light the radiance of a white Lambertian surface at half a
// voxel from it (the closest a voxel centre gets), I / (voxel/2)^2 / pi, or lux / pi.
float sceneMaxRadiance(const Scene& scene, float voxelSize);

// One draw of the GPU scene as the voxelizer sees it (mirrors GpuDraw of engine/gpu_scene.hpp).
struct VoxelDraw {
    uint32_t instance = 0;
    uint32_t firstIndex = 0;
    uint32_t triangleCount = 0;
    int32_t vertexOffset = 0;
    bool dynamic = false;
};

// GPU scene buffers in the engine/scene_types.h layouts.
struct VoxelSceneBuffers {
    VkBuffer vertices = VK_NULL_HANDLE;
    VkBuffer indices = VK_NULL_HANDLE;
    VkBuffer instances = VK_NULL_HANDLE;
    VkBuffer materials = VK_NULL_HANDLE;
    std::vector<VoxelDraw> draws;
};

// Persistent (imported into each frame's graph, which tracks their layouts across frames).
struct VoxelVolumes {
    rg::PersistentImage albedo;   // RGBA8: mean albedo, a = occupancy
    rg::PersistentImage normal;   // RGBA8: voxelNormalEncode(mean normal), a = occupancy
    rg::PersistentImage emission; // RGBA16F: emission * radianceScale
    rg::PersistentImage faces;    // R32UI: voxelFacesPack(coverage of the six facing directions)
};

// Which draws a voxelize pass takes.
enum class VoxelDrawSet { All, Static, Dynamic };

// One voxelization's choice of buffers (VoxelGrid::beginVoxelization).
struct VoxelizationPlan {
    int next = 0;          // touched list the voxelization appends to (index for listState)
    int previous = -1;     // list holding every nonzero voxel of the target volumes, or -1: clear them whole
    bool clearAccum = false; // the accumulation is not known to be zero (first voxelization): clear it
};

class VoxelGrid {
public:
    static Result<std::unique_ptr<VoxelGrid>> create(Context& ctx, const gpu::VoxelGridParams& params);
    ~VoxelGrid();
    VoxelGrid(const VoxelGrid&) = delete;
    VoxelGrid& operator=(const VoxelGrid&) = delete;

    const gpu::VoxelGridParams& params() const { return m_params; }
    uint32_t resolution() const { return m_params.dims.x; }
    // The grid every consumer reads (static and dynamic geometry merged).
    const VoxelVolumes& volumes() const { return m_volumes; }
    // Static geometry only, voxelized once (the flag volume is staticVolumes().albedo.a).
    const VoxelVolumes& staticVolumes() const { return m_static; }
    // Fixed-point records (gi/voxel_grid.h): N^3 * GI_VOXEL_ACC_STRIDE uint words, zero between
    // voxelizations.
    const Buffer& accumulation() const { return m_accum.buffer; }
    rg::PersistentBuffer& accumulationState() { return m_accum; }
    // Touched bits (bit x + N (y + N z)): set by the voxelize, listed and zeroed by the
    // touched-list pass, so zero between voxelizations like the accumulation.
    rg::PersistentBuffer& touchedBitsState() { return m_bits; }
    VoxelVolumes& volumesState() { return m_volumes; }
    VoxelVolumes& staticState() { return m_static; }
    // Touched-voxel list (gi/voxel_passes.h) of the last voxelization of `set`: All and Static
    // share a pair of lists used in turn (a scene has either), Dynamic has its own. Kept until
    // that set is re-voxelized (and the one before it, to clear its voxels).
    rg::PersistentBuffer& touchedState(VoxelDrawSet set) { return m_lists[listIndex(set)]; }
    const Buffer& touched(VoxelDrawSet set) const { return m_lists[listIndex(set)].buffer; }
    rg::PersistentBuffer& listState(int index) { return m_lists[index]; }
    VkDeviceSize bytes() const;

    // Called while building the graph of a voxelization of `set` (into staticVolumes() for
    // Static, volumes() otherwise): picks its touched list and what must be cleared, and plans
    // that afterwards the accumulation is zero (the resolve zeroes what it reads) and that the
    // target's nonzero voxels are those of the new list (Dynamic: not tracked, the grid is a
    // copy of the static volumes plus the merge). The plan starts from the state of the last
    // executed graph (startPlanning) and takes effect when the graph runs (commitPlanned, from
    // the last voxel pass), so a graph that is built but never run changes nothing.
    void startPlanning() { m_planned = m_state; }
    VoxelizationPlan beginVoxelization(VoxelDrawSet set);
    struct State {
        int current = 0;          // the All / Static list of the last such voxelization
        int cover[2] = {-1, -1};  // per target (volumes(), staticVolumes()): the list (0 or 1)
                                  // holding all its nonzero voxels, or -1 (unknown)
        bool accumZero = false;   // the accumulation and the touched bits are zero
    };
    const State& planned() const { return m_planned; }
    void commitPlanned(const State& s) { m_state = s; }

    // Pass bodies (all images in GENERAL layout unless a layout is passed; the graph passes in
    // voxel_graph.cpp declare the accesses). clear: the touched list `list` emptied, and with
    // `accum` the accumulation and the touched bits zeroed (transfer writes).
    void recordClear(VkCommandBuffer cmd, VkBuffer list, bool accum) const;
    // The four volumes of `target` := 0 (transfer write, images in `layouts`: albedo, normal,
    // emission, faces).
    void recordClearVolumes(VkCommandBuffer cmd, const VoxelVolumes& target, const VkImageLayout layouts[4]) const;
    // After a voxelization into `target`, before its touched bits are listed: the voxels of
    // touched list `previous` whose touched bit is not set := 0 (indirect over it; bits read,
    // storage write).
    void recordClearStale(VkCommandBuffer cmd, const VoxelVolumes& target, VkBuffer previous) const;
    // volumes() := staticVolumes() (transfer read / write, layouts in the same order).
    void recordCopyStatic(VkCommandBuffer cmd, const VkImageLayout src[4], const VkImageLayout dst[4]) const;
    // Adds the chosen draws to the accumulation and sets the touched bits of their voxels
    // (storage read-write, scene buffers read).
    void recordVoxelize(VkCommandBuffer cmd, const VoxelSceneBuffers& scene, VoxelDrawSet set) const;
    // Appends the voxels of the set touched bits to `list` in grid order and zeroes the bits
    // (storage read-write).
    void recordTouchedList(VkCommandBuffer cmd, VkBuffer list) const;
    // accumulation -> `target` at the voxels of touched list `list` (indirect over it; storage
    // write; the other voxels keep their zeros), zeroing the records it reads (storage read-write).
    void recordResolve(VkCommandBuffer cmd, const VoxelVolumes& target, VkBuffer list) const;
    // Dynamic accumulation merged under the static volumes -> volumes() at the voxels of the
    // dynamic touched list that no static voxel occupies (volumes() holds the static copy);
    // zeroes the records of every listed voxel.
    void recordResolveMerge(VkCommandBuffer cmd) const;

private:
    VoxelGrid(Context& ctx) : m_ctx(ctx) {}
    int listIndex(VoxelDrawSet set) const { return set == VoxelDrawSet::Dynamic ? 2 : m_state.current; }
    Context& m_ctx;
    gpu::VoxelGridParams m_params{};
    VoxelVolumes m_volumes, m_static;
    rg::PersistentBuffer m_accum, m_bits;
    // `items` plus the record ranges (VOXEL_ACC_BINDING_RECORDS on, shaders/gi/voxel/voxel_acc.glsl).
    std::vector<DescriptorItem> withRecords(std::span<const DescriptorItem> items) const;
    // 0, 1: the All / Static lists, used in turn; 2: the Dynamic list.
    rg::PersistentBuffer m_lists[3];
    State m_state, m_planned;
    Pipeline m_voxelize, m_resolve, m_resolveMerge, m_stale, m_touchedList;
};

} // namespace vkgi::gi
