#pragma once
// The value parsers every vkgi app shares (vkgi-render, vkgi-view, vkgi-bench, vkgi-graphbench):
// one function per kind of option value. Every bad value fails with the same one-line shape,
// "<flag>: expected <what>, got '<text>'", and the apps exit with code 2 (vkgi-graphbench: 1).
// The option table and the argv walker that call them are in cli.hpp.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "vkgi/result.hpp"
#include "vkgi/gi.hpp"

namespace vkgi::apps {

// Largest image side vkgi-render and vkgi-view accept: GiSystem's and the path tracer's limit.
constexpr uint32_t kMaxImageSide = 16384;

struct Extent {
    uint32_t width = 0;
    uint32_t height = 0;
};

// Technique knobs in command-line order ("lpv.grid", "64"); names and values from vkgi/knobs.hpp.
using KnobList = std::vector<std::pair<std::string, std::string>>;

// "<flag>: expected <what>, got '<text>'": the one shape of every bad-value error.
Error badValue(const std::string& flag, const std::string& what, const std::string& text);
// "a, b, c".
std::string joinNames(const std::vector<std::string>& names);

// A whole number in lo..hi, the entire text.
Result<uint64_t> parseWhole(const std::string& flag, const std::string& text, uint64_t lo, uint64_t hi);
// "WIDTHxHEIGHT", each side 1..maxSide.
Result<Extent> parseSize(const std::string& flag, const std::string& text, uint32_t maxSide = kMaxImageSide);
// A finite number in (0, max].
Result<double> parsePositive(const std::string& flag, const std::string& text, double max);
// One of `choices`, spelled exactly.
Result<std::string> parseChoice(const std::string& flag, const std::string& text,
                                const std::vector<std::string>& choices);

// A name of gi::techniqueNames() or of `extra` (vkgi-render's "reference").
Result<std::string> parseTechnique(const std::string& flag, const std::string& text,
                                   const std::vector<std::string>& extra = {});
// Comma-separated items with the empty ones skipped (vkgi-bench --scenes).
std::vector<std::string> splitList(const std::string& text);

// A non-empty file name, ending in one of `extensions` when any are given; `note` follows the
// expectation in the error ("(the .png is written beside it)").
Result<std::filesystem::path> parseFileName(const std::string& flag, const std::string& text,
                                            const std::vector<std::string>& extensions = {},
                                            const std::string& note = "");

// Space-separated "name=value" knob assignments (vkgi-bench --set), checked against the knob
// table; the error names the flag and the knob.
Result<void> checkKnobAssignments(const std::string& flag, const std::string& text);
// Applies --<knob> values gathered by parseCommandLine, then checks the settings as a whole
// (gi::validateSettings); the error names the knob as its flag, or the setting.
Result<void> applyKnobs(gi::GiSettings& settings, const KnobList& knobs);

} // namespace vkgi::apps
