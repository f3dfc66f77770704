#pragma once
// Error-against-run-time records and what vkgi-bench makes of them: the Pareto front per
// scene, the best configuration within a time budget, and CSV/JSON/SVG files.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "vkgi/result.hpp"

namespace vkgi::gi {

struct BenchRecord {
    std::string scene;
    std::string technique;
    std::string knobs;                                  // "grid=64 cones=6", as given to --set
    std::vector<std::pair<std::string, double>> passMs; // median GPU ms per pass
    double totalMs = 0.0;                               // median GPU ms of the whole frame
    double profiledMs = 0.0;         // the same with a timestamp scope per pass (what passMs splits; 0 = not measured)
    // Median GPU ms of the direct-only frame (technique none, same scene and size), rendered
    // right after each measured frame (0 = not measured): totalMs / directMs compares two
    // frames that saw the same load.
    double directMs = 0.0;
    double relMse = 0.0, rmse = 0.0; // full image vs reference
    double relMseIndirect = 0.0, rmseIndirect = 0.0; // indirect-only vs reference indirect
    // The reference above has the bounce count the technique models (at least 2, -1 = unbounded).
    // The same errors against the unbounded reference (all light paths) compare every technique
    // with one truth, whatever it models.
    int referenceBounces = 0;
    double relMseAll = 0.0, rmseAll = 0.0;
    double relMseIndirectAll = 0.0, rmseIndirectAll = 0.0;
    // Full-image relMSE with epsilon 0.001 instead of 0.01 (against the matched and the
    // all-bounce reference): it weighs dark regions, where blotches and upsampling losses show.
    double relMseDark = 0.0, relMseAllDark = 0.0;
    // Smoothness (issue #15): laplacianEnergy of the indirect image over that of the matched
    // reference's indirect image, on the surface pixels. About 1: as smooth as the truth; well
    // above: blotches; the reference's path-tracing noise adds to its own energy, so a clean
    // smooth image can read below 1. 0 where there is no indirect image (none, ambient).
    double hfRatio = 0.0;
    double deviceMiB = 0.0;                             // device memory of the module
    uint64_t triangles = 0;                             // the scene's triangle count
    // Bytes each pass's declared accesses move (rg::PassMemory::accessedBytes), same order as
    // passMs, and the device's measured streaming rate (compute copy, GB/s) of the same run:
    // stream ratio = ms / (bytes / rate), 1 = as fast as a copy of the same bytes.
    std::vector<std::pair<std::string, double>> passBytes;
    double streamGBs = 0.0;
};

// ms / (bytes / streamGBs) of a pass: how many times slower than streaming its bytes (0 when
// either is unknown).
double streamRatio(double ms, double bytes, double streamGBs);

// Indices of the records of `scene` on the (total ms, relMSE) Pareto front, fastest first:
// no other record of the scene is both faster (or equal) and more accurate (or equal).
std::vector<size_t> paretoFront(const std::vector<BenchRecord>& records, const std::string& scene);

// The record of `scene` with the least relMSE among those with totalMs <= budgetMs; -1 if none fits.
long bestWithinBudget(const std::vector<BenchRecord>& records, const std::string& scene, double budgetMs);

std::string toCsv(const std::vector<BenchRecord>& records);
std::string toJson(const std::vector<BenchRecord>& records);
// One Markdown table per scene (scenes in first-seen order, rows in record order): technique,
// knobs, GPU ms, device MiB, the reference's bounce count, relMSE full and indirect, RMSE indirect
// against it and against the unbounded reference; rows on the Pareto front are marked "*".
// Per scene: a table of every record, then, when there are VCT records, a line per VCT grid
// with the median voxelization time over them (every frame re-voxelizes all triangles) and the
// throughput it means in triangles per second.
std::string toMarkdown(const std::vector<BenchRecord>& records);
// "vct.grid=64" in a VCT record's knobs, else the default grid (VctSettings).
uint32_t vctGridOf(const BenchRecord& record);
// Log-log plot of relMSE against total ms for one scene, one colour per technique, the Pareto
// front drawn as a line. Self-contained SVG (no external fonts or scripts).
std::string toSvgPlot(const std::vector<BenchRecord>& records, const std::string& scene);

// ---- Scaling (vkgi-bench --scaling): GPU time against one axis at a time ------------------

// One measured point: `axis` ("pixels", "voxels", "triangles") at `value` (its count).
struct ScalingRecord {
    std::string axis;
    double value = 0.0;
    std::string series;    // the plot line: the technique, or e.g. "vct voxelize/frame"
    std::string technique;
    std::string knobs;     // knob assignments of the run ("vct.grid=64")
    std::string scene;
    uint32_t width = 0, height = 0;
    uint64_t triangles = 0;
    double totalMs = 0.0;     // median GPU ms of the frame (readbacks excluded)
    double techniqueMs = 0.0; // the technique's own passes (gi.<technique>.*, <technique>.*, gi.voxel.*)
    double wallMs = 0.0;      // median host time of the frame call (submit, wait, readback included)
    std::vector<std::pair<std::string, double>> passMs; // median GPU ms per pass
};

// True for the passes a technique adds (gi.vct.*, gi.lpv.*, vpl.*, gi.voxel.*), false for the
// frame the techniques share (G-buffer, shadow maps, direct light, composite).
bool isTechniquePass(const std::string& pass, const std::string& technique);

// Least-squares slope of log(y) against log(x) over the pairs with x > 0 and y > 0 (finite):
// y = c x^k gives k. NaN with fewer than two distinct x.
double fitLogLogSlope(const std::vector<double>& x, const std::vector<double>& y);

std::string toScalingCsv(const std::vector<ScalingRecord>& records);
std::string toScalingJson(const std::vector<ScalingRecord>& records);
// Log-log plot of total GPU ms against `axis`'s value, one line per series (in first-seen order),
// with a dashed line of slope 1 (cost proportional to the axis) through the first point of the
// first series for reference. Self-contained SVG.
std::string toScalingSvgPlot(const std::vector<ScalingRecord>& records, const std::string& axis);

} // namespace vkgi::gi
