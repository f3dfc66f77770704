#include "stream.hpp"

#include <algorithm>
#include <vector>

#include "vkgi/pipeline.hpp"
#include "vkgi/rg/compute_pass.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "engine/test_bindings.h"

namespace vkgi::bench {

namespace {
struct StreamPush {
    uint32_t count[4];
};
} // namespace

Result<double> measureStreamGBs(Context& ctx, uint32_t mib, uint32_t repeats) {
    auto pipeline = createComputePipeline(ctx, {"engine/stream_copy.comp", {}});
    if (!pipeline)
        return pipeline.error();
    const VkDeviceSize bytes = VkDeviceSize(mib) << 20;
    const uint32_t elements = uint32_t(bytes / 16);
    // 64 invocations per group; groups spread over x and y (x capped at 65535 groups).
    const uint32_t groups = (elements + 63) / 64;
    const uint32_t gx = std::min(groups, 4096u), gy = (groups + gx - 1) / gx;
    rg::TransientPool pool(ctx);
    TimestampPool timestamps(ctx, 4); // the graph's frame scope + fill + copy
    std::vector<double> ms;
    for (uint32_t r = 0; r <= repeats; ++r) { // r = 0 pays the shader JIT
        rg::RenderGraph g;
        rg::BufferHandle src = g.createBuffer("stream.src", {bytes});
        rg::BufferHandle dst = g.createBuffer("stream.dst", {bytes});
        const Pipeline* p = &*pipeline;
        g.addPass(
            "stream.fill", [&](rg::PassBuilder& b) { src = b.write(src, rg::Access::TransferWrite); },
            [=](rg::PassContext& c) { vkCmdFillBuffer(c.cmd(), c.buffer(src).buffer, 0, VK_WHOLE_SIZE, 0x3f800000u); });
        rg::ComputePass(g, "stream.copy", *p)
            .push(StreamPush{{elements, 0, 0, 0}})
            .read(ENGINE_STREAM_COPY_BINDING_SOURCE, src)
            .overwrite(ENGINE_STREAM_COPY_BINDING_TARGET, dst)
            .sideEffect()
            .dispatchGroups({gx, gy, 1});
        if (auto ok = g.compile(); !ok)
            return ok.error();
        ctx.submitAndWait([&](VkCommandBuffer cmd) { g.execute(cmd, ctx, pool, &timestamps); });
        if (r == 0)
            continue;
        for (const rg::PassTiming& t : g.timings())
            if (t.name == "stream.copy")
                ms.push_back(t.ms);
    }
    destroyPipeline(ctx, *pipeline);
    if (ms.empty())
        return makeError("stream probe: the device has no timestamps");
    std::sort(ms.begin(), ms.end());
    double median = ms[ms.size() / 2];
    return 2.0 * double(bytes) / (median * 1e6); // read + write, GB/s
}

} // namespace vkgi::bench
