#include "cli.hpp"

#include "vkgi/knobs.hpp"

namespace vkgi::apps {

namespace {

const Option* findOption(const OptionTable& table, const std::string& flag) {
    for (const Option& o : table)
        if (o.flag == flag)
            return &o;
    return nullptr;
}

// A knob's value is checked on default settings now, so a bad one fails before any work.
Result<void> takeKnob(const std::string& flag, const std::string& value, KnobList& knobs) {
    gi::GiSettings probe;
    if (auto ok = gi::setKnob(probe, flag.substr(2), value); !ok)
        return makeError("--" + ok.error().message);
    knobs.emplace_back(flag.substr(2), value);
    return {};
}

} // namespace

Result<void> parseCommandLine(int argc, const char* const* argv, const OptionTable& table, KnobList* knobs) {
    for (int i = 1; i < argc; ++i) {
        std::string arg = argv[i] == std::string("-h") ? "--help" : argv[i];
        std::string value;
        bool inlineValue = false;
        if (size_t eq = arg.find('='); arg.rfind("--", 0) == 0 && eq != std::string::npos) {
            value = arg.substr(eq + 1);
            arg = arg.substr(0, eq);
            inlineValue = true;
        }
        const Option* option = findOption(table, arg);
        bool knob = !option && knobs && arg.rfind("--", 0) == 0 && gi::findKnob(arg.substr(2));
        if (!option && !knob)
            return makeError("unknown option '" + arg + "' (see --help)");
        if (option && option->value.empty()) {
            if (inlineValue)
                return makeError(arg + " takes no value (see --help)");
        } else if (!inlineValue) {
            if (i + 1 >= argc)
                return makeError(arg + " needs a value (see --help)");
            value = argv[++i];
        }
        if (auto ok = knob ? takeKnob(arg, value, *knobs) : option->apply(value); !ok)
            return ok;
    }
    return {};
}

std::string formatOptions(const OptionTable& table, size_t column) {
    std::string text;
    for (const Option& o : table) {
        std::string line = "  " + o.flag + (o.value.empty() ? "" : " " + o.value);
        line.resize(std::max(line.size() + 1, column), ' ');
        for (char c : o.help)
            line += c == '\n' ? "\n" + std::string(column, ' ') : std::string(1, c);
        text += line + "\n";
    }
    return text;
}

std::string techniqueNameList(const std::vector<std::string>& extra) {
    std::vector<std::string> names = gi::techniqueNames();
    names.insert(names.end(), extra.begin(), extra.end());
    return joinNames(names);
}

std::string knobHelpSection() {
    return "\nTechnique settings (--name value or --name=value):\n" + gi::knobHelp();
}

Option helpOption(bool& help) {
    return switchOption("--help", "this text", help);
}

Option switchOption(const std::string& flag, const std::string& help, bool& to) {
    return {flag, "", help, [&to](const std::string&) -> Result<void> {
                to = true;
                return {};
            }};
}

Option sceneOption(std::string& scene) {
    return textOption("--scene", "NAME|FILE", "built-in scene name or a .gltf/.glb file (default: " + scene + ")",
                      scene);
}

Option sizeOption(const std::string& help, uint32_t& width, uint32_t& height, uint32_t maxSide) {
    return {"--size", "WxH", help, [&width, &height, maxSide](const std::string& v) -> Result<void> {
                auto size = parseSize("--size", v, maxSide);
                if (!size)
                    return size.error();
                width = size->width;
                height = size->height;
                return {};
            }};
}

Option techniqueOption(const std::string& help, std::string& technique) {
    return {"--technique", "T", help, [&technique](const std::string& v) -> Result<void> {
                auto t = parseTechnique("--technique", v);
                if (!t)
                    return t.error();
                technique = *t;
                return {};
            }};
}

Option textOption(const std::string& flag, const std::string& value, const std::string& help, std::string& to) {
    return {flag, value, help, [&to](const std::string& v) -> Result<void> {
                to = v;
                return {};
            }};
}

Option wholeOption(const std::string& flag, const std::string& value, const std::string& help, uint32_t& to,
                   uint32_t lo, uint32_t hi) {
    return {flag, value, help, [flag, &to, lo, hi](const std::string& v) -> Result<void> {
                auto n = parseWhole(flag, v, lo, hi);
                if (!n)
                    return n.error();
                to = uint32_t(*n);
                return {};
            }};
}

Option positiveOption(const std::string& flag, const std::string& value, const std::string& help, float& to,
                      double max) {
    return {flag, value, help, [flag, &to, max](const std::string& v) -> Result<void> {
                auto x = parsePositive(flag, v, max);
                if (!x)
                    return x.error();
                to = float(*x);
                return {};
            }};
}

Option imageFileOption(const std::string& flag, const std::string& help, std::vector<std::filesystem::path>& to) {
    return {flag, "FILE", help, [flag, &to](const std::string& v) -> Result<void> {
                auto path = parseFileName(flag, v, {".exr", ".png"});
                if (!path)
                    return path.error();
                to.push_back(*path);
                return {};
            }};
}

} // namespace vkgi::apps
