#pragma once
// vkgi-bench's measuring loop, kept out of main(): the sweep table per technique, one
// measured configuration, and the reference each technique is compared with.
#include <string>
#include <vector>

#include "engine/context.hpp"
#include "engine/result.hpp"
#include "engine/scene.hpp"
#include "gi/bench.hpp"
#include "gi/gi.hpp"

namespace vkgi::bench {

struct Options {
    std::vector<std::string> scenes{"cornell", "room", "atrium"};
    std::vector<std::string> techniques; // empty = every technique the library has
    uint32_t width = 128, height = 128;
    uint32_t spp = 1024;   // reference paths per pixel (its own relMSE ~ 1.5/spp on cornell)
    uint32_t repeat = 5;   // measured frames per configuration after one warm-up frame
    bool quick = false;    // first configuration of each technique only (smoke runs)
    bool passes = false;   // print per-pass ms, bytes moved and stream ratio of every configuration
    double budgetMs = 0.0; // > 0: report the best configuration within this GPU time
    std::string outDir = "out/bench";
};

// Knob assignments ("lpv.grid=32 lpv.iterations=8") to measure for `technique`.
std::vector<std::string> sweepFor(const std::string& technique, bool quick);

// Renders `scene` with `settings` 1 + repeat times and fills a record: median per-pass and
// total GPU ms (readback passes excluded), errors against the reference images.
Result<gi::BenchRecord> measure(Context& ctx, const Scene& scene, const std::string& sceneName,
                                const gi::GiSettings& settings, const std::string& knobs, const Options& opt,
                                const HdrImage& refFull, const HdrImage& refIndirect);

} // namespace vkgi::bench
