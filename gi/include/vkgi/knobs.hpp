#pragma once
// Every tunable of GiSettings by name ("lpv.grid", "shadow.pcf"), with its range and help:
// the one table behind vkgi-render's technique flags, vkgi-bench's sweeps and the help text.
// Values are parsed strictly (whole string, finite, in range); an error names the knob.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vkgi/result.hpp"
#include "vkgi/gi.hpp"

namespace vkgi::gi {

struct Knob {
    enum class Kind { Uint, Float, Bool, Enum };
    std::string name;
    std::string help;
    Kind kind = Kind::Uint;
    double min = 0.0, max = 0.0;            // inclusive range (Uint, Float; Enum: 0 .. choices - 1)
    std::optional<Technique> technique;     // the technique it tunes; empty = all
    std::function<std::string(const GiSettings&)> get;
    std::function<void(GiSettings&, double)> set; // value already parsed and range-checked
    std::vector<std::string> choices;             // Enum: the value names, the value being the index
};

const std::vector<Knob>& knobs();
const Knob* findKnob(std::string_view name);

// Sets knob `name` from text ("64", "0.25", "on"/"off"/"true"/"false"/"1"/"0", an Enum's name).
Result<void> setKnob(GiSettings& settings, std::string_view name, std::string_view value);
// "name=value" form (vkgi-bench sweeps, --set).
Result<void> applyKnob(GiSettings& settings, std::string_view assignment);
// "grid=32 iterations=8 ..." of the knobs that matter for the selected technique (for tables).
std::string describeKnobs(const GiSettings& settings);
// Help text: one line per knob with its range and default.
std::string knobHelp();

} // namespace vkgi::gi
