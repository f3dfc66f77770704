// Deferred direct lighting (one compute pass over the G-buffer for all lights), the composite
// and the readback of requested images.
#include "direct/direct_passes.hpp"

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

struct DeferredPass {
    GBufferData g;
    ShadowData shadow;
    rg::BufferHandle lights;
    rg::ImageHandle out;
    const DirectPipelines* p = nullptr;
    gpu::DeferredPush push{};
};

struct CompositePass {
    rg::ImageHandle direct, indirect, out;
    const DirectPipelines* p = nullptr;
    gpu::CompositePush push{};
};

struct ReadbackPass {
    rg::ImageHandle image;
    rg::BufferHandle buffer;
};

} // namespace

DirectData addDeferredPass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                           const SceneHandles& scene, const GBufferData& g, const ShadowData& shadow) {
    const GiSettings& s = *frame.settings;
    const DeferredPass& pass = graph.addPass<DeferredPass>(
        "gi.direct",
        [&](rg::PassBuilder& b, DeferredPass& d) {
            for (rg::ImageHandle h : {g.position, g.normal, g.albedo, g.emission})
                b.read(h, Access::ComputeStorageRead);
            b.read(shadow.atlas, Access::ComputeSampledRead);
            b.read(scene.lights, Access::ComputeStorageRead);
            b.read(shadow.views, Access::ComputeStorageRead);
            b.read(shadow.lightShadows, Access::ComputeStorageRead);
            d.out = b.write(b.create("gi.direct", radianceDesc(frame)), Access::ComputeStorageWriteDiscard);
            d.g = g;
            d.shadow.atlas = shadow.atlas;
            d.shadow.views = shadow.views;
            d.shadow.lightShadows = shadow.lightShadows;
            d.lights = scene.lights;
            d.p = &p;
            d.push.size = glm::uvec4(frame.width, frame.height, uint32_t(frame.scene->lights.size()), s.pcfRadius);
            d.push.bias = glm::vec4(s.shadowNormalOffset, s.shadowConstantBias, 0.0f, 0.0f);
        },
        [](const DeferredPass& d, rg::PassContext& pc) {
            const Pipeline& pl = d.p->deferred;
            VkSampler pt = d.p->pointSampler;
            pc.dispatch(pl, rg::PassContext::groupsFor(pl, {d.push.size.x, d.push.size.y, 1}), d.push,
                        {pc.storage(0, d.g.position), pc.storage(1, d.g.normal), pc.storage(2, d.g.albedo),
                         pc.storage(3, d.g.emission), pc.buffer(4, d.lights), pc.buffer(5, d.shadow.lightShadows),
                         pc.buffer(6, d.shadow.views), pc.sampled(7, d.shadow.atlas, pt),
                         pc.storage(8, d.out)});
        });
    return DirectData{pass.out};
}

CompositeData addCompositePass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                               rg::ImageHandle direct, rg::ImageHandle indirect) {
    const CompositePass& pass = graph.addPass<CompositePass>(
        "gi.composite",
        [&](rg::PassBuilder& b, CompositePass& d) {
            b.read(direct, Access::ComputeStorageRead);
            b.read(indirect, Access::ComputeStorageRead);
            d.out = b.write(b.create("gi.composite", radianceDesc(frame)), Access::ComputeStorageWriteDiscard);
            d.direct = direct;
            d.indirect = indirect;
            d.p = &p;
            d.push.size = glm::uvec4(frame.width, frame.height, 0u, 0u);
        },
        [](const CompositePass& d, rg::PassContext& pc) {
            const Pipeline& pl = d.p->composite;
            pc.dispatch(pl, rg::PassContext::groupsFor(pl, {d.push.size.x, d.push.size.y, 1}), d.push,
                        {pc.storage(0, d.direct), pc.storage(1, d.indirect), pc.storage(2, d.out)});
        });
    return CompositeData{pass.out};
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
