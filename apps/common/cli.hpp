#pragma once
// The command-line grammar every vkgi app with options shares (vkgi-render, vkgi-view,
// vkgi-bench): an app lists its options once in an OptionTable (flag, value name, help text,
// what to do with the value), and the same table drives parsing and the --help listing.
// Grammar: "--flag value" and "--flag=value", valueless switches, "-h" for "--help", and, where
// the app takes them, each technique knob of vkgi/knobs.hpp as "--<knob> value". Errors are one
// line naming the option and the problem (the apps exit with code 2).
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "args.hpp"

namespace vkgi::apps {

struct Option {
    std::string flag;  // "--size"
    std::string value; // the value's name in the help ("WxH"); empty for a switch
    // Help text; each '\n' starts a continuation line at the description column.
    std::string help;
    // Takes the value ("" for a switch); the error names the flag.
    std::function<Result<void>(const std::string& value)> apply;
};
using OptionTable = std::vector<Option>;

// Walks argv[1..]. With `knobs`, knob flags are checked against the knob table now (a bad value
// fails before any work starts) and appended as (name, value) in command-line order; without,
// they are unknown options.
Result<void> parseCommandLine(int argc, const char* const* argv, const OptionTable& table, KnobList* knobs);

// The table as help lines: "  --flag VALUE", the help text from `column` on.
std::string formatOptions(const OptionTable& table, size_t column);
// The technique names for a help text, with `extra` appended: "none, lpv, vpl, vct".
std::string techniqueNameList(const std::vector<std::string>& extra = {});
// The help section listing every knob (for the apps that take knob flags).
std::string knobHelpSection();

// ---- Options every app spells the same way ----
// --help / -h: "this text".
Option helpOption(bool& help);
// A switch that sets `to`.
Option switchOption(const std::string& flag, const std::string& help, bool& to);
// --scene NAME|FILE: kept as given (loadScene checks it when the app loads it: exit code 1).
Option sceneOption(std::string& scene);
// --size WxH into two fields, each side 1..maxSide.
Option sizeOption(const std::string& help, uint32_t& width, uint32_t& height, uint32_t maxSide = kMaxImageSide);
// --technique T, checked when given against gi::techniqueNames().
Option techniqueOption(const std::string& help, std::string& technique);
// A value kept as given (checked by the app later, e.g. after --help was seen).
Option textOption(const std::string& flag, const std::string& value, const std::string& help, std::string& to);
// A whole number lo..hi.
Option wholeOption(const std::string& flag, const std::string& value, const std::string& help, uint32_t& to,
                   uint32_t lo, uint32_t hi);
// A finite number in (0, max].
Option positiveOption(const std::string& flag, const std::string& value, const std::string& help, float& to,
                      double max);
// An image file ending in .exr or .png; each use appends (the flag may be repeated).
Option imageFileOption(const std::string& flag, const std::string& help, std::vector<std::filesystem::path>& to);

} // namespace vkgi::apps
