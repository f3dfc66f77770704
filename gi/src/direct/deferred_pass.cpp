// Deferred direct lighting (one compute pass over the G-buffer for all lights), the composite
// and the readback of requested images.
#include "direct/direct_passes.hpp"

#include "vkgi/rg/compute_pass.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

using rg::Access;

ImageDesc radianceDesc(const FrameData& frame) {
    ImageDesc d;
    d.format = kRadianceFormat;
    d.width = frame.width;
    d.height = frame.height;
    return d;
}

struct ReadbackPass {
    rg::ImageHandle image;
    rg::BufferHandle buffer;
};

} // namespace

DirectData addDeferredPass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                           const SceneHandles& scene, const GBufferData& g, const ShadowData& shadow) {
    const GiSettings& s = *frame.settings;
    gpu::DeferredPush push{};
    push.size = glm::uvec4(frame.width, frame.height, uint32_t(frame.scene->lights.size()), s.pcfRadius);
    push.bias = glm::vec4(s.shadowNormalOffset, s.shadowConstantBias, 0.0f, 0.0f);
    rg::ImageHandle out = graph.createImage("gi.direct", radianceDesc(frame));
    rg::ComputePass(graph, "gi.direct", p.deferred)
        .push(push)
        .read(DIRECT_DEFERRED_BINDING_POSITION, g.position)
        .read(DIRECT_DEFERRED_BINDING_NORMAL, g.normal)
        .read(DIRECT_DEFERRED_BINDING_ALBEDO, g.albedo)
        .read(DIRECT_DEFERRED_BINDING_EMISSION, g.emission)
        .read(DIRECT_DEFERRED_BINDING_LIGHTS, scene.lights)
        .read(DIRECT_DEFERRED_BINDING_LIGHT_SHADOWS, shadow.lightShadows)
        .read(DIRECT_DEFERRED_BINDING_SHADOW_VIEWS, shadow.views)
        .sample(DIRECT_DEFERRED_BINDING_SHADOW_ATLAS, shadow.atlas, p.pointSampler)
        .overwrite(DIRECT_DEFERRED_BINDING_OUTPUT, out)
        .dispatch({frame.width, frame.height, 1});
    return DirectData{out};
}

CompositeData addCompositePass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                               rg::ImageHandle direct, rg::ImageHandle indirect) {
    gpu::CompositePush push{};
    push.size = glm::uvec4(frame.width, frame.height, 0u, 0u);
    rg::ImageHandle out = graph.createImage("gi.composite", radianceDesc(frame));
    rg::ComputePass(graph, "gi.composite", p.composite)
        .push(push)
        .read(DIRECT_COMPOSITE_BINDING_DIRECT, direct)
        .read(DIRECT_COMPOSITE_BINDING_INDIRECT, indirect)
        .overwrite(DIRECT_COMPOSITE_BINDING_OUTPUT, out)
        .dispatch({frame.width, frame.height, 1});
    return CompositeData{out};
}

void addReadbackPass(rg::RenderGraph& graph, const std::string& name, rg::ImageHandle image, const Buffer& dst) {
    rg::BufferHandle buffer = graph.importBuffer(name + ".buffer", dst, Access::HostRead);
    const ReadbackPass& pass = graph.addPass<ReadbackPass>(
        name,
        [&](rg::PassBuilder& b, ReadbackPass& d) {
            b.read(image, Access::TransferRead);
            d.image = image;
            d.buffer = b.write(buffer, Access::TransferWrite);
            b.sideEffect();
        },
        [](const ReadbackPass& d, rg::PassContext& pc) {
            const Image& img = pc.image(d.image);
            VkBufferImageCopy region{};
            region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.imageExtent = {img.desc.width, img.desc.height, 1};
            vkCmdCopyImageToBuffer(pc.cmd(), img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                   pc.buffer(d.buffer).buffer, 1, &region);
        });
    graph.exportBuffer(pass.buffer, Access::HostRead);
}

HdrImage readbackToImage(const Buffer& src, uint32_t width, uint32_t height, ReadbackChannels channels) {
    HdrImage img(width, height);
    const auto* texels = static_cast<const glm::vec4*>(src.mapped());
    for (size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = channels == ReadbackChannels::AlphaToRgb ? glm::vec3(texels[i].w) : glm::vec3(texels[i]);
    return img;
}

} // namespace vkgi::gi
