#pragma once
// Technique::Vpl's GiSystem module (private to gi/): reads the shared G-buffer, RSM and shadow
// views from the blackboard, adds the VPL passes and publishes IndirectData (and VplOutputs,
// for tests and tools that want the VPL buffers).
#include <memory>

#include "technique.hpp"

namespace vkgi::gi {

Result<std::unique_ptr<TechniqueModule>> createVplModule(Context& ctx, const GiSettings& settings);

} // namespace vkgi::gi
