#pragma once
// The LPV technique as a GiSystem module (Technique::Lpv).
#include <memory>

#include "technique.hpp"

namespace vkgi::gi {

Result<std::unique_ptr<TechniqueModule>> createLpvTechnique(Context& ctx, const GiSettings& settings);

} // namespace vkgi::gi
