#include "cli.hpp"

#include <algorithm>

#include "../common/cli.hpp"

namespace vkgi::bench {

namespace {

// Every option, in --help order; the actions write into `o`.
apps::OptionTable optionTable(Options& o) {
    using namespace apps;
    return {
        {"--scenes", "a,b", "built-in names or glTF files (default cornell,room,atrium,hall)",
         [&o](const std::string& v) -> Result<void> {
             o.scenes = splitList(v);
             return {};
         }},
        {"--techniques", "a,b", "subset of the library's techniques (default: all)",
         [&o](const std::string& v) -> Result<void> {
             o.techniques = splitList(v);
             return {};
         }},
        sizeOption("image size (default 128x128)", o.width, o.height, 4096),
        wholeOption("--spp", "N", "reference paths/pixel (default 1024)", o.spp, 1, 1u << 20),
        wholeOption("--repeat", "N",
                    "measured frames per configuration (default 5, after one warm-up frame), each rendered\n"
                    "with and without per-pass timestamps (total ms: without; the passes: with)",
                    o.repeat, 1, 1000),
        {"--budget-ms", "X", "also print the least-error configuration within this GPU time per scene",
         [&o](const std::string& v) -> Result<void> {
             auto ms = parsePositive("--budget-ms", v, 1e9);
             if (!ms)
                 return ms.error();
             o.budgetMs = *ms;
             return {};
         }},
        switchOption("--quick", "one configuration per technique (smoke run)", o.quick),
        {"--set", "KNOBS",
         "only this configuration of the one --techniques given besides none: \"vct.grid=64\n"
         "vct.cones=6\", or \"\" for every technique's defaults (e.g. --techniques none,vpl --passes)",
         [&o](const std::string& v) -> Result<void> {
             o.set = v;
             return {};
         }},
        switchOption("--passes", "also print every configuration's passes: GPU ms, MiB moved, x streaming rate",
                     o.passes),
        {"--out", "DIR", "output folder (default out/bench): bench.csv, bench.json, bench.md, plot-<scene>.svg",
         [&o](const std::string& v) -> Result<void> {
             if (v.empty())
                 return badValue("--out", "a folder name", v);
             o.outDir = v;
             return {};
         }},
        switchOption("--scaling",
                     "GPU time against pixels (cornell 64^2..512^2), voxels (cornell 128^2, vct.grid 32..128,\n"
                     "lpv.grid 16..64) and triangles (bunny_box 128^2, 1.3k..82k triangles; vct also\n"
                     "re-voxelized every frame); every frame relights the scene. Writes scaling.csv,\n"
                     "scaling.json, scaling-<axis>.svg; prints log-log slopes per technique and pass and\n"
                     "the voxelization timing; --quick: tiny sizes, two points per axis",
                     o.scaling),
        switchOption("--jit",
                     "lavapipe's first-dispatch shader compilation per pass (Mesa's disk cache off): the\n"
                     "first frame of a fresh GiSystem minus warm frames, for configurations covering every\n"
                     "pass at 128x128; writes jit.csv, prints passes by cost and those over 1 s",
                     o.jit),
        switchOption("--flight",
                     "a camera flight forward from each --scenes camera (default hall_world), 0.05 m per frame,\n"
                     "every technique at its defaults (or --set): per frame GPU ms, re-voxelized VCT levels,\n"
                     "re-rendered light passes and the indirect image's change against the direct image's;\n"
                     "writes flight.csv, prints the cost by levels rebuilt and the worst change ratio",
                     o.flight),
        wholeOption("--frames", "N", "frames of --flight (default 48)", o.flightFrames, 2, 100000),
        {"--path", "dolly|orbit", "--flight's path: dolly (default) or orbit, 0.5 degrees per frame about the\n"
                                  "vertical axis through the point the camera looks at (temporal stability)",
         [&o](const std::string& v) -> Result<void> {
             if (v != "dolly" && v != "orbit")
                 return badValue("--path", "dolly or orbit", v);
             o.flightOrbit = v == "orbit";
             o.pathGiven = true;
             return {};
         }},
        helpOption(o.help),
    };
}

// The options of the error-vs-time sweep only (--scaling and --jit pick their own).
bool sweepOnly(const std::string& flag) {
    for (const char* f : {"--scenes", "--size", "--spp", "--budget-ms", "--passes", "--set"})
        if (flag == f)
            return true;
    return false;
}

// The checks between options, once the whole line is read; `given` = the sweep-only options
// on the command line, in order.
Result<void> checkCombination(Options& o, const std::vector<std::string>& given, bool framesGiven) {
    if (int(o.scaling) + int(o.jit) + int(o.flight) > 1)
        return makeError("--scaling, --jit and --flight are separate runs: give one");
    if ((framesGiven || o.pathGiven) && !o.flight)
        return makeError(std::string(framesGiven ? "--frames" : "--path") + " applies to --flight only");
    if (o.flight) {
        for (const std::string& flag : given)
            if (flag == "--spp" || flag == "--budget-ms" || flag == "--passes")
                return makeError(flag + " does not apply to --flight (it measures no error)");
        if (std::find(given.begin(), given.end(), "--scenes") == given.end())
            o.scenes = {"hall_world"};
    }
    if ((o.scaling || o.jit) && !given.empty())
        return makeError(given.front() + " does not apply to " + (o.scaling ? "--scaling" : "--jit") +
                         " (it uses its own scenes and sizes)");
    if (o.set && o.quick)
        return makeError("--set and --quick both pick the configurations: give one");
    if (o.set && !o.set->empty()) {
        // "none" has no knobs and rides along as the baseline of the ratios.
        size_t withKnobs = 0;
        for (const auto& t : o.techniques)
            withKnobs += t != "none";
        if (withKnobs != 1)
            return makeError("--set: name exactly one technique besides none with --techniques (the knobs are "
                             "that technique's); --set \"\" (the defaults) takes any");
    }
    if (o.techniques.empty())
        o.techniques = gi::techniqueNames();
    for (const auto& t : o.techniques)
        if (auto p = apps::parseTechnique("--techniques", t); !p)
            return p.error();
    if (o.set) // bad knobs fail here, before any long work
        return apps::checkKnobAssignments("--set", *o.set);
    return {};
}

} // namespace

Result<Options> parseArgs(int argc, const char* const* argv) {
    Options o;
    std::vector<std::string> given;
    bool framesGiven = false;
    apps::OptionTable table = optionTable(o);
    for (apps::Option& option : table) {
        if (sweepOnly(option.flag))
            option.apply = [flag = option.flag, apply = option.apply, &given](const std::string& v) {
                given.push_back(flag);
                return apply(v);
            };
        if (option.flag == "--frames")
            option.apply = [apply = option.apply, &framesGiven](const std::string& v) {
                framesGiven = true;
                return apply(v);
            };
    }
    if (auto ok = apps::parseCommandLine(argc, argv, table, nullptr); !ok)
        return ok.error();
    if (o.help)
        return o;
    if (auto ok = checkCombination(o, given, framesGiven); !ok)
        return ok.error();
    return o;
}

std::string helpText() {
    Options defaults;
    return "usage: vkgi-bench [--scenes a,b] [--techniques a,b] [--size WxH] [--spp N] [--repeat N]\n"
           "                  [--budget-ms X] [--quick | --set KNOBS] [--passes] [--out DIR]\n"
           "       vkgi-bench --scaling [--techniques a,b] [--repeat N] [--quick] [--out DIR]\n"
           "       vkgi-bench --jit [--techniques a,b] [--repeat N] [--out DIR]\n"
           "       vkgi-bench --flight [--scenes a,b] [--techniques a,b] [--size WxH] [--set KNOBS] [--frames N]\n"
           "                  [--path dolly|orbit] [--out DIR]\n" +
           apps::formatOptions(optionTable(defaults), 19) +
           "Exit codes: 0 success, 1 scene/render/output failure, 2 bad arguments, 3 validation messages\n"
           "(VKGI_VALIDATION=1 enables the validation layers).\n";
}

} // namespace vkgi::bench
