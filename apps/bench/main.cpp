// vkgi-bench: error against run time. For each scene x technique x knob configuration it
// measures median per-pass GPU ms on this device and the error against the path-traced
// reference with the matching bounce count, then writes bench.csv, bench.json, bench.md and one
// error-vs-time plot per scene (Pareto front marked) into --out.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <sstream>

#include "engine/file_util.hpp"
#include "engine/gltf_loader.hpp"
#include "engine/progress.hpp"
#include "gi/knobs.hpp"
#include "gi/reference.hpp"
#include "jit.hpp"
#include "scaling.hpp"
#include "stream.hpp"
#include "sweep.hpp"

using namespace vkgi;

namespace {

const char* kUsage =
    "usage: vkgi-bench [--scenes a,b] [--techniques a,b] [--size WxH] [--spp N] [--repeat N]\n"
    "                  [--budget-ms X] [--quick | --set KNOBS] [--passes] [--out DIR]\n"
    "       vkgi-bench --scaling [--techniques a,b] [--repeat N] [--quick] [--out DIR]\n"
    "       vkgi-bench --jit [--techniques a,b] [--repeat N] [--out DIR]\n"
    "  --scenes      built-in names or glTF files (default cornell,room,atrium)\n"
    "  --techniques  subset of the library's techniques (default: all)\n"
    "  --size        image size (default 128x128)      --spp     reference paths/pixel (default 1024)\n"
    "  --repeat      measured frames per configuration (default 5, after one warm-up frame), each rendered\n"
    "                with and without per-pass timestamps (total ms: without; the passes: with)\n"
    "  --budget-ms   also print the least-error configuration within this GPU time per scene\n"
    "  --quick       one configuration per technique (smoke run)\n"
    "  --set KNOBS   only this configuration of the one --techniques given: \"vct.grid=64 vct.cones=6\",\n"
    "                or \"\" for the library's defaults (e.g. per-pass times of the defaults with --passes)\n"
    "  --passes      also print every configuration's passes: GPU ms, MiB moved, x streaming rate\n"
    "  --out         output folder (default out/bench): bench.csv, bench.json, bench.md, plot-<scene>.svg\n"
    "  --scaling     GPU time against pixels (cornell 64^2..512^2), voxels (cornell 128^2, vct.grid 32..128,\n"
    "                lpv.grid 16..64) and triangles (bunny_box 128^2, 1.3k..82k triangles; vct also\n"
    "                re-voxelized every frame); every frame relights the scene. Writes scaling.csv,\n"
    "                scaling.json, scaling-<axis>.svg; prints log-log slopes per technique and pass and\n"
    "                the voxelization timing; --quick: tiny sizes, two points per axis\n"
    "  --jit         lavapipe's first-dispatch shader compilation per pass (Mesa's disk cache off): the\n"
    "                first frame of a fresh GiSystem minus warm frames, for configurations covering every\n"
    "                pass at 128x128; writes jit.csv, prints passes by cost and those over 1 s\n";

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string item; std::getline(in, item, ',');)
        if (!item.empty())
            out.push_back(item);
    return out;
}

bool parseUint(const char* s, uint32_t lo, uint32_t hi, uint32_t& out) {
    char* end = nullptr;
    unsigned long v = std::strtoul(s, &end, 10);
    if (!*s || *end || s[0] == '-' || v < lo || v > hi)
        return false;
    out = uint32_t(v);
    return true;
}

