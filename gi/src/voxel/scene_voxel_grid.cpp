#include "voxel/scene_voxel_grid.hpp"

#include <algorithm>
#include <bit>

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

bool sharedGridFollowsCamera(const Aabb& bounds, uint32_t resolution, glm::vec3 eye, float span) {
    if (!bounds.valid() || resolution < 2)
        return false;
    const bool inside =
        glm::all(glm::greaterThanEqual(eye, bounds.min)) && glm::all(glm::lessThanEqual(eye, bounds.max));
    const glm::vec3 e = bounds.extent();
    const float fittedVoxel = std::max({e.x, e.y, e.z}) / float(resolution - 1);
    return inside && fittedVoxel > kSharedGridCoarsening * span / float(resolution);
}

glm::ivec3 sharedGridCell(glm::vec3 eye, float voxel, uint32_t n) {
    const int step = int(std::max(n / 4, 1u));
    const glm::vec3 steps = glm::floor(eye / (float(step) * voxel) + 0.5f);
    return step * glm::ivec3(steps) - glm::ivec3(int(n / 2));
}

Result<void> SceneVoxelGrid::sceneChanged(Context& ctx, const GpuScene& gpu, bool uploaded, uint32_t resolution,
                                          glm::vec3 eye, SharedGridPlacement placement, bool halfVoxels,
                                          float span) {
    m_draws = voxelDraws(gpu);
    if (!gpu.bounds.valid() || (!uploaded && m_grid))
        return {}; // what moved arrives as PassSelection::changes with the next frame
    const bool camera =
        placement == SharedGridPlacement::Camera ||
        (placement == SharedGridPlacement::Auto && sharedGridFollowsCamera(gpu.bounds, resolution, eye, span));
    gpu::VoxelGridParams params{};
    if (camera) {
        // Voxels set in metres; the corner is placed by follow() at the first frame. Radiance
        // scale 1, as the fitted grid's: its readers take albedo, normals and faces only.
        const float voxel = span / float(resolution);
        params.originSize = glm::vec4(glm::vec3(0.0f), voxel);
        params.scales = glm::vec4(1.0f / voxel, 1.0f, 1.0f, 0.0f);
        // Half-voxel bits: 1 m voxels half-close a 2.4 m arcade (docs/vpl.md, "Visibility").
        params.dims = glm::uvec4(resolution, uint32_t(std::countr_zero(resolution)), halfVoxels ? 1u : 0u, 0u);
    } else {
        // Fitted to the scene's bounds: scenes whose fitted voxels are metre-scale or finer, and
        // a large level whose camera is outside its bounds (the rule above; docs/vpl.md
        // "Visibility").
        auto fitted = fitVoxelGrid(gpu.bounds, resolution, 1.0f);
        if (!fitted)
            return fitted.error();
        params = *fitted;
    }
    auto grid = VoxelGrid::create(ctx, params);
    if (!grid)
        return grid.error();
    m_grid = std::move(*grid);
    m_followsCamera = camera;
    m_placed = false;
    m_move.reset();
    m_update = VoxelUpdate::Full;
    return {};
}

void SceneVoxelGrid::follow(glm::vec3 eye) {
    if (!m_grid || !m_followsCamera)
        return;
    const glm::ivec3 cell = sharedGridCell(eye, m_grid->params().originSize.w, m_grid->resolution());
    if (m_placed && cell == m_grid->cell())
        return;
    // What both corners cover is kept (addVoxelGridPasses decides whether it can be), unless the
    // grid was never voxelized where it stands or a full voxelization is pending anyway.
    if (m_placed && m_update == VoxelUpdate::None)
        m_move = cell - m_grid->cell();
    else
        m_move.reset();
    m_grid->setCell(cell);
    m_placed = true;
    m_update = VoxelUpdate::Full;
}

VoxelGridData SceneVoxelGrid::addPasses(rg::RenderGraph& graph, const SceneHandles& scene, const SceneChanges& changes,
                                        glm::vec3 eye) {
    follow(eye);
    const VoxelUpdate sceneUpdate = voxelUpdateFor(changes);
    if (sceneUpdate == VoxelUpdate::Full)
        m_move.reset(); // a moved static object makes the kept content stale too
    m_update = std::max(m_update, sceneUpdate);
    VoxelGridData data = addVoxelGridPasses(
        graph, *m_grid, {scene.vertices, scene.indices, scene.instances, scene.materials, m_draws}, m_update, m_move);
    m_update = VoxelUpdate::None;
    m_move.reset();
    return data;
}

} // namespace vkgi::gi
