#include "lpv/lpv_grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace vkgi::gi::lpv {

Result<gpu::LpvGrid> fitLpvGrid(const Aabb& region, uint32_t cells) {
    glm::vec3 extent = region.extent();
    bool finite = std::isfinite(extent.x) && std::isfinite(extent.y) && std::isfinite(extent.z) &&
                  std::isfinite(region.min.x) && std::isfinite(region.min.y) && std::isfinite(region.min.z);
    if (!region.valid() || !finite)
        return makeError("LPV grid: the region to cover is empty or not finite");
    if (cells < 1)
        return makeError("LPV grid: needs at least 1 cell per axis");
    float longest = std::max({extent.x, extent.y, extent.z});
    // The cell follows the region at every scale (a millimetre scene gets micrometre cells); only
    // a point-like region, which has no scale, gets 1 mm cells.
    float span = cells > 2 ? float(cells - 2) : float(cells);
    float cell = longest > 0.0f ? longest / span : 1e-3f;
    gpu::LpvGrid grid{};
    glm::vec3 origin = region.centre() - 0.5f * cell * float(cells);
    grid.origin = glm::vec4(origin, cell);
    grid.size = glm::ivec4(int(cells), int(cells), int(cells), 0);
    return grid;
}

uint32_t fittedCells(const Aabb& region, uint32_t minCells, float maxCell) {
    const glm::vec3 extent = region.extent();
    const float longest = std::max({extent.x, extent.y, extent.z});
    if (!(maxCell > 0.0f) || !region.valid() || !std::isfinite(longest) || minCells >= kMaxFittedCells)
        return minCells;
    // The longest side spans cells - 2 cells (fitLpvGrid); computed in double, so a huge region
    // cannot overflow.
    const double needed = std::ceil(double(longest) / double(maxCell)) + 2.0;
    if (needed > double(kMaxFittedCells))
        return minCells; // the cap cannot reach the cell edge: the grid stays as it was
    return std::max(uint32_t(needed), minCells);
}

uint32_t fittedIterations(uint32_t iterations, uint32_t gridSize, uint32_t cells) {
    if (gridSize == 0 || cells == gridSize)
        return iterations;
    // At most the largest step count the settings accept, unless iterations is larger itself.
    const uint64_t scaled = (uint64_t(iterations) * cells + gridSize / 2) / gridSize;
    return uint32_t(std::min<uint64_t>(scaled, std::max(iterations, kMaxFittedIterations)));
}

Aabb litRegion(const Aabb& bounds, const std::vector<Light>& lights) {
    Aabb lit;
    for (const Light& light : lights) {
        if (light.type == LightType::Directional || !(light.range > 0.0f) || !std::isfinite(light.range))
            return bounds;
        lit.extend(light.position - glm::vec3(light.range));
        lit.extend(light.position + glm::vec3(light.range));
    }
    if (!lit.valid() || !bounds.valid())
        return Aabb{};
    Aabb clipped;
    clipped.min = glm::max(bounds.min, lit.min);
    clipped.max = glm::min(bounds.max, lit.max);
    return clipped.valid() ? clipped : Aabb{};
}

std::vector<gpu::LpvGrid> fitCascades(glm::vec3 eye, glm::vec3 forward, float finest, uint32_t cells, uint32_t count) {
    std::vector<gpu::LpvGrid> grids;
    float cell = finest;
    for (uint32_t level = 0; level < count; ++level, cell *= 2.0f) {
        glm::vec3 centre = eye + forward * (0.25f * float(cells) * cell);
        glm::vec3 origin = glm::floor(centre / cell - 0.5f * float(cells)) * cell; // whole cells of this level
        gpu::LpvGrid g{};
        g.origin = glm::vec4(origin, cell);
        g.size = glm::ivec4(int(cells), int(cells), int(cells), 0);
        grids.push_back(g);
    }
    return grids;
}

uint32_t cascadeCount(uint32_t requested, float cellSize, float fittedCell, bool cameraInside) {
    if (requested > 0)
        return requested;
    const float coarsest = cellSize * float(1u << (kAutoCascades - 1));
    return cameraInside && fittedCell > coarsest ? kAutoCascades : 1u;
}

} // namespace vkgi::gi::lpv
