#include "cli.hpp"

#include <tuple>

#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "gi/gi.hpp"
#include "gi/knobs.hpp"
#include "../common/args.hpp"

namespace vkgi::render {

namespace {

// More samples than this would run for days on the CPU path tracer.
constexpr uint32_t kMaxSpp = 1u << 20;
// Beyond this many reflections the path tracer's own cap (1024) applies anyway.
constexpr int kMaxBounces = 1024;

Result<void> parseOutput(const std::string& flag, const std::string& text, std::vector<std::filesystem::path>& to) {
    std::string ext = std::filesystem::path(text).extension().string();
    if (ext != ".exr" && ext != ".png")
        return makeError(flag + ": '" + text + "' must end in .exr or .png");
    to.emplace_back(text);
    return {};
}

// Applies one option that takes a value.
Result<void> applyValue(const std::string& flag, const std::string& value, Options& o) {
    if (flag == "--scene") {
        o.scene = value;
    } else if (flag == "--technique") {
        o.technique = value;
    } else if (flag == "--size") {
        auto size = apps::parseSize("--size", value);
        if (!size)
            return size.error();
        std::tie(o.width, o.height) = *size;
    } else if (flag == "--out") {
        return parseOutput(flag, value, o.outputs);
    } else if (flag == "--out-direct") {
        return parseOutput(flag, value, o.directOutputs);
    } else if (flag == "--out-indirect") {
        return parseOutput(flag, value, o.indirectOutputs);
    } else if (flag == "--out-glossy") {
        return parseOutput(flag, value, o.glossyOutputs);
    } else if (flag == "--out-ao") {
        return parseOutput(flag, value, o.aoOutputs);
    } else if (flag == "--spp") {
        auto v = apps::parseWhole("--spp", value, 1, kMaxSpp);
        if (!v)
            return v.error();
        o.spp = uint32_t(*v);
    } else if (flag == "--bounces") {
        if (value == "-1") {
            o.bounces = -1;
            return {};
        }
        auto v = apps::parseWhole("--bounces", value, 0, kMaxBounces);
        if (!v)
            return makeError(v.error().message + " (or -1 = unbounded)");
        o.bounces = int(*v);
    } else if (flag == "--exposure") {
        auto e = apps::parsePositive("--exposure", value, 1e12);
        if (!e)
            return e.error();
        o.exposure = *e;
    } else if (flag == "--json") {
        if (value.empty())
            return makeError("--json: empty file name");
        o.json = value;
    }
    return {};
}

bool takesValue(const std::string& flag) {
    for (const char* f : {"--scene", "--technique", "--size", "--out", "--out-direct", "--out-indirect", "--out-glossy",
                          "--out-ao", "--spp", "--bounces", "--exposure", "--json"})
        if (flag == f)
            return true;
    return false;
}

} // namespace

Result<Options> parseArgs(int argc, const char* const* argv) {
    Options o;
    apps::CommandLine grammar;
    grammar.takesValue = takesValue;
    grammar.applyValue = [&](const std::string& flag, const std::string& value) { return applyValue(flag, value, o); };
    grammar.applySwitch = [&](const std::string& flag) {
        if (flag == "--help" || flag == "-h")
            o.help = true;
        else if (flag == "--compare")
            o.compare = true;
        else
            return false;
        return true;
    };
    if (auto ok = apps::parseCommandLine(argc, argv, grammar, o.knobs); !ok)
        return ok.error();
    if (o.outputs.empty() && o.directOutputs.empty() && o.indirectOutputs.empty() && o.glossyOutputs.empty() &&
        o.aoOutputs.empty())
        o.outputs.push_back(std::filesystem::path("out") / (std::filesystem::path(o.scene).stem().string() + ".png"));
    return o;
}

std::string helpText() {
    std::string text = R"(vkgi-render: render a scene headless and report per-pass GPU times.

Usage: vkgi-render [options]
  --scene NAME|FILE   built-in scene name or a .gltf/.glb file (default: cornell)
  --technique T       TECHNIQUES, or reference (CPU path tracer); default none
                      (none = direct light + emission only)
  --size WxH          image size, each side 1..16384 (default: 256x256)
  --out FILE          output image, .exr (linear float) or .png (tone mapped); may be repeated;
                      default out/<scene>.png (unless a part below is asked for). Files are
                      written atomically.
  --out-direct FILE   the direct part (direct light + emission) of the same frame; may be repeated
  --out-indirect FILE the indirect part: image - direct (the indirect light the technique adds), or
                      the path tracer's own paths of 2+ reflections; may be repeated
  --out-glossy FILE   vct: the glossy cone's radiance along the mirror direction (nits, before the
                      albedo * metallic weight of the indirect part); may be repeated
  --out-ao FILE       vct: cone-traced ambient occlusion, visibility 1 - occlusion in [0, 1] (grey;
                      a PNG stores it without exposure or tone curve); may be repeated
  --spp N             path-tracer samples per pixel for --technique reference and --compare (default 64)
  --bounces K         reflections: 1 = direct only, -1 = unbounded. Default: the count the technique
                      models (none: 1, one indirect bounce: 2), or -1 for --technique reference.
                      --compare uses the same K.
  --compare           print relMSE and RMSE (full image and indirect only) against the path-traced
                      reference (cached by scene hash in $VKGI_CACHE_DIR or ~/.cache/vkgi)
  --exposure E        PNG only: linear radiance is multiplied by E before the tone map (default 1;
                      sun-lit scenes of ~1e3 nits want ~1e-3)
  --json FILE         write {scene, technique, width, height, passes[{name, ms}], total_ms,
                      unprofiled_ms (GPU techniques: the frame without pass timestamps) or null,
                      left_out[{name, reason: culled|not-needed|not-dirty, detail}],
                      static_frame{passes, total_ms, left_out} or null,
                      error{relmse, rmse, relmse_indirect, rmse_indirect} or null}
  --help              this text

GPU times are of a second frame that recomputes everything (the first pays the driver's shader
compilation); unprofiled_ms is a third such frame timed without a timestamp per pass (they cost
~0.1 ms each on lavapipe); static_frame is a fourth one with nothing changed, which reuses the
persistent volumes.
Environment: VKGI_DEVICE=<substring> picks the Vulkan device by name; VKGI_VALIDATION=1 enables
the validation layers.
Exit codes: 0 success, 1 scene/render/output failure, 2 bad arguments.
)";
    std::string names;
    for (const std::string& n : gi::techniqueNames())
        names += (names.empty() ? "" : ", ") + n;
    text.replace(text.find("TECHNIQUES"), 10, names);
    return text + "\nTechnique settings (--name value or --name=value):\n" + gi::knobHelp();
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
