#pragma once
// vkgi-bench --scaling: GPU time of each technique against one axis at a time (pixels, voxels,
// triangles), the fitted log-log slopes, and the voxelization throughput (DESIGN.md, Budgets).
#include "vkgi/context.hpp"
#include "sweep.hpp"

namespace vkgi::bench {

// Measures every axis for opt.techniques with opt.repeat frames per point (opt.quick: tiny
// sizes, two points per axis), writes scaling.csv, scaling.json and scaling-<axis>.svg into
// opt.outDir and prints the slopes. Returns the process exit code.
int runScaling(Context& ctx, const Options& opt);

} // namespace vkgi::bench
