#pragma once
// What every technique that voxelizes the scene does the same way: the draws the voxelizer takes
// from the GPU scene, the re-voxelization that what moved calls for, and (for LPV's
// multi-bounce, VPL visibility and VPL bounces) the shared grid itself: fitted around the scene,
// or in a large world a camera-centred box of voxels set in metres.
#include <cstdint>
#include <memory>
#include <optional>
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

// Where the shared grid goes.
enum class SharedGridPlacement {
    Auto,   // sharedGridFollowsCamera decides, when the scene is uploaded
    Fitted, // around the scene's bounds, whatever their size
    Camera, // centred on the camera, kSharedGridSpan (or the caller's span) metres per axis
};

// Metres per axis of a camera-centred shared grid, whatever its resolution: 1 m voxels at the
// default 64^3, the scale of walls and doorways, and a box that holds a building around the
// camera (a 28 m atrium seen from one end).
inline constexpr float kSharedGridSpan = 64.0f;
// The span VPL takes in scenes lit only by point and spot lights: their light, and the
// occluders that shadow it, are those of the interior around the camera, and half the span
// halves the voxels (0.5 m at 64^3, 0.25 m halves: a hall's fitted grid) for the same memory.
inline constexpr float kSharedGridLampSpan = 32.0f;
// The fitted grid's voxel must be more than this many camera-grid voxels for the camera-centred
// grid to be taken: below it the fitted grid is about as fine and sees the whole scene.
inline constexpr float kSharedGridCoarsening = 2.0f;

// The automatic rule (like resolveVctLevels and LPV's cascades): true when the camera `eye` is
// inside `bounds` and a grid of `resolution`^3 fitted to them (fitVoxelGrid: the longest side
// spans resolution - 1 voxels) would have voxels coarser than kSharedGridCoarsening times the
// camera-centred grid's kSharedGridSpan / resolution. The bounds only select: the camera grid's
// voxels are set in metres.
// `span` is the camera-centred grid's (kSharedGridSpan unless the caller takes another).
bool sharedGridFollowsCamera(const Aabb& bounds, uint32_t resolution, glm::vec3 eye, float span = kSharedGridSpan);

// Min corner, in voxels of edge `voxel`, of the camera-centred grid of n^3 around `eye`: snapped
// to steps of n/4 voxels, so that the grid moves (and re-voxelizes) only when the camera has
// moved a quarter of the grid, and the camera always stays at least n/4 voxels from its faces.
glm::ivec3 sharedGridCell(glm::vec3 eye, float voxel, uint32_t n);

// The shared voxel grid of `resolution`^3: fitted around the scene, or centred on the camera in a
// large world (SharedGridPlacement), baked when the scene is uploaded and re-voxelized for what
// moves and, camera-centred, when the camera moves a step (only the slabs the grid newly covers
// are voxelized).
class SceneVoxelGrid {
public:
    // From TechniqueModule::sceneChanged: takes the draws, and makes a new grid (voxelized in
    // full with the next frame) when the scene was uploaded or there is none yet: placed by
    // `placement`, Auto deciding with the scene's camera `eye`. An empty scene gets no grid.
    // `halfVoxels`: a camera-centred grid also records each voxel's 2x2x2 half-voxel occupancy
    // (gi/voxel_grid.h, dims.z = 1; VPL's visibility march reads it); a fitted grid never does.
    Result<void> sceneChanged(Context& ctx, const GpuScene& gpu, bool uploaded, uint32_t resolution, glm::vec3 eye,
                              SharedGridPlacement placement = SharedGridPlacement::Auto, bool halfVoxels = false,
                              float span = kSharedGridSpan);
    // A camera-centred grid moves its corner to the step around `eye`, which makes a
    // re-voxelization pending; a fitted grid ignores it. Call before updatePending() is asked
    // (addPasses calls it too).
    void follow(glm::vec3 eye);
    // Adds the grid's passes for what moved since the last graph (`changes`), for a pending bake
    // and for a move of a camera-centred grid to `eye`; afterwards nothing is pending.
    VoxelGridData addPasses(rg::RenderGraph& graph, const SceneHandles& scene, const SceneChanges& changes,
                            glm::vec3 eye);
    bool exists() const { return m_grid != nullptr; }
    // A bake or a re-voxelization waits for the next addPasses (moved objects not counted).
    bool updatePending() const { return m_update != VoxelUpdate::None; }
    uint64_t bytes() const { return m_grid ? uint64_t(m_grid->bytes()) : 0; }
    void reset() { m_grid.reset(); }

private:
    std::unique_ptr<VoxelGrid> m_grid;
    std::vector<VoxelDraw> m_draws;
    VoxelUpdate m_update = VoxelUpdate::None;
    bool m_followsCamera = false;
    bool m_placed = false;            // camera-centred: the corner was set by follow()
    std::optional<glm::ivec3> m_move; // camera-centred: the corner's move since the last voxelization
};

} // namespace vkgi::gi
