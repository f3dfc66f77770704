#include "cli.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "../common/cli.hpp"
#include "vkgi/gi.hpp"

namespace vkgi::render {

namespace {

// More samples than this would run for days on the CPU path tracer.
constexpr uint32_t kMaxSpp = 1u << 20;
// Beyond this many reflections the path tracer's own cap (1024) applies anyway.
constexpr int kMaxBounces = 1024;

Result<void> parseBounces(const std::string& value, Options& o) {
    if (value == "-1") {
        o.bounces = -1;
        return {};
    }
    auto v = apps::parseWhole("--bounces", value, 0, kMaxBounces);
    if (!v)
        return apps::badValue("--bounces", "a whole number in 0.." + std::to_string(kMaxBounces) + " or -1 (unbounded)",
                              value);
    o.bounces = int(*v);
    return {};
}

// Every option, in --help order; the actions write into `o`.
apps::OptionTable optionTable(Options& o) {
    using namespace apps;
    return {
        sceneOption(o.scene),
        textOption("--technique", "T",
                   techniqueNameList() + ", or reference (CPU path tracer); default none\n"
                                         "(none = direct light + emission only)",
                   o.technique),
        sizeOption("image size, each side 1..16384 (default: 256x256)", o.width, o.height),
        imageFileOption("--out",
                        "output image, .exr (linear float) or .png (tone mapped); may be repeated;\n"
                        "default out/<scene>.png (unless a part below is asked for). Files are\n"
                        "written atomically.",
                        o.outputs),
        imageFileOption("--out-direct", "the direct part (direct light + emission) of the same frame; may be repeated",
                        o.directOutputs),
        imageFileOption("--out-indirect",
                        "the indirect part: image - direct (the indirect light the technique adds), or\n"
                        "the path tracer's own paths of 2+ reflections; may be repeated",
                        o.indirectOutputs),
        imageFileOption("--out-glossy",
                        "vct: the glossy cone's radiance along the mirror direction (nits, before the\n"
                        "albedo * metallic weight of the indirect part); may be repeated",
                        o.glossyOutputs),
        imageFileOption("--out-ao",
                        "vct: cone-traced ambient occlusion, visibility 1 - occlusion in [0, 1] (grey;\n"
                        "a PNG stores it without exposure or tone curve); may be repeated",
                        o.aoOutputs),
        wholeOption("--spp", "N", "path-tracer samples per pixel for --technique reference and --compare (default 64)",
                    o.spp, 1, kMaxSpp),
        {"--bounces", "K",
         "reflections: 1 = direct only, -1 = unbounded. Default: the count the technique\n"
         "models (none: 1, one indirect bounce: 2), or -1 for --technique reference.\n"
         "--compare uses the same K.",
         [&o](const std::string& v) { return parseBounces(v, o); }},
        apps::cameraOption(o.camera),
        apps::lightOption(o.lights),
        switchOption("--allow-outside-folder",
                     "glTF buffer and image URIs may name files outside the scene file's folder\n"
                     "(by default such an image is dropped with a warning, such a buffer is an error)",
                     o.allowOutsideFolder),
        switchOption("--compare",
                     "print relMSE and RMSE (full image and indirect only) against the path-traced\n"
                     "reference (cached by scene hash in $VKGI_CACHE_DIR or ~/.cache/vkgi)",
                     o.compare),
        {"--exposure", "E|auto",
         "PNG only: linear radiance is multiplied by E before the tone map. Default auto:\n"
         "0.18 over the log-average luminance of the image's lit pixels (printed), one value\n"
         "for every part of the frame",
         [&o](const std::string& v) -> Result<void> {
             if (v == "auto") {
                 o.exposure.reset();
                 return {};
             }
             auto e = apps::parsePositive("--exposure", v, 1e12);
             if (!e)
                 return e.error();
             o.exposure = float(*e);
             return {};
         }},
        {"--json", "FILE",
         "write {scene, technique, width, height, passes[{name, ms}], total_ms,\n"
         "unprofiled_ms (GPU techniques: the frame without pass timestamps) or null,\n"
         "left_out[{name, reason: culled|not-needed|not-dirty, detail}],\n"
         "static_frame{passes, total_ms, left_out} or null,\n"
         "error{relmse, rmse, relmse_indirect, rmse_indirect} or null}",
         [&o](const std::string& v) -> Result<void> {
             auto path = parseFileName("--json", v);
             if (!path)
                 return path.error();
             o.json = *path;
             return {};
         }},
        helpOption(o.help),
    };
}

} // namespace

Result<Options> parseArgs(int argc, const char* const* argv) {
    Options o;
    if (auto ok = apps::parseCommandLine(argc, argv, optionTable(o), &o.knobs); !ok)
        return ok.error();
    // Checked once the whole line is read, so --help still shows the help after a bad name.
    if (!o.help)
        if (auto t = apps::parseTechnique("--technique", o.technique, {"reference"}); !t)
            return t.error();
    if (o.outputs.empty() && o.directOutputs.empty() && o.indirectOutputs.empty() && o.glossyOutputs.empty() &&
        o.aoOutputs.empty())
        o.outputs.push_back(std::filesystem::path("out") / (std::filesystem::path(o.scene).stem().string() + ".png"));
    return o;
}

std::vector<std::pair<std::string, std::filesystem::path>> outputFiles(const Options& o) {
    std::vector<std::pair<std::string, std::filesystem::path>> files;
    const std::pair<const char*, const std::vector<std::filesystem::path>*> lists[] = {
        {"--out", &o.outputs},           {"--out-direct", &o.directOutputs}, {"--out-indirect", &o.indirectOutputs},
        {"--out-glossy", &o.glossyOutputs}, {"--out-ao", &o.aoOutputs}};
    for (const auto& [flag, paths] : lists)
        for (const std::filesystem::path& p : *paths)
            files.emplace_back(flag, p);
    if (o.json)
        files.emplace_back("--json", *o.json);
    return files;
}

std::string helpText() {
    Options defaults;
    return R"(vkgi-render: render a scene headless and report per-pass GPU times.

Usage: vkgi-render [options]
)" + apps::formatOptions(optionTable(defaults), 22) +
           R"(
GPU times are of a second frame that recomputes everything (the first pays the driver's shader
compilation); unprofiled_ms is a third such frame timed without a timestamp per pass (they cost
~0.1 ms each on lavapipe); static_frame is a fourth one with nothing changed, which reuses the
persistent volumes.
Environment: VKGI_DEVICE=<substring> picks the Vulkan device by name; VKGI_VALIDATION=1 enables
the validation layers.
Exit codes: 0 success, 1 scene/render/output failure, 2 bad arguments, 3 validation messages
(VKGI_VALIDATION=1; nothing is written).
)" + apps::knobHelpSection();
}

