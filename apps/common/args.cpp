#include "args.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "vkgi/knobs.hpp"

namespace vkgi::apps {

Error badValue(const std::string& flag, const std::string& what, const std::string& text) {
    return makeError(flag + ": expected " + what + ", got '" + text + "'");
}

std::string joinNames(const std::vector<std::string>& names) {
    std::string joined;
    for (const std::string& n : names)
        joined += (joined.empty() ? "" : ", ") + n;
    return joined;
}

namespace {

bool wholeNumber(const std::string& text, uint64_t lo, uint64_t hi, uint64_t& v) {
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    return !text.empty() && ec == std::errc() && end == text.data() + text.size() && v >= lo && v <= hi;
}

} // namespace

Result<uint64_t> parseWhole(const std::string& flag, const std::string& text, uint64_t lo, uint64_t hi) {
    uint64_t v = 0;
    if (!wholeNumber(text, lo, hi, v))
        return badValue(flag, "a whole number in " + std::to_string(lo) + ".." + std::to_string(hi), text);
    return v;
}

Result<Extent> parseSize(const std::string& flag, const std::string& text, uint32_t maxSide) {
    size_t x = text.find('x');
    uint64_t w = 0, h = 0;
    if (x == std::string::npos || !wholeNumber(text.substr(0, x), 1, maxSide, w) ||
        !wholeNumber(text.substr(x + 1), 1, maxSide, h))
        return badValue(flag, "WxH with each side 1.." + std::to_string(maxSide), text);
    return Extent{uint32_t(w), uint32_t(h)};
}

Result<double> parsePositive(const std::string& flag, const std::string& text, double max) {
    char* end = nullptr;
    double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(v) || !(v > 0.0) || v > max) {
        char range[48];
        std::snprintf(range, sizeof(range), "a number in (0, %g]", max);
        return badValue(flag, range, text);
    }
    return v;
}

Result<std::string> parseChoice(const std::string& flag, const std::string& text,
                                const std::vector<std::string>& choices) {
    for (const std::string& c : choices)
        if (text == c)
            return text;
    return badValue(flag, "one of " + joinNames(choices), text);
}

Result<std::string> parseTechnique(const std::string& flag, const std::string& text,
                                   const std::vector<std::string>& extra) {
    std::vector<std::string> names = gi::techniqueNames();
    names.insert(names.end(), extra.begin(), extra.end());
    return parseChoice(flag, text, names);
}

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');)
        if (!item.empty())
            items.push_back(item);
    return items;
}

Result<std::filesystem::path> parseFileName(const std::string& flag, const std::string& text,
                                            const std::vector<std::string>& extensions, const std::string& note) {
    std::string what = "a file name";
    std::string ext = std::filesystem::path(text).extension().string();
    bool extOk = extensions.empty();
    for (size_t i = 0; i < extensions.size(); ++i) {
        what += (i == 0 ? " ending in " : i + 1 == extensions.size() ? " or " : ", ") + extensions[i];
        extOk = extOk || ext == extensions[i];
    }
    if (text.empty() || !extOk)
        return badValue(flag, what + (note.empty() ? "" : " " + note), text);
    return std::filesystem::path(text);
}

Result<void> checkKnobAssignments(const std::string& flag, const std::string& text) {
    gi::GiSettings probe;
    std::stringstream in(text);
    for (std::string assignment; in >> assignment;)
        if (auto ok = gi::applyKnob(probe, assignment); !ok)
            return makeError(flag + ": " + ok.error().message);
    return {};
}

Result<void> applyKnobs(gi::GiSettings& settings, const KnobList& knobs) {
    for (const auto& [name, value] : knobs)
        if (auto ok = gi::setKnob(settings, name, value); !ok)
            return makeError("--" + ok.error().message);
    // Values each inside its knob's range can still be wrong (a grid that is not a power of
    // two): the settings as a whole are checked here, before any work, as a bad argument.
    return gi::validateSettings(settings);
}

} // namespace vkgi::apps
