#include "vkgi/lpv.hpp"

#include <string>

namespace vkgi::gi {

namespace {
constexpr uint32_t kMaxGrid = 128; // 128^3 x 3 volumes x 3 channels of RGBA16F: the largest we support
constexpr uint32_t kMaxCascades = 4;
constexpr float kMaxCell = 1e4f; // 10 km cells: beyond any level a float position resolves well
constexpr uint32_t kMaxIterations = 4096; // far beyond any grid diagonal (128 * sqrt(3) = 222 cells)
} // namespace

Result<void> validate(const LpvSettings& s) {
    if (s.gridSize < 1 || s.gridSize > kMaxGrid)
        return makeError("LpvSettings.gridSize = " + std::to_string(s.gridSize) + ": must be in [1, " +
                         std::to_string(kMaxGrid) + "]");
    if (s.iterations > kMaxIterations)
        return makeError("LpvSettings.iterations = " + std::to_string(s.iterations) + ": must be in [0, " +
                         std::to_string(kMaxIterations) + "]");
    if (s.cascades > kMaxCascades)
        return makeError("LpvSettings.cascades = " + std::to_string(s.cascades) + ": must be in [0, " +
                         std::to_string(kMaxCascades) + "] (0 = automatic)");
    if (!(s.cellSize > 0.0f && s.cellSize <= kMaxCell))
        return makeError("LpvSettings.cellSize = " + std::to_string(s.cellSize) + ": must be in (0, 1e4] metres");
    if (!(s.fittedCell >= 0.0f && s.fittedCell <= kMaxCell))
        return makeError("LpvSettings.fittedCell = " + std::to_string(s.fittedCell) +
                         ": must be in [0, 1e4] metres (0 = gridSize cells)");
    if (!(s.damping >= 0.0f && s.damping <= 1.0f))
        return makeError("LpvSettings.damping = " + std::to_string(s.damping) + ": must be in [0, 1]");
    if (s.rsmReduce != 1 && s.rsmReduce != 2 && s.rsmReduce != 4)
        return makeError("LpvSettings.rsmReduce = " + std::to_string(s.rsmReduce) + ": must be 1, 2 or 4");
    return {};
}

} // namespace vkgi::gi
