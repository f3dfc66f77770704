#include "options.hpp"

#include <cmath>
#include <cstdlib>

#include "gi/gi.hpp"
#include "gi/knobs.hpp"
#include "../common/args.hpp"

namespace vkgi::view {

namespace {

constexpr uint32_t kMaxFrames = 1u << 24;

// "WIDTHxHEIGHT" into two fields.
Result<void> parseSize(const std::string& flag, const std::string& value, uint32_t& width, uint32_t& height) {
    auto size = apps::parseSize(flag, value);
    if (!size)
        return size.error();
    width = size->first;
    height = size->second;
    return {};
}

Result<void> applyValue(const std::string& flag, const std::string& value, Options& o) {
    if (flag == "--scene") {
        o.scene = value;
    } else if (flag == "--technique") {
        if (auto t = gi::parseTechnique(value); !t)
            return makeError("--technique: " + t.error().message);
        o.technique = value;
    } else if (flag == "--size") {
        return parseSize(flag, value, o.width, o.height);
    } else if (flag == "--resize-at") {
        size_t colon = value.find(':');
        if (colon == std::string::npos)
            return makeError("--resize-at: '" + value + "' is not FRAME:WIDTHxHEIGHT (e.g. 3:320x240)");
        auto frame = apps::parseWhole("--resize-at frame", value.substr(0, colon), 0, kMaxFrames);
        if (!frame)
            return frame.error();
        o.resizeFrame = uint32_t(*frame);
        return parseSize(flag, value.substr(colon + 1), o.resizeWidth, o.resizeHeight);
    } else if (flag == "--switch-at") {
        size_t colon = value.find(':');
        if (colon == std::string::npos)
            return makeError("--switch-at: '" + value + "' is not FRAME:TECHNIQUE (e.g. 3:vpl)");
        auto frame = apps::parseWhole("--switch-at frame", value.substr(0, colon), 0, kMaxFrames);
        if (!frame)
            return frame.error();
        if (auto t = gi::parseTechnique(value.substr(colon + 1)); !t)
            return makeError("--switch-at: " + t.error().message);
        o.switchFrame = uint32_t(*frame);
        o.switchTechnique = value.substr(colon + 1);
    } else if (flag == "--exposure") {
        auto e = apps::parsePositive("--exposure", value, 1e12);
        if (!e)
            return e.error();
        o.exposure = *e;
    } else if (flag == "--present") {
        if (value == "fifo")
            o.present = PresentMode::Fifo;
        else if (value == "mailbox")
            o.present = PresentMode::Mailbox;
        else if (value == "immediate")
            o.present = PresentMode::Immediate;
        else
            return makeError("--present: '" + value + "' is not fifo, mailbox or immediate");
    } else if (flag == "--frames") {
        auto n = apps::parseWhole("--frames", value, 1, kMaxFrames);
        if (!n)
            return n.error();
        o.frames = uint32_t(*n);
    } else if (flag == "--camera-script") {
        if (value.empty())
            return makeError("--camera-script: empty name");
        o.cameraScript = value;
    } else if (flag == "--screenshot") {
        if (std::filesystem::path(value).extension() != ".exr")
            return makeError("--screenshot: '" + value + "' must end in .exr (the .png is written beside it)");
        o.screenshot = value;
    }
    return {};
}

bool takesValue(const std::string& flag) {
    for (const char* f : {"--scene", "--technique", "--size", "--exposure", "--present", "--frames", "--camera-script",
                          "--screenshot", "--resize-at", "--switch-at"})
        if (flag == f)
            return true;
    return false;
}

} // namespace

Result<Options> parseArgs(int argc, const char* const* argv) {
    Options o;
    if (const char* v = std::getenv("VKGI_VALIDATION"); v && std::string(v) != "0")
        o.validation = true;
    apps::CommandLine grammar;
    grammar.takesValue = takesValue;
    grammar.applyValue = [&](const std::string& flag, const std::string& value) { return applyValue(flag, value, o); };
    grammar.applySwitch = [&](const std::string& flag) {
        if (flag == "--help" || flag == "-h")
            o.help = true;
        else if (flag == "--validation")
            o.validation = true;
        else if (flag == "--no-ui")
            o.ui = false;
        else if (flag == "--animate")
            o.animate = true;
        else if (flag == "--exit")
            o.exitAfterFrames = true;
        else
            return false;
        return true;
    };
    if (auto ok = apps::parseCommandLine(argc, argv, grammar, o.knobs); !ok)
        return ok.error();
    if (o.exitAfterFrames && !o.frames)
        return makeError("--exit needs --frames N");
    if (o.resizeFrame && (!o.frames || *o.resizeFrame >= *o.frames))
        return makeError("--resize-at: the frame must be one of the --frames N scripted frames");
    if (o.switchFrame && (!o.frames || *o.switchFrame >= *o.frames))
        return makeError("--switch-at: the frame must be one of the --frames N scripted frames");
    if (o.screenshot && !o.frames)
        return makeError("--screenshot needs --frames N (it captures the last scripted frame)");
    return o;
}

std::string helpText() {
    std::string text = R"(vkgi-view: interactive viewer of a scene lit by a vkgi GI technique.

Usage: vkgi-view [options]
  --scene NAME|FILE      built-in scene name or a .gltf/.glb file (default: cornell)
  --technique T          TECHNIQUES (default none); switchable at run time
  --size WxH             initial window size = render size (default 640x480)
  --exposure E           display / PNG exposure: radiance is multiplied by E before the ACES curve
  --present MODE         fifo (default), mailbox or immediate
  --validation           Khronos validation + synchronization validation; any message makes the
                         exit code 3 (also VKGI_VALIDATION=1)
  --no-ui                no ImGui panel
Scripted mode (CI):
  --frames N             render N frames with the scripted camera, then continue interactively
                         (or exit with --exit)
  --camera-script S      still (the scene camera; default), orbit (one turn around the scene's
                         vertical axis, back to the scene camera at the last frame), or a file of
                         keyframes "px py pz tx ty tz [yfov_degrees]" (position, look-at target), one
                         per line, spread evenly over the N frames and interpolated linearly
  --animate              move the first light and the dynamic object (GiSystem::updateScene) along
                         loops that return to their start at the last frame
  --resize-at F:WxH      resize the window to WxH before scripted frame F (swapchain recreation)
  --switch-at F:T        switch to technique T before scripted frame F (the GiSystem is rebuilt)
  --screenshot FILE.exr  capture the last scripted frame: linear radiance FILE.exr + tone-mapped
                         FILE.png (atomic writes)
  --exit                 exit after the N frames (0 = success)
  --help                 this text

Controls: left drag orbit (fly: look), right drag pan, wheel dolly; Tab orbit/fly camera;
fly: W/A/S/D/Q/E move, Shift faster; R reset camera; 1-4 technique (in --technique's order); F12 or P screenshot
(vkgi-view-<scene>-<technique>-<n>.exr/.png); H hide panel; Esc quit.
Environment: VKGI_DEVICE=<substring> picks the Vulkan device by name.
Exit codes: 0 success, 1 window/device/scene/render/output failure, 2 bad arguments,
3 validation messages were reported.
)";
    std::string names;
    for (const std::string& n : gi::techniqueNames())
        names += (names.empty() ? "" : ", ") + n;
    text.replace(text.find("TECHNIQUES"), 10, names);
    return text + "\nTechnique settings (--name value or --name=value):\n" + gi::knobHelp();
}

} // namespace vkgi::view
