#pragma once
// The voxel grid's passes in a render graph. The grid's volumes are persistent resources
// imported into every frame's graph; passes only run when their content changes. Techniques
// get the grid from the blackboard as VoxelGridData (VCT, LPV multi-bounce).
#include <cstdint>
#include <optional>
#include <vector>

#include "vkgi/rg/render_graph.hpp"
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

// Imports the grid and adds "gi.voxel.*" passes for `update`. `move`: the grid's corner moved by
// that many voxels (VoxelGrid::setCell) since its last voxelization, which a Full update of a
// scene without dynamic draws then keeps where both corners cover it, voxelizing only the slabs
// the grid newly covers ("gi.voxel.voxelize.slab"; docs/vct.md "Clipmap").
VoxelGridData addVoxelGridPasses(rg::RenderGraph& graph, VoxelGrid& grid, const VoxelSceneHandles& scene,
                                 VoxelUpdate update, std::optional<glm::ivec3> move = std::nullopt);

} // namespace vkgi::gi
