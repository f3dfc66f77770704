#include "support/gpu_util.hpp"

#include <memory>

#include <gtest/gtest.h>

namespace vkgi::test {

void toGeneral(VkCommandBuffer cmd, std::initializer_list<const Image*> images) {
    std::vector<VkImageMemoryBarrier2> bs;
    for (const Image* img : images) {
        VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
        b.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        b.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
        b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
        b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        b.image = img->image;
        b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, 1};
        bs.push_back(b);
    }
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = uint32_t(bs.size());
    dep.pImageMemoryBarriers = bs.data();
    vkCmdPipelineBarrier2(cmd, &dep);
}

namespace {

// Adds a pass that writes the host buffer `host` through `record(pc, hostBuffer)` after reading
// `source`, then compiles and executes the graph and returns the buffer's first `bytes`.
template <typename Handle, typename Record>
std::vector<uint8_t> runAndRead(Context& ctx, rg::RenderGraph& graph, Handle source, VkDeviceSize bytes,
                                rg::TransientPool* pool, Record record) {
    Buffer host = createBuffer(ctx, {bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::GpuToCpu}, "test.readback");
    rg::BufferHandle hostHandle = graph.importBuffer("test.readback", host, rg::Access::None);
    graph.addPass(
        "test.readback",
        [&](rg::PassBuilder& b) {
            b.read(source, rg::Access::TransferRead);
            hostHandle = b.write(hostHandle, rg::Access::TransferWrite);
            b.sideEffect();
        },
        [=](rg::PassContext& pc) { record(pc, source, pc.buffer(hostHandle).buffer); });
    graph.exportBuffer(hostHandle, rg::Access::HostRead);
    std::vector<uint8_t> out;
    auto compiled = graph.compile();
    EXPECT_TRUE(compiled) << (compiled ? "" : compiled.error().message);
    if (compiled) {
        std::unique_ptr<rg::TransientPool> own;
        if (!pool)
            pool = (own = std::make_unique<rg::TransientPool>(ctx)).get();
        ctx.submitAndWait([&](VkCommandBuffer cmd) { graph.execute(cmd, ctx, *pool); });
        out.resize(size_t(bytes));
        std::memcpy(out.data(), host.mapped(), out.size());
    }
    destroyBuffer(ctx, host);
    return out;
}

} // namespace

std::vector<uint8_t> runAndReadImage(Context& ctx, rg::RenderGraph& graph, rg::ImageHandle image, VkDeviceSize bytes,
                                     rg::TransientPool* pool) {
    return runAndRead(ctx, graph, image, bytes, pool, [bytes](rg::PassContext& pc, rg::ImageHandle src, VkBuffer dst) {
        const Image& img = pc.image(src);
        const ImageDesc& d = img.desc;
        VkDeviceSize size = VkDeviceSize(d.width) * d.height * d.depth * d.arrayLayers * formatBytes(d.format);
        EXPECT_EQ(size, bytes) << "runAndReadImage: the image holds another number of bytes";
        if (size != bytes)
            return;
        VkBufferImageCopy region{};
        region.imageSubresource = {aspectOf(d.format), 0, 0, d.arrayLayers};
        region.imageExtent = {d.width, d.height, d.depth};
        vkCmdCopyImageToBuffer(pc.cmd(), img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, 1, &region);
    });
}

std::vector<uint8_t> runAndReadBuffer(Context& ctx, rg::RenderGraph& graph, rg::BufferHandle buffer, VkDeviceSize bytes,
                                      rg::TransientPool* pool) {
    return runAndRead(ctx, graph, buffer, bytes, pool,
                      [bytes](rg::PassContext& pc, rg::BufferHandle src, VkBuffer dst) {
                          VkBufferCopy region{0, 0, bytes};
                          vkCmdCopyBuffer(pc.cmd(), pc.buffer(src).buffer, dst, 1, &region);
                      });
}

} // namespace vkgi::test
