#pragma once
// What every technique that voxelizes the scene does the same way: the draws the voxelizer takes
// from the GPU scene, the re-voxelization that what moved calls for, and (for LPV's
// multi-bounce and VPL visibility, which fit a plain grid around the scene) the grid itself.
#include <cstdint>
#include <memory>
#include <vector>

#include "vkgi/gpu_scene.hpp"
#include "vkgi/result.hpp"
#include "vkgi/frame_data.hpp"
#include "pass_selection.hpp"
#include "voxel/voxel_graph.hpp"
#include "voxel/voxel_grid.hpp"

namespace vkgi {
class Context;
}

namespace vkgi::gi {

// One VoxelDraw per draw of the GPU scene, same order.
std::vector<VoxelDraw> voxelDraws(const GpuScene& gpu);

// The re-voxelization `changes` call for: a moved static object invalidates the static bake
// (Full), a moved dynamic one only the dynamic draws.
VoxelUpdate voxelUpdateFor(const SceneChanges& changes);

// A voxel grid of `resolution`^3 fitted around the scene, baked when the scene is uploaded and
// re-voxelized for what moves.
class SceneVoxelGrid {
public:
    // From TechniqueModule::sceneChanged: takes the draws, and makes a new grid around the
    // scene's bounds (voxelized in full with the next frame) when the scene was uploaded or
    // there is none yet. An empty scene gets no grid.
    Result<void> sceneChanged(Context& ctx, const GpuScene& gpu, bool uploaded, uint32_t resolution);
    // Adds the grid's passes for what moved since the last graph (`changes`) and for a pending
    // bake; afterwards nothing is pending.
    VoxelGridData addPasses(rg::RenderGraph& graph, const SceneHandles& scene, const SceneChanges& changes);
    bool exists() const { return m_grid != nullptr; }
    // A bake or a re-voxelization waits for the next addPasses (moved objects not counted).
    bool updatePending() const { return m_update != VoxelUpdate::None; }
    uint64_t bytes() const { return m_grid ? uint64_t(m_grid->bytes()) : 0; }
    void reset() { m_grid.reset(); }

private:
    std::unique_ptr<VoxelGrid> m_grid;
    std::vector<VoxelDraw> m_draws;
    VoxelUpdate m_update = VoxelUpdate::None;
};

} // namespace vkgi::gi
