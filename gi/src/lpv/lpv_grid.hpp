#pragma once
// Where LPVs sit in the world: one volume fitted to the lit part of the scene (point and spot
// lights with a finite range only light their range), or nested camera-centred cascades whose
// cells are set in metres, for any light type. Pure CPU.
#include <cstdint>
#include <vector>

#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"
#include "gi/lpv_passes.h"

namespace vkgi::gi::lpv {

// A cubic-cell grid of `cells`^3 around `region`: the longest side spans cells - 2 cells (one
// cell of margin on every side, so the half-cell injection offset and the GV corners of surfaces
// on the region's faces stay inside), centred. Errors on an empty or non-finite region.
Result<gpu::LpvGrid> fitLpvGrid(const Aabb& region, uint32_t cells);

// The most cells per axis the fitted grid takes to make its cells small enough (fittedCells):
// propagation updates cells^3 cells per step with steps growing with the cells, 5.1x the cell
// updates of 16^3 x 20 at 24^3 x 30 (16x at 32^3 x 40).
constexpr uint32_t kMaxFittedCells = 24;

// Cells per axis of the grid fitted to `region`: the fewest whose cells (fitLpvGrid: the longest
// side over cells - 2) are at most `maxCell` metres, and at least `minCells`
// (LpvSettings::gridSize). A region that needs more than kMaxFittedCells for that keeps `minCells`:
// its cells are coarser than `maxCell` either way, and with more of them the fitted atrium gets
// ahead of the camera-centred cascades that stand in for it inside a large world (docs/lpv.md,
// "Fitted grid resolution"). `maxCell` <= 0, or a region that is empty or not finite: `minCells`.
// The cell edge is set in metres, so a Cornell box keeps its 16^3 and a room gets the cells a
// room's features need, whatever the two have in common as a share of their bounds.
uint32_t fittedCells(const Aabb& region, uint32_t minCells, float maxCell);

// Propagation steps of a fitted grid of `cells` per axis: `iterations` per `gridSize` cells,
// rounded, so light crosses the same share of the grid (exactly `iterations` when cells equals
// gridSize), and at most kMaxFittedIterations (LpvSettings' largest step count).
constexpr uint32_t kMaxFittedIterations = 4096;
uint32_t fittedIterations(uint32_t iterations, uint32_t gridSize, uint32_t cells);

// The part of `bounds` the scene's lights can reach: the whole bounds when any light is
// directional or has an infinite range, else the bounds clipped to the union of the range
// boxes of the point and spot lights. Invalid when nothing is lit.
Aabb litRegion(const Aabb& bounds, const std::vector<Light>& lights);

// `count` nested grids of `cells`^3, cell size doubling per level from `finest`, each centred a
// quarter of its extent ahead of `eye` along the unit view direction `forward` (most of a
// level then covers what the camera sees, yet the camera stays inside it); origins snap to whole
// cells of their level so a moving camera does not make the volumes shimmer. Level 0 is the finest.
std::vector<gpu::LpvGrid> fitCascades(glm::vec3 eye, glm::vec3 forward, float finest, uint32_t cells, uint32_t count);

// Cascades the automatic setting (LpvSettings::cascades = 0) uses when the lit region is too
// large for one grid.
constexpr uint32_t kAutoCascades = 3;

// How many volumes a frame uses: `requested` (LpvSettings::cascades) when nonzero. Automatic
// (0): kAutoCascades camera-centred cascades starting at `cellSize` metres when the camera is
// inside the lit region (`cameraInside`) and the one grid fitted to that region would have
// coarser cells (`fittedCell`) than their coarsest level: a viewer inside a level much larger
// than the view. Otherwise the fitted grid, which covers everything lit at a resolution the
// cascades would not beat where it matters and is kept across frames; a camera outside the lit
// region sees all of it (a scaled-up box seen from afar renders like the small one). The region
// only selects between the two here; it never sets a cascade's cell.
uint32_t cascadeCount(uint32_t requested, float cellSize, float fittedCell, bool cameraInside);

} // namespace vkgi::gi::lpv
