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

#include "cli.hpp"
#include "vkgi/file_util.hpp"
#include "vkgi/gltf_loader.hpp"
#include "vkgi/progress.hpp"
#include "vkgi/knobs.hpp"
#include "vkgi/reference.hpp"
#include "flight.hpp"
#include "jit.hpp"
#include "scaling.hpp"
#include "stream.hpp"
#include "sweep.hpp"

using namespace vkgi;

namespace {

// bench.csv, bench.json, bench.md and one plot per scene into --out.
Result<void> writeOutputs(const bench::Options& opt, const std::vector<gi::BenchRecord>& records) {
    std::filesystem::path dir(opt.outDir);
    std::filesystem::create_directories(dir);
    Result<void> ok = writeFileAtomic(dir / "bench.csv", gi::toCsv(records));
    if (ok)
        ok = writeFileAtomic(dir / "bench.json", gi::toJson(records));
    if (ok)
        ok = writeFileAtomic(dir / "bench.md", gi::toMarkdown(records));
    for (const auto& sceneName : opt.scenes)
        if (ok)
            ok = writeFileAtomic(dir / ("plot-" + std::filesystem::path(sceneName).stem().string() + ".svg"),
                                 gi::toSvgPlot(records, sceneName));
    return ok;
}

// The table of every configuration, the streaming rate, --passes and --budget-ms.
void printReport(const bench::Options& opt, const std::vector<gi::BenchRecord>& records, double streamGBs) {
    // Errors against the reference with the technique's bounce count ("ref": reflections, -1 =
    // unbounded), then the indirect-only errors against the unbounded reference (the truth).
    // "total ms": the frame without pass timestamps; "prof ms": with them (what --passes splits);
    // "x direct": the frame over the same system's direct-only frame, rendered alternately.
    std::printf("%-8s %-5s %-40s %9s %9s %8s %3s %10s %10s %10s | %10s %10s\n", "scene", "tech", "knobs", "total ms",
                "prof ms", "x direct", "ref", "relMSE", "relMSE ind", "RMSE ind", "all: r.ind", "RMSE ind");
    for (const auto& r : records)
        std::printf("%-8s %-5s %-40s %9.2f %9.2f %8.2f %3d %10.4g %10.4g %10.4g | %10.4g %10.4g\n", r.scene.c_str(),
                    r.technique.c_str(), r.knobs.c_str(), r.totalMs, r.profiledMs,
                    r.directMs > 0.0 ? r.totalMs / r.directMs : 0.0, r.referenceBounces, r.relMse, r.relMseIndirect,
                    r.rmseIndirect, r.relMseIndirectAll, r.rmseIndirectAll);
    std::printf("streaming rate (compute copy, 64 MiB): %.2f GB/s\n", streamGBs);
    if (opt.passes)
        for (const auto& r : records) {
            std::printf("%s %s [%s]\n", r.scene.c_str(), r.technique.c_str(), r.knobs.c_str());
            for (size_t i = 0; i < r.passMs.size(); ++i) {
                double bytes = i < r.passBytes.size() ? r.passBytes[i].second : 0.0;
                std::printf("    %-32s %9.3f ms %9.2f MiB %8.2fx\n", r.passMs[i].first.c_str(), r.passMs[i].second,
                            bytes / (1024.0 * 1024.0), gi::streamRatio(r.passMs[i].second, bytes, streamGBs));
            }
        }
    for (const auto& sceneName : opt.scenes)
        if (opt.budgetMs > 0.0) {
            long best = gi::bestWithinBudget(records, sceneName, opt.budgetMs);
            if (best < 0)
                std::printf("budget %.2f ms, %s: no configuration fits\n", opt.budgetMs, sceneName.c_str());
            else
                std::printf("budget %.2f ms, %s: %s %s (%.2f ms, relMSE %.4f)\n", opt.budgetMs, sceneName.c_str(),
                            records[size_t(best)].technique.c_str(), records[size_t(best)].knobs.c_str(),
                            records[size_t(best)].totalMs, records[size_t(best)].relMse);
        }
}

// The default mode: every scene x technique x configuration against the path-traced reference.
int runTable(Context& ctx, const bench::Options& opt) {
    // The streaming rate every pass is compared with, measured now on this device and load.
    auto streamGBs = bench::measureStreamGBs(ctx);
    if (!streamGBs) {
        std::fprintf(stderr, "vkgi-bench: %s\n", streamGBs.error().message.c_str());
        return 1;
    }
    std::vector<std::pair<std::string, std::string>> jobs; // technique, knobs
    for (const auto& t : opt.techniques)
        for (const auto& k : !opt.set ? bench::sweepFor(t, opt.quick)
                             : t == "none" ? std::vector<std::string>{""}
                                           : std::vector<std::string>{*opt.set})
            jobs.push_back({t, k});
    std::vector<Scene> scenes; // all loaded up front: a bad name fails before any long work
    for (const auto& sceneName : opt.scenes) {
        auto scene = loadScene(sceneName);
        if (!scene) {
            std::fprintf(stderr, "vkgi-bench: %s\n", scene.error().message.c_str());
            return 1;
        }
        scenes.push_back(std::move(*scene));
    }
    std::vector<gi::BenchRecord> records;
    Progress progress("vkgi-bench", jobs.size() * opt.scenes.size());
    for (size_t si = 0; si < scenes.size(); ++si) {
        const std::string& sceneName = opt.scenes[si];
        const Scene* scene = &scenes[si];
        std::map<int, gi::ReferenceImages> refs; // by bounce count
        auto reference = [&](int bounces) -> Result<const gi::ReferenceImages*> {
            if (!refs.count(bounces)) {
                gi::ReferenceSettings rs;
                rs.spp = opt.spp;
                rs.maxBounces = bounces;
                auto ref = gi::renderReferenceCached(*scene, scene->cameraOrDefault(), opt.width, opt.height, rs);
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
            int bounces = gi::modelledBounces(s, scene);
            bounces = bounces < 0 ? -1 : std::max(bounces, 2);
            auto matched = reference(bounces);
            auto all = matched ? reference(-1) : matched;
            if (!all) {
                std::fprintf(stderr, "vkgi-bench: %s\n", all.error().message.c_str());
                return 1;
            }
            bench::References r{&(*matched)->full, &(*matched)->indirect, bounces, &(*all)->full, &(*all)->indirect};
            auto m = bench::measure(ctx, *scene, sceneName, s, knobs, opt, r);
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
            if (m->ambient) // the baseline row, beside the direct image's
                records.push_back(std::move(*m->ambient));
        }
    }
    progress.finish();
    if (auto ok = writeOutputs(opt, records); !ok) {
        std::fprintf(stderr, "vkgi-bench: %s\n", ok.error().message.c_str());
        return 1;
    }
    printReport(opt, records, *streamGBs);
    std::printf("wrote %s/bench.csv, bench.json, bench.md and plots\n", opt.outDir.c_str());
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    auto opt = bench::parseArgs(argc, argv);
    if (!opt) {
        std::fprintf(stderr, "vkgi-bench: %s\n", opt.error().message.c_str());
        return 2;
    }
    if (opt->help) {
        std::fputs(bench::helpText().c_str(), stdout);
        return 0;
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
    int code = opt->scaling ? bench::runScaling(**ctx, *opt)
               : opt->jit   ? bench::runJit(**ctx, *opt)
               : opt->flight ? bench::runFlight(**ctx, *opt)
                             : runTable(**ctx, *opt);
    // With VKGI_VALIDATION=1 any message (printed as it came) fails the run; counted once the
    // context is destroyed, which reports the objects it still held.
    const std::shared_ptr<const ValidationLog> log = (*ctx)->sharedValidation();
    ctx->reset();
    if (uint32_t n = log->count(); n > 0) {
        std::fprintf(stderr, "vkgi-bench: %u validation message(s) (printed above)\n", n);
        return 3;
    }
    return code;
}
