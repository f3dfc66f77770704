#pragma once
// The command-line grammar every vkgi app shares (vkgi-render, vkgi-view): "--flag value" and
// "--flag=value", valueless switches, and each technique knob of gi/knobs.hpp as
// "--<knob> value"; plus the value parsers behind --size, counts and --exposure. Errors are one
// line naming the option and the problem (the apps exit with code 2).
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "engine/result.hpp"

namespace vkgi::apps {

// Largest image side any app accepts: GiSystem's and the path tracer's limit.
constexpr uint32_t kMaxImageSide = 16384;

struct CommandLine {
    // True for the flags that take a value ("--scene").
    std::function<bool(const std::string& flag)> takesValue;
    // Applies a value flag; the error names the flag.
    std::function<Result<void>(const std::string& flag, const std::string& value)> applyValue;
    // Applies a switch ("--compare"); false = not a switch of this app.
    std::function<bool(const std::string& flag)> applySwitch;
};

// Walks argv[1..]. Knob flags are checked against the knob table now (a bad value fails before
// any work starts) and appended to `knobs` as (name, value) in command-line order.
Result<void> parseCommandLine(int argc, const char* const* argv, const CommandLine& grammar,
                              std::vector<std::pair<std::string, std::string>>& knobs);

// A whole number in lo..hi, the entire text.
Result<uint64_t> parseWhole(const std::string& option, const std::string& text, uint64_t lo, uint64_t hi);
// "WIDTHxHEIGHT", each side 1..maxSide.
Result<std::pair<uint32_t, uint32_t>> parseSize(const std::string& option, const std::string& text,
                                                uint32_t maxSide = kMaxImageSide);
// A finite number in (0, max].
Result<float> parsePositive(const std::string& option, const std::string& text, double max);

} // namespace vkgi::apps
