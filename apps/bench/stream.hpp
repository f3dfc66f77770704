#pragma once
// The memory-streaming rate the bench compares every pass with (DESIGN.md budgets): a compute
// shader copying `mib` MiB, median GPU time over `repeats` runs after a warm-up.
#include "vkgi/context.hpp"
#include "vkgi/result.hpp"

namespace vkgi::bench {

// Bytes read + written per second by the copy, in GB/s (1e9 bytes).
Result<double> measureStreamGBs(Context& ctx, uint32_t mib = 64, uint32_t repeats = 5);

} // namespace vkgi::bench