Result<bench::Options> parseArgs(int argc, char** argv) {
    bench::Options o;
    std::vector<std::string> sweepOnly; // options of the error-vs-time sweep given on the command line
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--scaling" || a == "--jit") {
            (a == "--scaling" ? o.scaling : o.jit) = true;
            continue;
        }
        if (a == "--scenes" || a == "--size" || a == "--spp" || a == "--budget-ms" || a == "--passes" || a == "--set")
            sweepOnly.push_back(a);
        if (a == "--help" || a == "-h") {
            std::fputs(kUsage, stdout);
            std::exit(0);
        }
        if (a == "--quick" || a == "--passes") {
            (a == "--quick" ? o.quick : o.passes) = true;
            continue;
        }
        if (i + 1 >= argc)
            return makeError(a + ": missing value (see --help)");
        const char* v = argv[++i];
        if (a == "--scenes")
            o.scenes = split(v);
        else if (a == "--techniques")
            o.techniques = split(v);
        else if (a == "--out")
            o.outDir = v;
        else if (a == "--set")
            o.set = v;
        else if (a == "--size") {
            if (std::sscanf(v, "%ux%u", &o.width, &o.height) != 2 || o.width < 1 || o.height < 1 ||
                o.width > 4096 || o.height > 4096)
                return makeError(std::string("--size: '") + v + "' is not WxH with 1..4096");
        } else if (a == "--spp" ? !parseUint(v, 1, 1u << 20, o.spp)
                   : a == "--repeat" ? !parseUint(v, 1, 1000, o.repeat)
                   : false)
            return makeError(a + ": '" + v + "' is out of range");
        else if (a == "--budget-ms") {
            char* end = nullptr;
            o.budgetMs = std::strtod(v, &end);
            if (*end || !(o.budgetMs > 0.0 && o.budgetMs < 1e9))
                return makeError(std::string("--budget-ms: '") + v + "' is not a positive number");
        } else if (a != "--spp" && a != "--repeat")
            return makeError("unknown option '" + a + "' (see --help)");
    }
    if (o.scaling && o.jit)
        return makeError("--scaling and --jit are separate runs: give one");
    if ((o.scaling || o.jit) && !sweepOnly.empty())
        return makeError(sweepOnly.front() + " does not apply to " + (o.scaling ? "--scaling" : "--jit") +
                         " (it uses its own scenes and sizes)");
    if (o.set && o.quick)
        return makeError("--set and --quick both pick the configurations: give one");
    if (o.set && o.techniques.size() != 1)
        return makeError("--set: name exactly one technique with --techniques (the knobs are that technique's)");
    if (o.techniques.empty())
        o.techniques = gi::techniqueNames();
    for (const auto& t : o.techniques)
        if (auto p = gi::parseTechnique(t); !p)
            return p.error();
    if (o.set) { // bad knobs fail here, before any long work
        gi::GiSettings s;
        std::stringstream in(*o.set);
        for (std::string kv; in >> kv;)
            if (auto ok = gi::applyKnob(s, kv); !ok)
                return makeError("--set: " + ok.error().message);
    }
    return o;
}

} // namespace

