#include "jit.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "vkgi/builtin_scenes.hpp"
#include "vkgi/file_util.hpp"
#include "vkgi/progress.hpp"
#include "vkgi/knobs.hpp"

namespace vkgi::bench {

namespace {

struct JitConfig {
    const char* scene;
    const char* technique;
    const char* knobs;
};

// Defaults first, then the knobs that switch in passes or shader variants of their own.
constexpr JitConfig kConfigs[] = {
    {"cornell", "none", ""},
    {"cornell", "vpl", ""},
    {"cornell", "vpl", "vpl.negative=100 vpl.lowres=2"},
    {"cornell", "lpv", ""},
    {"cornell", "lpv", "lpv.bounces=on lpv.half=off lpv.rsm_reduce=4"},
    {"room", "lpv", "lpv.cascades=2"},
    {"cornell", "vct", ""},
    {"cornell", "vct", "vct.soft_shadows=on vct.lowres=1 vct.bounces=1"},
    {"cornell_emissive", "vct", ""},
};

struct Row {
    std::string config;
    std::string pass;
    double firstMs = 0.0, warmMs = 0.0;
    double jitMs() const { return std::max(0.0, firstMs - warmMs); }
};

} // namespace

int runJit(Context& ctx, const Options& opt) {
    std::vector<Row> rows;
    std::vector<std::pair<std::string, double>> frames; // config, first-frame total - warm total
    Progress progress("vkgi-bench --jit", std::size(kConfigs));
    for (const JitConfig& c : kConfigs) {
        progress.add(1);
        if (std::find(opt.techniques.begin(), opt.techniques.end(), c.technique) == opt.techniques.end())
            continue;
        auto scene = makeBuiltinScene(c.scene);
        if (!scene) {
            std::fprintf(stderr, "vkgi-bench: %s\n", scene.error().message.c_str());
            return 1;
        }
        gi::GiSettings s;
        s.technique = *gi::parseTechnique(c.technique);
        std::stringstream in(c.knobs);
        for (std::string kv; in >> kv;)
            if (auto ok = gi::applyKnob(s, kv); !ok) {
                std::fprintf(stderr, "vkgi-bench: %s\n", ok.error().message.c_str());
                return 1;
            }
        gi::FrameRequest request;
        request.indirect = s.technique != gi::Technique::None;
        auto invalidate = [](gi::GiSystem& sys) -> Result<void> {
            sys.invalidate();
            return {};
        };
        // The compiling frame: a fresh GiSystem, no warm-up.
        auto first = measureTiming(ctx, *scene, s, opt.width, opt.height, 1, request, invalidate, 0);
        if (!first) {
            std::fprintf(stderr, "vkgi-bench: %s %s [%s]: %s\n", c.scene, c.technique, c.knobs,
                         first.error().message.c_str());
            return 1;
        }
        // Warm frames: another GiSystem compiles its own pipelines again in its warm-up frame.
        auto warm = measureTiming(ctx, *scene, s, opt.width, opt.height, opt.repeat, request, invalidate, 1);
        if (!warm) {
            std::fprintf(stderr, "vkgi-bench: %s %s [%s]: %s\n", c.scene, c.technique, c.knobs,
                         warm.error().message.c_str());
            return 1;
        }
        std::string name = std::string(c.scene) + " " + c.technique + (c.knobs[0] ? std::string(" [") + c.knobs + "]" : "");
        for (const auto& [pass, ms] : first->passMs) {
            Row r{name, pass, ms, 0.0};
            for (const auto& [wpass, wms] : warm->passMs)
                if (wpass == pass)
                    r.warmMs = wms;
            rows.push_back(r);
        }
        // Profiled against profiled: the compiling frame is the first one rendered, which is the
        // profiled one of measureTiming's pair (its unprofiled twin runs warm).
        frames.push_back({name, first->profiledMs - warm->profiledMs});
    }
    progress.finish();

    std::ostringstream csv;
    csv << "configuration,pass,first_frame_ms,warm_ms,jit_ms\n";
    for (const Row& r : rows)
        csv << '"' << r.config << "\"," << r.pass << "," << r.firstMs << "," << r.warmMs << "," << r.jitMs() << "\n";
    std::filesystem::create_directories(opt.outDir);
    if (auto ok = writeFileAtomic(std::filesystem::path(opt.outDir) / "jit.csv", csv.str()); !ok) {
        std::fprintf(stderr, "vkgi-bench: %s\n", ok.error().message.c_str());
        return 1;
    }
    std::vector<const Row*> sorted;
    for (const Row& r : rows)
        sorted.push_back(&r);
    std::sort(sorted.begin(), sorted.end(), [](const Row* a, const Row* b) { return a->jitMs() > b->jitMs(); });
    std::printf("%-60s %-28s %10s %9s %9s\n", "configuration", "pass", "first ms", "warm ms", "JIT ms");
    size_t over = 0;
    for (const Row* r : sorted) {
        over += r->jitMs() > 1000.0 ? 1 : 0;
        if (r->jitMs() >= 1.0)
            std::printf("%-60s %-28s %10.1f %9.1f %9.1f\n", r->config.c_str(), r->pass.c_str(), r->firstMs, r->warmMs,
                        r->jitMs());
    }
    for (const auto& [name, ms] : frames)
        std::printf("first frame of %s: +%.0f ms\n", name.c_str(), ms);
    std::printf("passes whose first dispatch costs over 1 s: %zu\n", over);
    std::printf("wrote %s/jit.csv\n", opt.outDir.c_str());
    return 0;
}

} // namespace vkgi::bench