std::string timingTable(const std::vector<rg::PassTiming>& passes, double totalMs, std::optional<double> unprofiledMs,
                        const std::vector<gi::LeftOutPass>& leftOut, const std::optional<MemoryUse>& memory,
                        const std::optional<StaticFrame>& staticFrame) {
    std::ostringstream out;
    char line[160];
    std::snprintf(line, sizeof(line), "%-32s %10s\n", "pass", "ms");
    out << line;
    for (const rg::PassTiming& p : passes) {
        std::snprintf(line, sizeof(line), "%-32s %10.3f\n", p.name.c_str(), p.ms);
        out << line;
    }
    double sum = 0.0;
    for (const rg::PassTiming& p : passes)
        sum += p.ms;
    // The frame's own timestamp scope covers the barriers too; what no pass's scope saw shows here.
    if (totalMs > sum) {
        std::snprintf(line, sizeof(line), "%-32s %10.3f\n", "(barriers, outside the passes)", totalMs - sum);
        out << line;
    }
    std::snprintf(line, sizeof(line), "%-32s %10.3f\n", "total", totalMs);
    out << line;
    // Each pass's timestamp scope costs ~0.06 ms on lavapipe (rg::TimestampScopes): the same frame
    // timed by its own scope only.
    if (unprofiledMs) {
        std::snprintf(line, sizeof(line), "%-32s %10.3f\n", "frame without pass timestamps", *unprofiledMs);
        out << line;
    }
    for (const gi::LeftOutPass& p : leftOut)
        out << "left out: " << p.name << " (" << gi::toString(p.reason) << ": " << p.detail << ")\n";
    if (staticFrame) {
        std::snprintf(line, sizeof(line), "next frame, nothing changed: %.3f ms, %zu passes\n", staticFrame->totalMs,
                      staticFrame->passes.size());
        out << line;
    }
    if (memory) {
        const double mib = 1024.0 * 1024.0;
        std::snprintf(line, sizeof(line),
                      "device memory: %.2f MiB (scene %.2f, shadow atlas %.2f, technique %.2f, readback %.2f, "
                      "frame transients %.2f)\n",
                      double(memory->total()) / mib, double(memory->persistent.scene) / mib,
                      double(memory->persistent.shadows) / mib, double(memory->persistent.technique) / mib,
                      double(memory->persistent.readback) / mib, double(memory->transientBytes) / mib);
        out << line;
    }
    return out.str();
}

