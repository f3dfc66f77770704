// Host G-buffer path: the host's depth/normal/albedo(/position) images stand in for the
// G-buffer pass; the graph derives every barrier from the access the host says they are in.
#include "direct/host_gbuffer.hpp"

#include <string>

#include "vkgi/rg/compute_pass.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

using rg::Access;

std::string formatName(VkFormat f) {
    switch (f) {
    case VK_FORMAT_D32_SFLOAT: return "D32_SFLOAT";
    case VK_FORMAT_R16G16B16A16_SFLOAT: return "R16G16B16A16_SFLOAT";
    case VK_FORMAT_R32G32B32A32_SFLOAT: return "R32G32B32A32_SFLOAT";
    default: return "VkFormat " + std::to_string(int(f));
    }
}

Result<void> checkImage(const std::string& name, const HostImage& im, std::initializer_list<VkFormat> formats,
                        VkImageUsageFlags usage, uint32_t width, uint32_t height, bool input) {
    if (!im.image || !im.view)
        return makeError(name + ": image and view must be set");
    bool formatOk = false;
    std::string expected;
    for (VkFormat f : formats) {
        formatOk = formatOk || im.format == f;
        expected += (expected.empty() ? "" : " or ") + formatName(f);
    }
    if (!formatOk)
        return makeError(name + ": format " + formatName(im.format) + " is not " + expected);
    if (im.width != width || im.height != height)
        return makeError(name + ": size " + std::to_string(im.width) + "x" + std::to_string(im.height) +
                         " differs from the G-buffer normal's " + std::to_string(width) + "x" + std::to_string(height));
    if ((im.usage & usage) != usage)
        return makeError(name + ": usage lacks bits vkgi needs (SAMPLED/STORAGE for inputs, TRANSFER_DST for the output)");
    if (int(im.access) >= int(Access::Count) || !rg::accessInfo(im.access).image)
        return makeError(name + ": access " + std::to_string(int(im.access)) + " is not an image access");
    if (input && im.access == Access::None)
        return makeError(name + ": access None means undefined contents; give the access the host wrote it with");
    return {};
}

Image asImage(const HostImage& h) {
    Image img;
    img.image = h.image;
    img.view = h.view;
    img.mipViews = {h.view};
    img.layerViews = {h.view};
    img.desc.format = h.format;
    img.desc.width = h.width;
    img.desc.height = h.height;
    img.desc.usage = h.usage;
    return img;
}

struct HostCopyPass {
    rg::ImageHandle src, dst;
    VkFormat srcFormat = VK_FORMAT_UNDEFINED;
    VkFormat dstFormat = VK_FORMAT_UNDEFINED;
};

} // namespace

Result<void> checkHostGBuffer(const HostGBuffer& g) {
    uint32_t w = g.normal.width, h = g.normal.height;
    if (w == 0 || h == 0 || w > 16384 || h > 16384)
        return makeError("HostGBuffer.normal: size " + std::to_string(w) + "x" + std::to_string(h) +
                         " is outside 1..16384");
    constexpr VkImageUsageFlags kRead = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
    if (auto ok = checkImage("HostGBuffer.normal", g.normal, {kNormalFormat}, kRead, w, h, true); !ok)
        return ok;
    if (auto ok = checkImage("HostGBuffer.albedo", g.albedo, {kAlbedoFormat}, kRead, w, h, true); !ok)
        return ok;
    if (g.position.image)
        return checkImage("HostGBuffer.position", g.position, {kPositionFormat}, kRead, w, h, true);
    return checkImage("HostGBuffer.depth", g.depth, {kDepthFormat}, VK_IMAGE_USAGE_SAMPLED_BIT, w, h, true);
}

Result<void> checkHostIndirect(const HostImage& target, const HostGBuffer& g) {
    return checkImage("HostFrame.indirect", target, {kRadianceFormat, VK_FORMAT_R16G16B16A16_SFLOAT},
                      VK_IMAGE_USAGE_TRANSFER_DST_BIT, g.normal.width, g.normal.height, false);
}

Result<void> checkFinalAccess(const char* name, rg::Access access) {
    if (int(access) >= int(Access::Count) || access == Access::None || !rg::accessInfo(access).image ||
        rg::accessInfo(access).write)
        return makeError(std::string(name) + ": " + (int(access) < int(Access::Count) ? rg::toString(access) : "?") +
                         " is not a read access of images (e.g. FragmentSampledRead)");
    return {};
}

void exportHostGBuffer(rg::RenderGraph& graph, const GBufferData& imported, const HostGBuffer& g,
                       rg::Access finalAccess) {
    graph.exportImage(imported.normal, finalAccess);
    graph.exportImage(imported.albedo, finalAccess);
    graph.exportImage(g.position.image ? imported.position : imported.depth, finalAccess);
}

GBufferData importHostGBuffer(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                              const HostGBuffer& g) {
    GBufferData out;
    out.normal = graph.importImage("host.normal", asImage(g.normal), g.normal.access);
    out.albedo = graph.importImage("host.albedo", asImage(g.albedo), g.albedo.access);
    if (g.position.image) {
        out.position = graph.importImage("host.position", asImage(g.position), g.position.access);
        return out;
    }
    out.depth = graph.importImage("host.depth", asImage(g.depth), g.depth.access);
    gpu::HostPositionPush push{};
    push.invViewProj = frame.invViewProj;
    push.size = glm::uvec4(frame.width, frame.height, 0u, 0u);
    ImageDesc desc;
    desc.format = kPositionFormat;
    desc.width = frame.width;
    desc.height = frame.height;
    out.position = graph.createImage("gbuffer.position", desc);
    rg::ComputePass(graph, "gi.host.position", p.hostPosition)
        .push(push)
        .sample(DIRECT_HOST_POSITION_BINDING_DEPTH, out.depth, p.pointSampler)
        .overwrite(DIRECT_HOST_POSITION_BINDING_OUTPUT, out.position)
        .dispatch({frame.width, frame.height, 1});
    return out;
}

void addHostIndirectCopy(rg::RenderGraph& graph, rg::ImageHandle indirect, const HostImage& target,
                         rg::Access finalAccess) {
    rg::ImageHandle dst = graph.importImage("host.indirect", asImage(target), target.access);
    const HostCopyPass& pass = graph.addPass<HostCopyPass>(
        "gi.host.indirect",
        [&](rg::PassBuilder& b, HostCopyPass& d) {
            b.read(indirect, Access::TransferRead);
            d.src = indirect;
            d.dst = b.write(dst, Access::TransferWrite);
            d.srcFormat = kRadianceFormat;
            d.dstFormat = target.format;
        },
        [](const HostCopyPass& d, rg::PassContext& pc) {
            const Image& src = pc.image(d.src);
            const Image& dstImage = pc.image(d.dst);
            VkImageSubresourceLayers layers{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            if (d.srcFormat == d.dstFormat) {
                VkImageCopy region{};
                region.srcSubresource = layers;
                region.dstSubresource = layers;
                region.extent = {src.desc.width, src.desc.height, 1};
                vkCmdCopyImage(pc.cmd(), src.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dstImage.image,
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
                return;
            }
            VkImageBlit blit{};
            blit.srcSubresource = layers;
            blit.dstSubresource = layers;
            blit.srcOffsets[1] = {int32_t(src.desc.width), int32_t(src.desc.height), 1};
            blit.dstOffsets[1] = blit.srcOffsets[1];
            vkCmdBlitImage(pc.cmd(), src.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dstImage.image,
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_NEAREST);
        });
    graph.exportImage(pass.dst, finalAccess);
}

} // namespace vkgi::gi
