#include "voxel/scene_voxel_grid.hpp"

#include <algorithm>

namespace vkgi::gi {

std::vector<VoxelDraw> voxelDraws(const GpuScene& gpu) {
    std::vector<VoxelDraw> draws;
    draws.reserve(gpu.draws.size());
    for (const GpuDraw& d : gpu.draws)
        draws.push_back({d.instance, d.firstIndex, d.indexCount / 3, d.vertexOffset, d.dynamic});
    return draws;
}

VoxelUpdate voxelUpdateFor(const SceneChanges& changes) {
    return changes.all || changes.staticGeometry ? VoxelUpdate::Full
           : changes.dynamicGeometry             ? VoxelUpdate::Dynamic
                                                 : VoxelUpdate::None;
}

Result<void> SceneVoxelGrid::sceneChanged(Context& ctx, const GpuScene& gpu, bool uploaded, uint32_t resolution) {
    m_draws = voxelDraws(gpu);
    if (!gpu.bounds.valid() || (!uploaded && m_grid))
        return {}; // what moved arrives as PassSelection::changes with the next frame
    // Fitted to the scene's bounds: LPV's multi-bounce and VPL visibility, both off by default,
    // read this grid, so in a level much larger than the view their voxels coarsen with it
    // (docs/lpv.md, docs/vpl.md limits). VCT's own grids follow the camera (levels > 1).
    auto params = fitVoxelGrid(gpu.bounds, resolution, 1.0f);
    if (!params)
        return params.error();
    auto grid = VoxelGrid::create(ctx, *params);
    if (!grid)
        return grid.error();
    m_grid = std::move(*grid);
    m_update = VoxelUpdate::Full;
    return {};
}

VoxelGridData SceneVoxelGrid::addPasses(rg::RenderGraph& graph, const SceneHandles& scene,
                                        const SceneChanges& changes) {
    m_update = std::max(m_update, voxelUpdateFor(changes));
    VoxelGridData data = addVoxelGridPasses(
        graph, *m_grid, {scene.vertices, scene.indices, scene.instances, scene.materials, m_draws}, m_update);
    m_update = VoxelUpdate::None;
    return data;
}

} // namespace vkgi::gi
