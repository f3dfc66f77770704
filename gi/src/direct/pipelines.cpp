// Pipelines and samplers of the shared direct-lighting passes, created once per GiSystem.
#include "direct/direct_passes.hpp"

#include "vkgi/context.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

// `textured` = false removes the base-colour texture lookup (surface.h, constant_id 0).
Result<Pipeline> rasterPipeline(Context& ctx, const char* fragment, std::vector<VkFormat> colors,
                                bool textured = true, const char* vertex = "gi/direct/raster.vert") {
    GraphicsPipelineDesc d;
    d.specialization = {{0, textured ? 1u : 0u}};
    d.vertexShader = vertex;
    d.fragmentShader = fragment;
    d.colorFormats = std::move(colors);
    d.depthFormat = kDepthFormat;
    d.cullMode = VK_CULL_MODE_NONE; // surfaces are seen and reflect from both sides
    return createGraphicsPipeline(ctx, d);
}

} // namespace

Result<DirectPipelines> createDirectPipelines(Context& ctx) {
    DirectPipelines p;
    auto fail = [&](const Error& e) -> Result<DirectPipelines> {
        destroyDirectPipelines(ctx, p);
        return e;
    };
    auto gbuffer = rasterPipeline(ctx, "gi/direct/gbuffer.frag",
                                  {kPositionFormat, kNormalFormat, kAlbedoFormat, kEmissionFormat});
    if (!gbuffer)
        return fail(gbuffer.error());
    p.gbuffer = *gbuffer;
    auto gbufferUntextured = rasterPipeline(ctx, "gi/direct/gbuffer.frag",
                                            {kPositionFormat, kNormalFormat, kAlbedoFormat, kEmissionFormat}, false);
    if (!gbufferUntextured)
        return fail(gbufferUntextured.error());
    p.gbufferUntextured = *gbufferUntextured;
    auto shadow = rasterPipeline(ctx, "gi/direct/shadow.frag", {});
    if (!shadow)
        return fail(shadow.error());
    p.shadow = *shadow;
    auto rsm = rasterPipeline(ctx, "gi/direct/rsm.frag", {kPositionFormat, kNormalFormat, kRsmFluxFormat}, true,
                              "gi/direct/rsm.vert");
    if (!rsm)
        return fail(rsm.error());
    p.rsm = *rsm;
    auto rsmUntextured = rasterPipeline(ctx, "gi/direct/rsm.frag", {kPositionFormat, kNormalFormat, kRsmFluxFormat},
                                        false, "gi/direct/rsm.vert");
    if (!rsmUntextured)
        return fail(rsmUntextured.error());
    p.rsmUntextured = *rsmUntextured;
    auto deferred = createComputePipeline(ctx, {"gi/direct/deferred.comp", {}});
    if (!deferred)
        return fail(deferred.error());
    p.deferred = *deferred;
    auto composite = createComputePipeline(ctx, {"gi/direct/composite.comp", {}});
    if (!composite)
        return fail(composite.error());
    p.composite = *composite;
    auto hostPosition = createComputePipeline(ctx, {"gi/direct/host_position.comp", {}});
    if (!hostPosition)
        return fail(hostPosition.error());
    p.hostPosition = *hostPosition;
    SamplerDesc point;
    point.filter = VK_FILTER_NEAREST;
    point.mipmap = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    p.pointSampler = createSampler(ctx, point);
    SamplerDesc shadowDesc;
    shadowDesc.mipmap = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    shadowDesc.compare = true;
    p.shadowSampler = createSampler(ctx, shadowDesc);
    return p;
}

void destroyDirectPipelines(Context& ctx, DirectPipelines& p) {
    for (Pipeline* pl : {&p.gbuffer, &p.gbufferUntextured, &p.shadow, &p.rsm, &p.rsmUntextured, &p.deferred, &p.composite, &p.hostPosition})
        if (pl->pipeline)
            destroyPipeline(ctx, *pl);
    for (VkSampler s : {p.pointSampler, p.shadowSampler})
        if (s)
            vkDestroySampler(ctx.device(), s, nullptr);
    p = DirectPipelines{};
}

void beginRendering(VkCommandBuffer cmd, VkExtent2D extent, const std::vector<VkImageView>& colors, VkImageView depth) {
    std::vector<VkRenderingAttachmentInfo> color(colors.size());
    for (size_t i = 0; i < colors.size(); ++i) {
        color[i] = {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        color[i].imageView = colors[i];
        color[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        color[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        color[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    }
    VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depthInfo.imageView = depth;
    depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depthInfo.clearValue.depthStencil = {1.0f, 0};
    VkRenderingInfo info{VK_STRUCTURE_TYPE_RENDERING_INFO};
    info.renderArea = {{0, 0}, extent};
    info.layerCount = 1;
    info.colorAttachmentCount = uint32_t(color.size());
    info.pColorAttachments = color.data();
    info.pDepthAttachment = &depthInfo;
    vkCmdBeginRendering(cmd, &info);
    VkViewport vp{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &vp);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
}

} // namespace vkgi::gi