int main(int argc, char** argv) {
    auto opt = parseArgs(argc, argv);
    if (!opt) {
        std::fprintf(stderr, "vkgi-bench: %s\n", opt.error().message.c_str());
        return 2;
    }
    // Compilation is what --jit measures: Mesa's disk cache would serve shaders compiled by an
    // earlier run. Must be set before the driver loads.
    if (opt->jit)
        setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);
    auto ctx = defaultDeviceBuilder().build();
    if (!ctx) {
        std::fprintf(stderr, "vkgi-bench: %s\n", ctx.error().message.c_str());
        return 1;
    }
    if (opt->scaling)
        return bench::runScaling(**ctx, *opt);
    if (opt->jit)
        return bench::runJit(**ctx, *opt);
    // The streaming rate every pass is compared with, measured now on this device and load.
    auto streamGBs = bench::measureStreamGBs(**ctx);
    if (!streamGBs) {
        std::fprintf(stderr, "vkgi-bench: %s\n", streamGBs.error().message.c_str());
        return 1;
    }
    std::vector<std::pair<std::string, std::string>> jobs; // technique, knobs
    for (const auto& t : opt->techniques)
        for (const auto& k : opt->set ? std::vector<std::string>{*opt->set} : bench::sweepFor(t, opt->quick))
            jobs.push_back({t, k});
    std::vector<Scene> scenes; // all loaded up front: a bad name fails before any long work
    for (const auto& sceneName : opt->scenes) {
        auto scene = loadScene(sceneName);
        if (!scene) {
            std::fprintf(stderr, "vkgi-bench: %s\n", scene.error().message.c_str());
            return 1;
        }
        scenes.push_back(std::move(*scene));
    }
    std::vector<gi::BenchRecord> records;
    Progress progress("vkgi-bench", jobs.size() * opt->scenes.size());
    for (size_t si = 0; si < scenes.size(); ++si) {
        const std::string& sceneName = opt->scenes[si];
        const Scene* scene = &scenes[si];
        std::map<int, gi::ReferenceImages> refs; // by bounce count
        auto reference = [&](int bounces) -> Result<const gi::ReferenceImages*> {
            if (!refs.count(bounces)) {
                gi::ReferenceSettings rs;
                rs.spp = opt->spp;
                rs.maxBounces = bounces;
                auto ref = gi::renderReferenceCached(*scene, scene->cameraOrDefault(), opt->width, opt->height, rs);
                if (!ref)
                    return ref.error();
                refs[bounces] = std::move(*ref);
            }
            return &refs[bounces];
        };
        std::set<std::string> notApplicable; // techniques this scene does not need: measured once
        for (const auto& [tech, knobs] : jobs) {
            progress.add(1);
            if (notApplicable.count(tech))
                continue;
            gi::GiSettings s;
            s.technique = *gi::parseTechnique(tech);
            std::string err;
            std::stringstream in(knobs);
            for (std::string kv; in >> kv && err.empty();)
                if (auto ok = gi::applyKnob(s, kv); !ok)
                    err = ok.error().message;
            if (!err.empty()) { // a knob of a technique that is not built yet: skip, say so
                progress.note("vkgi-bench: skipped " + tech + " [" + knobs + "]: " + err);
                continue;
            }
            // The bounce count each technique models, but at least one indirect bounce: then "none" shows
            // the error of having no GI, and the techniques share one reference and one Pareto front.
            int bounces = gi::modelledBounces(s);
            bounces = bounces < 0 ? -1 : std::max(bounces, 2);
            auto matched = reference(bounces);
            auto all = matched ? reference(-1) : matched;
            if (!all) {
                std::fprintf(stderr, "vkgi-bench: %s\n", all.error().message.c_str());
                return 1;
            }
            bench::References r{&(*matched)->full, &(*matched)->indirect, bounces, &(*all)->full, &(*all)->indirect};
            auto m = bench::measure(**ctx, *scene, sceneName, s, knobs, *opt, r);
            if (!m) {
                std::fprintf(stderr, "vkgi-bench: %s %s [%s]: %s\n", sceneName.c_str(), tech.c_str(), knobs.c_str(),
                             m.error().message.c_str());
                return 1;
            }
            if (!m->notApplicable.empty()) {
                // Every configuration would render the direct image again: one line instead of rows.
                progress.note("vkgi-bench: " + sceneName + ": " + tech + " left out (" + m->notApplicable + ")");
                notApplicable.insert(tech);
                continue;
            }
            m->record.streamGBs = *streamGBs;
            records.push_back(std::move(m->record));
        }
    }
    progress.finish();
    std::filesystem::create_directories(opt->outDir);
    std::string csv = gi::toCsv(records);
    Result<void> ok = writeFileAtomic(std::filesystem::path(opt->outDir) / "bench.csv", csv);
    if (ok)
        ok = writeFileAtomic(std::filesystem::path(opt->outDir) / "bench.json", gi::toJson(records));
    if (ok)
        ok = writeFileAtomic(std::filesystem::path(opt->outDir) / "bench.md", gi::toMarkdown(records));
    for (const auto& sceneName : opt->scenes)
        if (ok)
            ok = writeFileAtomic(std::filesystem::path(opt->outDir) / ("plot-" + std::filesystem::path(sceneName).stem().string() + ".svg"),
                                 gi::toSvgPlot(records, sceneName));
    if (!ok) {
        std::fprintf(stderr, "vkgi-bench: %s\n", ok.error().message.c_str());
        return 1;
    }
    // Errors against the reference with the technique's bounce count ("ref": reflections, -1 =
    // unbounded), then the indirect-only errors against the unbounded reference (the truth).
    // "total ms": the frame without pass timestamps; "prof ms": with them (what --passes splits).
    std::printf("%-8s %-5s %-40s %9s %9s %3s %10s %10s %10s | %10s %10s\n", "scene", "tech", "knobs", "total ms",
                "prof ms", "ref", "relMSE", "relMSE ind", "RMSE ind", "all: r.ind", "RMSE ind");
    for (const auto& r : records)
        std::printf("%-8s %-5s %-40s %9.2f %9.2f %3d %10.4g %10.4g %10.4g | %10.4g %10.4g\n", r.scene.c_str(),
                    r.technique.c_str(), r.knobs.c_str(), r.totalMs, r.profiledMs, r.referenceBounces, r.relMse,
                    r.relMseIndirect, r.rmseIndirect, r.relMseIndirectAll, r.rmseIndirectAll);
    std::printf("streaming rate (compute copy, 64 MiB): %.2f GB/s\n", *streamGBs);
    if (opt->passes)
        for (const auto& r : records) {
            std::printf("%s %s [%s]\n", r.scene.c_str(), r.technique.c_str(), r.knobs.c_str());
            for (size_t i = 0; i < r.passMs.size(); ++i) {
                double bytes = i < r.passBytes.size() ? r.passBytes[i].second : 0.0;
                std::printf("    %-32s %9.3f ms %9.2f MiB %8.2fx\n", r.passMs[i].first.c_str(), r.passMs[i].second,
                            bytes / (1024.0 * 1024.0), gi::streamRatio(r.passMs[i].second, bytes, *streamGBs));
            }
        }
    for (const auto& sceneName : opt->scenes)
        if (opt->budgetMs > 0.0) {
            long best = gi::bestWithinBudget(records, sceneName, opt->budgetMs);
            if (best < 0)
                std::printf("budget %.2f ms, %s: no configuration fits\n", opt->budgetMs, sceneName.c_str());
            else
                std::printf("budget %.2f ms, %s: %s %s (%.2f ms, relMSE %.4f)\n", opt->budgetMs, sceneName.c_str(),
                            records[size_t(best)].technique.c_str(), records[size_t(best)].knobs.c_str(),
                            records[size_t(best)].totalMs, records[size_t(best)].relMse);
        }
    std::printf("wrote %s/bench.csv, bench.json, bench.md and plots\n", opt->outDir.c_str());
    return 0;
}
