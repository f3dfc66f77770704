#pragma once
// The shared voxel grid: fitting, and the persistent volumes, buffers and pipelines of the
// voxelization passes (clear, voxelize, resolve), which voxel_graph.hpp adds to a render graph.
// Layouts and encodings: shaders/include/gi/voxel_grid.h.
#include <cstdint>
#include <memory>
#include <vector>

#include "vkgi/pipeline.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/result.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/scene.hpp"
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

// World voxels (grids placed by VoxelGrid::setCell): voxel k of edge v spans [(k - 1/2) v,
// (k + 1/2) v) on each axis, so its centre lies on the lattice k v. Content authored on a metric
// grid (floors at y = 0, walls at whole metres, 0.3 m slabs at 5.1-5.4 m) then runs through voxel
// centres, as on a fitted grid (fitVoxelGrid puts the box faces on voxel centres), instead of
// lying on voxel faces, where a surface's voxel lies wholly on one side of it and a thin slab
// falls into one voxel with both its faces (docs/vct.md "Clipmap", "Voxel centres on the lattice").
// The min corner (world position) of the voxel `cell`:
inline glm::vec3 worldVoxelCorner(glm::ivec3 cell, float voxel) {
    return (glm::vec3(cell) - 0.5f) * voxel;
}

// One draw of the GPU scene as the voxelizer sees it (mirrors GpuDraw of vkgi/gpu_scene.hpp).
struct VoxelDraw {
    uint32_t instance = 0;
    uint32_t firstIndex = 0;
    uint32_t triangleCount = 0;
    int32_t vertexOffset = 0;
    bool dynamic = false;
    // World-space bounds of the draw's triangles, if known (static draws of a clipmap's scene):
    // a world-voxel grid skips the draw for boxes it cannot touch. Invalid: never skipped.
    Aabb bounds;
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
    int next = 0;            // touched list the voxelization appends to (index for listState)
    int previous = -1;       // list holding every nonzero voxel of the target volumes, or -1: clear them whole
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
    // Places the grid's min corner at world voxel `cell` (a clipmap level following the camera)
    // and voxelizes it in world voxels from then on (VoxelizePush::info.y), so that a voxel's
    // content does not depend on where the corner is. What the volumes hold belongs to the old
    // corner until the caller re-voxelizes (VoxelUpdate::Full, given the move to keep what both
    // corners cover: addVoxelGridPasses).
    void setCell(glm::ivec3 cell) {
        m_cell = cell;
        m_worldVoxels = true;
        m_params.originSize = glm::vec4(worldVoxelCorner(cell, m_params.originSize.w), m_params.originSize.w);
    }
    glm::ivec3 cell() const { return m_cell; }
    bool worldVoxels() const { return m_worldVoxels; }
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
        int current = 0;         // the All / Static list of the last such voxelization
        int cover[2] = {-1, -1}; // per target (volumes(), staticVolumes()): the list (0 or 1)
                                 // holding all its nonzero voxels, or -1 (unknown)
        bool accumZero = false;  // the accumulation and the touched bits are zero
    };
    const State& planned() const { return m_planned; }
    // Target volumes `target` (0: volumes(), 1: staticVolumes()) were used as scratch: no list
    // covers them.
    void planVolumesOverwritten(int target) { m_planned.cover[target] = -1; }
    void commitPlanned(const State& s) { m_state = s; }

    // The passes' pipelines (voxel_graph.cpp declares and dispatches them).
    struct Pipelines {
        Pipeline voxelize;     // voxelize.comp: draws -> accumulation + touched bits
        Pipeline touchedList;  // voxel_touched_list.comp: touched bits -> touched list
        Pipeline clearStale;   // voxel_resolve_stale.comp: zeroes voxels the new voxelization left out
        Pipeline resolve;      // voxel_resolve.comp: accumulation -> volumes at a touched list
        Pipeline resolveMerge; // voxel_resolve_merge.comp: dynamic accumulation merged under the static volumes
        Pipeline mark;         // voxel_mark.comp: the last touched list, moved -> touched bits of the kept voxels
    };
    const Pipelines& pipelines() const { return m_pipelines; }
    // The accumulation's binding ranges (VOXEL_ACC_BINDING_RECORDS + k, voxel_acc.glsl): range k
    // of the GI_VOXEL_ACC_SLABS, each a whole number of z-layers (all at offset 0 when the records
    // fit in one range).
    VkDeviceSize accumulationRangeOffset(uint32_t k) const;
    VkDeviceSize accumulationRangeBytes() const;

private:
    VoxelGrid(Context& ctx) : m_ctx(ctx) {}
    int listIndex(VoxelDrawSet set) const { return set == VoxelDrawSet::Dynamic ? 2 : m_state.current; }
    Context& m_ctx;
    gpu::VoxelGridParams m_params{};
    glm::ivec3 m_cell{0};       // setCell: the min corner in world voxels
    bool m_worldVoxels = false; // setCell was called: voxelize in world voxels
    VoxelVolumes m_volumes, m_static;
    rg::PersistentBuffer m_accum, m_bits;
    // 0, 1: the All / Static lists, used in turn; 2: the Dynamic list.
    rg::PersistentBuffer m_lists[3];
    State m_state, m_planned;
    Pipelines m_pipelines;
};

} // namespace vkgi::gi
