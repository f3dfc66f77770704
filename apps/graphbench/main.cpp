// vkgi-graphbench: what the render graph itself costs.
//  1. CPU: declaring + compiling graphs of 10/100/1000 passes (median of repeats).
//  2. GPU (lavapipe by default via VK_DRIVER_FILES): N one-group dispatches as N graph passes,
//     either chained through one buffer (a barrier before every pass) or independent (no
//     barriers), against a single-pass graph; total, per-pass GPU ms (timestamp scopes hold
//     the dispatch only) and submit wall time (dispatches + barriers + timestamps).
// Usage: vkgi-graphbench [dispatch passes, default 200]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <vector>

#include "../common/args.hpp"
#include "vkgi/context.hpp"
#include "vkgi/pipeline.hpp"
#include "vkgi/rg/compute_pass.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "engine/test_bindings.h"

using namespace vkgi;
using namespace vkgi::rg;

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// A realistic shape: each pass reads the previous result and two of the passes before it,
// writes a new 64x64 image; after every fourth pass a debug pass nobody reads is culled.
void declareChain(RenderGraph& g, uint32_t passes) {
    ImageDesc desc;
    desc.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    desc.width = desc.height = 64;
    std::vector<ImageHandle> outs;
    for (uint32_t i = 0; i < passes; ++i) {
        ImageHandle out = g.createImage("img", desc);
        g.addPass(
            "pass",
            [&](PassBuilder& b) {
                for (size_t back = 1; back <= 3 && back <= outs.size(); ++back)
                    b.read(outs[outs.size() - back], Access::ComputeSampledRead);
                out = b.write(out, Access::ComputeStorageWriteDiscard);
            },
            [](PassContext&) {});
        outs.push_back(out);
        if (i % 4 == 3)
            g.addPass(
                "debug",
                [&](PassBuilder& b) {
                    b.read(out, Access::ComputeSampledRead);
                    (void)b.write(b.create("debug", desc), Access::ComputeStorageWrite);
                },
                [](PassContext&) {});
    }
    g.markOutput(outs.back());
}

void benchCompile() {
    std::printf("graph declare + compile (median; plus one culled debug pass per 4 passes)\n");
    std::printf("%8s %8s %12s %12s %14s\n", "passes", "repeats", "declare ms", "compile ms", "compile us/pass");
    for (uint32_t passes : {10u, 100u, 1000u}) {
        uint32_t repeats = passes >= 1000 ? 15 : 51; // odd, so the median is one sample
        std::vector<double> declare, compile;
        for (uint32_t r = 0; r < repeats; ++r) {
            RenderGraph g;
            auto t0 = Clock::now();
            declareChain(g, passes);
            declare.push_back(msSince(t0));
            auto t1 = Clock::now();
            if (!g.compile())
                std::abort();
            compile.push_back(msSince(t1));
        }
        double c = median(compile);
        std::printf("%8u %8u %12.3f %12.3f %14.2f\n", passes, repeats, median(declare), c, 1000.0 * c / passes);
    }
}

struct GpuRun {
    double recordMs = 0, submitMs = 0, gpuMs = 0;
};

// Records `passes` tiny dispatches; chained = all on one buffer (read-modify-write, so a
// barrier before each pass), else each pass has its own buffer (no barriers at all).
GpuRun runDispatches(Context& ctx, const Pipeline& tiny, TransientPool& pool, TimestampPool* ts, uint32_t passes,
                     bool chained) {
    RenderGraph g;
    BufferHandle shared = g.createBuffer("counter", {64});
    const Pipeline* p = &tiny;
    for (uint32_t i = 0; i < passes; ++i) {
        BufferHandle buf = chained ? shared : g.createBuffer("counter", {64});
        ComputePass pass(g, "tiny", *p);
        if (i == 0 || !chained)
            pass.overwrite(ENGINE_TINY_BINDING_COUNTER, buf);
        else
            pass.write(ENGINE_TINY_BINDING_COUNTER, buf);
        pass.sideEffect().dispatchGroups({1, 1, 1});
        if (chained)
            shared = buf;
    }
    if (!g.compile())
        std::abort();
    GpuRun run;
    auto t0 = Clock::now();
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        auto r0 = Clock::now();
        g.execute(cmd, ctx, pool, ts);
        run.recordMs = msSince(r0);
    });
    run.submitMs = msSince(t0) - run.recordMs;
    for (const PassTiming& t : g.timings())
        run.gpuMs += t.ms;
    return run;
}

void benchDispatch(Context& ctx, uint32_t passes) {
    auto tiny = createComputePipeline(ctx, {"engine/test/tiny.comp", {}});
    if (!tiny) {
        std::fprintf(stderr, "vkgi-graphbench: %s\n", tiny.error().message.c_str());
        std::exit(1);
    }
    TransientPool pool(ctx);
    TimestampPool ts(ctx, passes + 1); // + the graph's frame scope
    runDispatches(ctx, *tiny, pool, &ts, passes, true); // warm-up: JIT, pool entries
    std::printf("\ntiny dispatches on %s (median of 21)\n", ctx.properties().deviceName);
    std::printf("%-22s %7s %11s %15s %12s %15s\n", "graph", "passes", "record ms", "submit+wait ms", "gpu sum ms",
                "gpu ms per pass");
    struct Case {
        const char* name;
        uint32_t passes;
        bool chained;
        bool timed;
    };
    // "independent" uses a fresh pool per run: reused entries would need a first-use barrier
    // against the previous run, and this case is meant to have none.
    for (Case c :
         {Case{"one pass", 1, true, true}, Case{"chained (barriers)", passes, true, true},
          Case{"chained, no timestamps", passes, true, false}, Case{"independent (none)", passes, false, true}}) {
        std::vector<double> rec, sub, gpu;
        for (int r = 0; r < 21; ++r) {
            TransientPool fresh(ctx);
            GpuRun run =
                runDispatches(ctx, *tiny, c.chained ? pool : fresh, c.timed ? &ts : nullptr, c.passes, c.chained);
            vkDeviceWaitIdle(ctx.device());
            rec.push_back(run.recordMs);
            sub.push_back(run.submitMs);
            gpu.push_back(run.gpuMs);
        }
        std::printf("%-22s %7u %11.3f %15.3f %12.3f %15.4f\n", c.name, c.passes, median(rec), median(sub), median(gpu),
                    median(gpu) / c.passes);
    }
    pool.clear();
    destroyPipeline(ctx, *tiny);
}

} // namespace

int main(int argc, char** argv) {
    uint32_t passes = 200;
    if (argc > 1) {
        auto n = apps::parseWhole("dispatch passes", argv[1], 2, 100000);
        if (!n) {
            std::fprintf(stderr, "vkgi-graphbench: %s\n", n.error().message.c_str());
            return 1;
        }
        passes = uint32_t(*n);
    }
    benchCompile();
    auto ctx = defaultDeviceBuilder().build();
    if (!ctx) {
        std::fprintf(stderr, "vkgi-graphbench: no Vulkan device: %s\n", ctx.error().message.c_str());
        return 1;
    }
    benchDispatch(**ctx, passes);
    return 0;
}
