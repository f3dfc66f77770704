#pragma once
// vkgi-render's command line: parsing with one-line errors, the help text, the timing table
// and the --json report. Kept out of main.cpp so main reads as the render steps.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "vkgi/image_metrics.hpp"
#include "vkgi/result.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/gi.hpp"
#include "../common/scene_overrides.hpp"

namespace vkgi::render {

struct Options {
    std::string scene = "cornell";
    std::string technique = "none"; // a gi::Technique name or "reference"
    uint32_t width = 256;
    uint32_t height = 256;
    std::vector<std::filesystem::path> outputs; // default out/<scene>.png
    // The direct part and the indirect part (image - direct; the path tracer's own paths of >= 2
    // reflections for --technique reference) of the same frame.
    std::vector<std::filesystem::path> directOutputs, indirectOutputs;
    // VCT's glossy cone radiance and ambient occlusion (gi::FrameRequest::glossy / ao).
    std::vector<std::filesystem::path> glossyOutputs, aoOutputs;
    uint32_t spp = 64;                          // path-tracer samples per pixel (reference, --compare)
    std::optional<int> bounces;                 // reflections; default: the technique's own count
    bool compare = false;
    std::optional<float> exposure; // PNG tone-map exposure (ToneMap::exposure); none = autoExposure
    std::optional<std::filesystem::path> json;
    bool help = false;
    // glTF buffer and image URIs may resolve outside the scene file's folder (GltfLoadOptions).
    bool allowOutsideFolder = false;
    std::optional<apps::CameraSpec> camera; // --camera: replaces the scene's
    std::vector<Light> lights;              // --light: added to the scene's
    // Technique knobs in command-line order ("lpv.grid", "64"); names and values from vkgi/knobs.hpp.
    std::vector<std::pair<std::string, std::string>> knobs;
};

// Parses argv. Errors are one line naming the option and the problem (exit code 2).
Result<Options> parseArgs(int argc, const char* const* argv);
// Every output file of `o` (images and --json) with the option that names it.
std::vector<std::pair<std::string, std::filesystem::path>> outputFiles(const Options& o);
std::string helpText();

struct Errors {
    ErrorMetrics full;
    ErrorMetrics indirect;
};

// A frame rendered after one with nothing changed: only what the persistent volumes do not cover.
struct StaticFrame {
    std::vector<rg::PassTiming> passes;
    double totalMs = 0.0;
    std::vector<gi::LeftOutPass> leftOut;
};

// Device memory of the measured frame: what the GiSystem keeps (by owner) and the render graph's
// transients of that frame, with the transient bytes each pass first used and touched.
struct MemoryUse {
    gi::PersistentMemory persistent;
    uint64_t transientBytes = 0;
    std::vector<rg::PassMemory> passes;
    uint64_t total() const { return persistent.total() + transientBytes; }
};

// The per-pass GPU time table (plus total, the frame without pass timestamps when measured,
// the passes left out with their reason, memory, and the static frame's total) for stdout.
std::string timingTable(const std::vector<rg::PassTiming>& passes, double totalMs, std::optional<double> unprofiledMs,
                        const std::vector<gi::LeftOutPass>& leftOut, const std::optional<MemoryUse>& memory,
                        const std::optional<StaticFrame>& staticFrame);
// The --json report: scene, technique, size, passes, total_ms, unprofiled_ms (the same kind of
// frame timed without pass timestamps; null for the path tracer), left_out[{name, reason, detail}],
// static_frame {passes, total_ms, left_out} or null, memory {total_bytes, persistent{scene, shadows,
// readback, technique}, transient_bytes, passes[{name, created_bytes, touched_bytes, accessed_bytes}]}
// or null (path tracer), error (null without --compare).
std::string jsonReport(const Options& o, const std::vector<rg::PassTiming>& passes, double totalMs,
                       std::optional<double> unprofiledMs, const std::vector<gi::LeftOutPass>& leftOut,
                       const std::optional<StaticFrame>& staticFrame, const std::optional<MemoryUse>& memory,
                       const std::optional<Errors>& errors);

} // namespace vkgi::render
