#pragma once
// vkgi-bench --flight: a camera flight through a static scene (issue #16). Per frame: the GPU
// time, which camera-following volumes were rebuilt (VCT clipmap levels re-voxelized, shadow
// cascades re-rendered), and the frame-to-frame change of the indirect image against that of the
// direct image, whose change is the camera's motion alone: a level or cascade border that pops
// shows up as an indirect change far above the direct one.
#include "vkgi/context.hpp"
#include "sweep.hpp"

namespace vkgi::bench {

// Flies each of opt.scenes' cameras forward by kFlightStep metres per frame for opt.flightFrames
// frames with every technique of opt.techniques at its defaults (or --set), at opt.width x
// opt.height. Writes flight.csv into opt.outDir and prints per technique: median frame ms by
// what was rebuilt, the ratio of a frame rebuilding only the finest clipmap level to the first
// (full) frame, and the median and largest indirect-to-direct change ratio. Returns the exit code.
int runFlight(Context& ctx, const Options& opt);

} // namespace vkgi::bench
