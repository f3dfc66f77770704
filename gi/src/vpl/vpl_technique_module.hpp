#pragma once
// Technique::Vpl's GiSystem module (private to gi/): a thin adapter that reads the shared
// G-buffer, RSM and shadow views from TechniqueInputs, runs VplTechnique (vkgi/vpl.hpp) and
// publishes IndirectData (and VplOutputs, for tests and tools that want the VPL buffers).
#include <memory>
#include <vector>

#include "technique.hpp"

namespace vkgi::gi {

Result<std::unique_ptr<TechniqueModule>> createVplTechniqueModule(Context& ctx, const GiSettings& settings);

// The kind of lighting of a scene with `lights` and (`emission`) emissive surfaces, which the
// automatic VPL settings follow (resolveVplSettings).
VplLighting vplLighting(const std::vector<Light>& lights, bool emission);

} // namespace vkgi::gi
