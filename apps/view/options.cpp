#include "options.hpp"

#include <cstdlib>

#include "../common/cli.hpp"

namespace vkgi::view {

namespace {

constexpr uint32_t kMaxFrames = 1u << 24;

// "FRAME:REST" split at the colon; the frame is a whole number 0..kMaxFrames.
Result<std::pair<uint32_t, std::string>> frameAndRest(const std::string& flag, const std::string& value,
                                                      const std::string& form) {
    size_t colon = value.find(':');
    if (colon == std::string::npos)
        return apps::badValue(flag, form, value);
    auto frame = apps::parseWhole(flag + " frame", value.substr(0, colon), 0, kMaxFrames);
    if (!frame)
        return frame.error();
    return std::pair{uint32_t(*frame), value.substr(colon + 1)};
}

Result<void> parseResizeAt(const std::string& value, Options& o) {
    auto at = frameAndRest("--resize-at", value, "FRAME:WxH (e.g. 3:320x240)");
    if (!at)
        return at.error();
    auto size = apps::parseSize("--resize-at size", at->second);
    if (!size)
        return size.error();
    o.resizeFrame = at->first;
    o.resizeWidth = size->width;
    o.resizeHeight = size->height;
    return {};
}

Result<void> parseSwitchAt(const std::string& value, Options& o) {
    auto at = frameAndRest("--switch-at", value, "FRAME:TECHNIQUE (e.g. 3:vpl)");
    if (!at)
        return at.error();
    auto technique = apps::parseTechnique("--switch-at technique", at->second);
    if (!technique)
        return technique.error();
    o.switchFrame = at->first;
    o.switchTechnique = *technique;
    return {};
}

Result<void> parsePresent(const std::string& value, Options& o) {
    auto mode = apps::parseChoice("--present", value, {"fifo", "mailbox", "immediate"});
    if (!mode)
        return mode.error();
    o.present = *mode == "fifo"      ? PresentMode::Fifo
                : *mode == "mailbox" ? PresentMode::Mailbox
                                     : PresentMode::Immediate;
    return {};
}

// The interactive options, in --help order; the actions write into `o`.
apps::OptionTable mainOptions(Options& o) {
    using namespace apps;
    return {
        sceneOption(o.scene),
        techniqueOption(techniqueNameList() + " (default none); switchable at run time", o.technique),
        sizeOption("initial window size = render size (default 640x480)", o.width, o.height),
        positiveOption("--exposure", "E", "display / PNG exposure: radiance is multiplied by E before the ACES curve",
                       o.exposure, 1e12),
        {"--present", "MODE", "fifo (default), mailbox or immediate",
         [&o](const std::string& v) { return parsePresent(v, o); }},
        switchOption("--validation",
                     "Khronos validation + synchronization validation; any message makes the\n"
                     "exit code 3 (also VKGI_VALIDATION=1)",
                     o.validation),
        {"--no-ui", "", "no ImGui panel",
         [&o](const std::string&) -> Result<void> {
             o.ui = false;
             return {};
         }},
    };
}

// The scripted-run options (CI), in --help order.
apps::OptionTable scriptOptions(Options& o) {
    using namespace apps;
    return {
        {"--frames", "N",
         "render N frames with the scripted camera, then continue interactively\n(or exit with --exit)",
         [&o](const std::string& v) -> Result<void> {
             auto n = parseWhole("--frames", v, 1, kMaxFrames);
             if (!n)
                 return n.error();
             o.frames = uint32_t(*n);
             return {};
         }},
        {"--camera-script", "S",
         "still (the scene camera; default), orbit (one turn around the scene's\n"
         "vertical axis, back to the scene camera at the last frame), or a file of\n"
         "keyframes \"px py pz tx ty tz [yfov_degrees]\" (position, look-at target), one\n"
         "per line, spread evenly over the N frames and interpolated linearly",
         [&o](const std::string& v) -> Result<void> {
             if (v.empty())
                 return badValue("--camera-script", "still, orbit or a file name", v);
             o.cameraScript = v;
             return {};
         }},
        apps::cameraOption(o.camera),
        apps::lightOption(o.lights),
        switchOption("--animate",
                     "move the first light and the dynamic object (GiSystem::updateScene) along\n"
                     "loops that return to their start at the last frame",
                     o.animate),
        {"--resize-at", "F:WxH", "resize the window to WxH before scripted frame F (swapchain recreation)",
         [&o](const std::string& v) { return parseResizeAt(v, o); }},
        {"--switch-at", "F:T", "switch to technique T before scripted frame F (the GiSystem is rebuilt)",
         [&o](const std::string& v) { return parseSwitchAt(v, o); }},
        {"--screenshot", "FILE.exr",
         "capture the last scripted frame: linear radiance FILE.exr + tone-mapped\nFILE.png (atomic writes)",
         [&o](const std::string& v) -> Result<void> {
             auto path = parseFileName("--screenshot", v, {".exr"}, "(the .png is written beside it)");
             if (!path)
                 return path.error();
             o.screenshot = *path;
             return {};
         }},
        switchOption("--exit", "exit after the N frames (0 = success)", o.exitAfterFrames),
        helpOption(o.help),
    };
}

// The checks between options, once the whole line is read.
Result<void> checkScript(const Options& o) {
    if (o.exitAfterFrames && !o.frames)
        return makeError("--exit needs --frames N");
    if (o.resizeFrame && (!o.frames || *o.resizeFrame >= *o.frames))
        return makeError("--resize-at: the frame must be one of the --frames N scripted frames");
    if (o.switchFrame && (!o.frames || *o.switchFrame >= *o.frames))
        return makeError("--switch-at: the frame must be one of the --frames N scripted frames");
    if (o.screenshot && !o.frames)
        return makeError("--screenshot needs --frames N (it captures the last scripted frame)");
    return {};
}

} // namespace

Result<Options> parseArgs(int argc, const char* const* argv) {
    Options o;
    if (const char* v = std::getenv("VKGI_VALIDATION"); v && std::string(v) != "0")
        o.validation = true;
    apps::OptionTable table = mainOptions(o);
    for (apps::Option& option : scriptOptions(o))
        table.push_back(std::move(option));
    if (auto ok = apps::parseCommandLine(argc, argv, table, &o.knobs); !ok)
        return ok.error();
    if (auto ok = checkScript(o); !ok)
        return ok.error();
    return o;
}

std::string helpText() {
    Options defaults;
    return R"(vkgi-view: interactive viewer of a scene lit by a vkgi GI technique.

Usage: vkgi-view [options]
)" + apps::formatOptions(mainOptions(defaults), 25) +
           "Scripted mode (CI):\n" + apps::formatOptions(scriptOptions(defaults), 25) + R"(
Controls: left drag orbit (fly: look), right drag pan, wheel dolly; Tab orbit/fly camera;
fly: W/A/S/D/Q/E move, Shift faster; R reset camera; 1-4 technique (in --technique's order); F12 or P screenshot
(vkgi-view-<scene>-<technique>-<n>.exr/.png); H hide panel; Esc quit.
Environment: VKGI_DEVICE=<substring> picks the Vulkan device by name.
Exit codes: 0 success, 1 window/device/scene/render/output failure, 2 bad arguments,
3 validation messages were reported.
)" + apps::knobHelpSection();
}

} // namespace vkgi::view
