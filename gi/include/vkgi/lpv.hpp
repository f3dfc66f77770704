#pragma once
// Public knobs of the light propagation volume technique (Kaplanyan's LPV as described in
// Elvek's thesis). Each field is a sweepable vkgi-bench knob; docs/lpv.md has the derivation.
#include <cstdint>

#include "vkgi/result.hpp"

namespace vkgi::gi {

struct LpvSettings {
    // Cells per axis, 1..128; memory and time grow as gridSize^3. With `iterations` >= gridSize
    // light crosses the whole grid. The defaults (16^3, 20 steps, rsmReduce 2) are the bench's
    // choice from its sweep over every built-in scene: the fewest steps at which the bunny box
    // beats the best constant by the 0.8x margin; more steps grow the point-lit box's grazing
    // self-lighting (docs/lpv.md "Defaults", docs/bench/lpv-128).
    // With fittedCell > 0 this is the fitted grid's fewest cells; cascades always have gridSize.
    uint32_t gridSize = 16;
    uint32_t iterations = 20; // propagation steps = how many cells light travels, 0..4096; a fitted grid
                              // with more than gridSize cells takes iterations * cells / gridSize
    // Metres, 0..1e4: the one grid fitted to the lit region gets more cells than gridSize, up to
    // 24 per axis, to make its cells no larger than this, and proportionally more steps, so light
    // still crosses it. The cell edge is set in metres, not as a share of the scene's bounds: the
    // Cornell boxes keep 16^3 x 20 (4 cm cells), the 6.4 m sun-lit room gets 24^3 x 30 (0.29 m cells
    // instead of 0.46 m), which brings its error against the all-bounce reference below 0.8x the best
    // constant's. A region longer than 22 cells of this size (the hall, the atrium) keeps gridSize.
    // 0 = gridSize cells whatever the region's size (docs/lpv.md "Fitted grid resolution").
    float fittedCell = 0.3f;
    bool occlusion = true;    // attenuate by the geometry volume (fuzzy blocking) while propagating
    bool bounces = false;     // reflect the light the GV stops at occupied voxels of the shared voxel grid
                              // (Gaitatzes et al.; needs occlusion); off by default: on the Cornell box
                              // it lowers RMSE but raises relMSE (docs/lpv.md)
    float damping = 1.0f;     // light-bleeding damping strength at lookup (thesis 3.3.1), 0 = off, 0..1
    // Nested camera-centred volumes (1..4) of gridSize^3, blended over 2 cells at their borders,
    // for any light type; 1 = one grid fitted to the lit region. 0 (default) = automatic: 3
    // cascades when the camera is inside the lit region and the fitted grid's cells would be
    // coarser than 4 * cellSize, else the fitted grid: a room keeps its fitted grid, a viewer
    // inside a level many times larger than the view gets cascades.
    uint32_t cascades = 0;
    float cellSize = 1.0f;    // metres: cell edge of the finest cascade (doubling per level), (0, 1e4]
    bool halfFloat = true;    // RGBA16F SH storage (half the bandwidth); false = RGBA32F reference
    uint32_t rsmReduce = 2;   // 1, 2 or 4: inject (and build the geometry volume) from the RSM reduced by this
                              // factor per axis, one flux-weighted surfel per block, energy conserved; a
                              // block spanning two levels (a roof's edge over the ground)
                              // or sharply folded is injected texel by texel instead. 2 by default: factor^2
                              // fewer texels to read where blocks merge; 4 reads fewer still but puts the
                              // sun-lit atrium_world and room further from the all-bounce reference
                              // (docs/lpv.md "Injection", "Defaults")

    bool operator==(const LpvSettings&) const = default;
};

// Checks ranges; the error names the field and the accepted range.
Result<void> validate(const LpvSettings& settings);

} // namespace vkgi::gi
