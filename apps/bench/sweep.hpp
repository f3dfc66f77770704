#pragma once
// vkgi-bench's measuring loop, kept out of main(): the sweep table per technique, one
// measured configuration, and the reference each technique is compared with.
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vkgi/context.hpp"
#include "vkgi/result.hpp"
#include "vkgi/scene.hpp"
#include "vkgi/bench.hpp"
#include "vkgi/gi.hpp"

namespace vkgi::bench {

struct Options {
    std::vector<std::string> scenes{"cornell", "room", "atrium", "hall"};
    std::vector<std::string> techniques; // empty = every technique the library has
    uint32_t width = 128, height = 128;
    uint32_t spp = 1024;   // reference paths per pixel (its own relMSE ~ 1.5/spp on cornell)
    uint32_t repeat = 5;   // measured frames per configuration after one warm-up frame
    bool quick = false;    // first configuration of each technique only (smoke runs)
    // --set: measure this one configuration ("vct.grid=64 vct.cones=6"; "" = the library's
    // defaults) instead of the sweep; needs exactly one technique.
    std::optional<std::string> set;
    bool passes = false;   // print per-pass ms, bytes moved and stream ratio of every configuration
    bool scaling = false;  // --scaling: time against pixels, voxels and triangles instead (scaling.hpp)
    bool jit = false;      // --jit: first-dispatch shader compilation per pass instead (jit.hpp)
    bool flight = false;   // --flight: a camera flight through each scene instead (flight.hpp)
    uint32_t flightFrames = 48; // --frames: frames of the flight
    bool flightOrbit = false;   // --path orbit: orbit the view's pivot instead of moving forward
    bool pathGiven = false;     // --path was on the command line
    double budgetMs = 0.0; // > 0: report the best configuration within this GPU time
    std::string outDir = "out/bench";
    bool help = false;     // --help: print the usage and exit
};

// Knob assignments ("lpv.grid=32 lpv.iterations=8") to measure for `technique`.
std::vector<std::string> sweepFor(const std::string& technique, bool quick);

// Median GPU times of `repeat` frames after `warmup` frames (lavapipe JITs each shader at its
// first dispatch), readback passes excluded, and the last frame's result.
struct Timing {
    std::vector<std::pair<std::string, double>> passMs; // median per pass, first-seen order
    // Median GPU ms of the frame, readbacks excluded: without pass timestamps (totalMs), and with
    // them (profiledMs, what passMs splits; each pass scope costs ~0.06 ms on lavapipe).
    double totalMs = 0.0;
    double profiledMs = 0.0;
    double wallMs = 0.0; // median host time of renderFrame without pass timestamps (record, submit, wait, readback)
    // Median GPU ms of the direct-only frame (a GiSystem with technique none, same settings
    // otherwise), readbacks excluded, rendered right after each measured frame (0 = not asked
    // for): totalMs / directMs is a ratio whose two halves saw the same machine load.
    double directMs = 0.0;
    gi::FrameResult last;
};
// Renders `scene` with `settings` 1 + repeat times. `beforeFrame`, when given, runs before every
// frame (vkgi-bench --scaling re-voxelizes a dynamic instance through updateScene). With
// `alternateDirect`, each measured frame is followed by a direct-only frame (Timing::directMs).
Result<Timing> measureTiming(Context& ctx, const Scene& scene, const gi::GiSettings& settings, uint32_t width,
                             uint32_t height, uint32_t repeat, const gi::FrameRequest& request,
                             const std::function<Result<void>(gi::GiSystem&)>& beforeFrame = {},
                             uint32_t warmup = 1, bool alternateDirect = false);

// The path-traced images a configuration is compared with: the bounce count it models and all
// bounces (the same images when the technique models unbounded light paths).
struct References {
    const HdrImage* full = nullptr;
    const HdrImage* indirect = nullptr;
    int bounces = 0;
    const HdrImage* fullAll = nullptr;
    const HdrImage* indirectAll = nullptr;
};

struct Measured {
    gi::BenchRecord record;
    // With technique none: the baseline "ambient" row, the direct image plus the constant that
    // minimises relMSE against each reference (engine bestAmbient), at the direct frame's cost.
    std::optional<gi::BenchRecord> ambient;
    // Non-empty when the scene does not need the technique at all (its passes were left out as
    // not needed, e.g. VPL without a spotlight): the record is then the direct image's.
    std::string notApplicable;
};

// Renders `scene` with `settings` 1 + repeat times (measureTiming) and fills a record: median per-pass and
// total GPU ms (readback passes excluded), errors against the reference images.
Result<Measured> measure(Context& ctx, const Scene& scene, const std::string& sceneName, const gi::GiSettings& settings,
                         const std::string& knobs, const Options& opt, const References& refs);

} // namespace vkgi::bench