namespace {

nlohmann::json passesJson(const std::vector<rg::PassTiming>& passes) {
    nlohmann::json a = nlohmann::json::array();
    for (const rg::PassTiming& p : passes)
        a.push_back({{"name", p.name}, {"ms", p.ms}});
    return a;
}

nlohmann::json leftOutJson(const std::vector<gi::LeftOutPass>& leftOut) {
    nlohmann::json a = nlohmann::json::array();
    for (const gi::LeftOutPass& p : leftOut)
        a.push_back({{"name", p.name}, {"reason", gi::toString(p.reason)}, {"detail", p.detail}});
    return a;
}

} // namespace

std::string jsonReport(const Options& o, const std::vector<rg::PassTiming>& passes, double totalMs,
                       std::optional<double> unprofiledMs, const std::vector<gi::LeftOutPass>& leftOut,
                       const std::optional<StaticFrame>& staticFrame, const std::optional<MemoryUse>& memory,
                       const std::optional<Errors>& errors) {
    nlohmann::json j;
    j["scene"] = o.scene;
    j["technique"] = o.technique;
    j["width"] = o.width;
    j["height"] = o.height;
    j["passes"] = passesJson(passes);
    j["total_ms"] = totalMs;
    if (unprofiledMs)
        j["unprofiled_ms"] = *unprofiledMs;
    else
        j["unprofiled_ms"] = nullptr;
    j["left_out"] = leftOutJson(leftOut);
    if (staticFrame)
        j["static_frame"] = {{"passes", passesJson(staticFrame->passes)},
                             {"total_ms", staticFrame->totalMs},
                             {"left_out", leftOutJson(staticFrame->leftOut)}};
    else
        j["static_frame"] = nullptr;
    if (memory) {
        nlohmann::json passMemory = nlohmann::json::array();
        for (const rg::PassMemory& p : memory->passes)
            passMemory.push_back({{"name", p.name},
                                  {"created_bytes", p.createdBytes},
                                  {"touched_bytes", p.touchedBytes},
                                  {"accessed_bytes", p.accessedBytes}});
        j["memory"] = {{"total_bytes", memory->total()},
                       {"persistent",
                        {{"scene", memory->persistent.scene},
                         {"shadows", memory->persistent.shadows},
                         {"readback", memory->persistent.readback},
                         {"technique", memory->persistent.technique}}},
                       {"transient_bytes", memory->transientBytes},
                       {"passes", passMemory}};
    } else {
        j["memory"] = nullptr;
    }
    // JSON has no infinity: a non-finite error (broken pixels) is reported as null.
    auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
    if (errors)
        j["error"] = {{"relmse", num(errors->full.relMse)},
                      {"rmse", num(errors->full.rmse)},
                      {"relmse_indirect", num(errors->indirect.relMse)},
                      {"rmse_indirect", num(errors->indirect.rmse)}};
    else
        j["error"] = nullptr;
    return j.dump(2) + "\n";
}

} // namespace vkgi::render
