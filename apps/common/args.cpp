#include "args.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "gi/gi.hpp"
#include "gi/knobs.hpp"

namespace vkgi::apps {

Result<void> parseCommandLine(int argc, const char* const* argv, const CommandLine& grammar,
                              std::vector<std::pair<std::string, std::string>>& knobs) {
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i];
        std::string value;
        bool inlineValue = false;
        if (size_t eq = arg.find('='); arg.rfind("--", 0) == 0 && eq != std::string::npos) {
            value = arg.substr(eq + 1);
            arg = arg.substr(0, eq);
            inlineValue = true;
        }
        bool knob = arg.rfind("--", 0) == 0 && gi::findKnob(arg.substr(2));
        if (!grammar.takesValue(arg) && !knob) {
            if (inlineValue)
                return makeError(arg + " takes no value (see --help)");
            if (!grammar.applySwitch(arg))
                return makeError("unknown option '" + arg + "' (see --help)");
            continue;
        }
        if (!inlineValue) {
            if (i + 1 >= argc)
                return makeError(arg + " needs a value (see --help)");
            value = argv[++i];
        }
        if (knob) {
            gi::GiSettings probe;
            if (auto ok = gi::setKnob(probe, arg.substr(2), value); !ok)
                return makeError("--" + ok.error().message);
            knobs.emplace_back(arg.substr(2), value);
        } else if (auto ok = grammar.applyValue(arg, value); !ok) {
            return ok.error();
        }
    }
    return {};
}

Result<uint64_t> parseWhole(const std::string& option, const std::string& text, uint64_t lo, uint64_t hi) {
    uint64_t v = 0;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
        return makeError(option + ": '" + text + "' is not a whole number in " + std::to_string(lo) + ".." +
                         std::to_string(hi));
    return v;
}

Result<std::pair<uint32_t, uint32_t>> parseSize(const std::string& option, const std::string& text,
                                                uint32_t maxSide) {
    size_t x = text.find('x');
    if (x == std::string::npos)
        return makeError(option + ": '" + text + "' is not WIDTHxHEIGHT (e.g. 256x256)");
    auto w = parseWhole(option + " width", text.substr(0, x), 1, maxSide);
    if (!w)
        return w.error();
    auto h = parseWhole(option + " height", text.substr(x + 1), 1, maxSide);
    if (!h)
        return h.error();
    return std::pair{uint32_t(*w), uint32_t(*h)};
}

Result<float> parsePositive(const std::string& option, const std::string& text, double max) {
    char* end = nullptr;
    double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(v) || !(v > 0.0) || v > max)
        return makeError(option + ": '" + text + "' is not a positive finite number");
    return float(v);
}

} // namespace vkgi::apps
