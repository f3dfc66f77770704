#pragma once
// Voxel cone tracing as a GiSystem technique (registered in technique_registry.cpp).
#include <memory>

#include "technique.hpp"

namespace vkgi::gi {

// Validates `settings` (a readable error otherwise) and returns the VCT module: it fits the
// voxel grid to each uploaded scene, adds the voxel and VCT passes every frame, and publishes
// VoxelGridData and VctOutputs on the blackboard next to IndirectData.
Result<std::unique_ptr<TechniqueModule>> createVctTechnique(Context& ctx, const VctSettings& settings);

} // namespace vkgi::gi
