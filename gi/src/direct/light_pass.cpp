// Per-light shadow map and (on request) reflective shadow map, in one pass per light: the
// depth and the RSM targets of the light's atlas layers are written by the same draws.
#include <memory>
#include <string>

#include "direct/direct_passes.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

std::string lightPassName(uint32_t light, LightType type) {
    const char* kind = type == LightType::Directional ? "directional" : type == LightType::Point ? "point" : "spot";
    return "gi.light[" + std::to_string(light) + "]." + kind;
}

std::string rsmWindowPassName(uint32_t light) { return lightPassName(light, LightType::Directional) + ".rsm"; }

std::string cascadePassName(uint32_t light, uint32_t cascade) {
    return lightPassName(light, LightType::Directional) + ".cascade[" + std::to_string(cascade) + "]";
}

std::string windowPassName(uint32_t light, uint32_t window) {
    return lightPassName(light, LightType::Directional) + ".window[" + std::to_string(window) + "]";
}

namespace {

using rg::Access;

struct ShadowTables {
    std::vector<gpu::GpuShadowView> views;
    std::vector<gpu::GpuLightShadow> lights;
};

// vkCmdUpdateBuffer takes at most 64 KiB per call.
void updateBuffer(VkCommandBuffer cmd, VkBuffer buffer, const void* data, size_t bytes) {
    constexpr size_t kChunk = 65536;
    for (size_t offset = 0; offset < bytes; offset += kChunk)
        vkCmdUpdateBuffer(cmd, buffer, offset, std::min(kChunk, bytes - offset),
                          static_cast<const uint8_t*>(data) + offset);
}

struct AtlasHandles {
    rg::ImageHandle atlas, position, normal, flux;
};

struct SetupPass {
    ShadowTables tables;
    AtlasHandles h;
    rg::BufferHandle views, lightShadows;
    bool clear = false;
    bool rsm = false;
};

void recordSetup(const SetupPass& d, rg::PassContext& pc) {
    VkCommandBuffer cmd = pc.cmd();
    updateBuffer(cmd, pc.buffer(d.views).buffer, d.tables.views.data(),
                 d.tables.views.size() * sizeof(gpu::GpuShadowView));
    updateBuffer(cmd, pc.buffer(d.lightShadows).buffer, d.tables.lights.data(),
                 d.tables.lights.size() * sizeof(gpu::GpuLightShadow));
    if (!d.clear)
        return;
    VkImageSubresourceRange depthRange{VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, VK_REMAINING_ARRAY_LAYERS};
    VkClearDepthStencilValue one{1.0f, 0};
    vkCmdClearDepthStencilImage(cmd, pc.image(d.h.atlas).image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &one, 1,
                                &depthRange);
    if (!d.rsm)
        return;
    VkImageSubresourceRange colorRange{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, VK_REMAINING_ARRAY_LAYERS};
    VkClearColorValue zero{};
    for (rg::ImageHandle img : {d.h.position, d.h.normal, d.h.flux})
        vkCmdClearColorImage(cmd, pc.image(img).image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &colorRange);
}

// Writes the per-frame shadow tables; when no light has layers, also clears the atlas (and RSM)
// so the deferred pass and RSM consumers read defined contents.
void addSetupPass(rg::RenderGraph& graph, const ShadowLayout& layout, uint32_t lightCount, bool rsm,
                  AtlasHandles& h, rg::BufferHandle& views, rg::BufferHandle& lightShadows) {
    const SetupPass& pass = graph.addPass<SetupPass>(
        "gi.shadow.setup",
        [&](rg::PassBuilder& b, SetupPass& d) {
            d.tables.views = layout.views;
            if (d.tables.views.empty())
                d.tables.views.push_back(gpu::GpuShadowView{});
            for (const LightShadowPlan& plan : layout.lights)
                d.tables.lights.push_back(
                    {glm::uvec4(plan.firstLayer, plan.layerCount, plan.kind, 0u),
                     glm::uvec4(plan.cascadeFirst, plan.cascadeCount, plan.windowFirst, plan.windowCount)});
            d.tables.lights.resize(std::max<size_t>(lightCount, 1));
            d.clear = layout.views.empty();
            d.rsm = rsm;
            d.h = h;
            d.views = b.write(b.create("gi.shadow.views", BufferDesc{d.tables.views.size() * sizeof(gpu::GpuShadowView)}),
                              Access::TransferWrite);
            d.lightShadows = b.write(
                b.create("gi.shadow.lights", BufferDesc{d.tables.lights.size() * sizeof(gpu::GpuLightShadow)}),
                Access::TransferWrite);
            if (d.clear) {
                d.h.atlas = b.write(h.atlas, Access::TransferWrite);
                if (rsm) {
                    d.h.position = b.write(h.position, Access::TransferWrite);
                    d.h.normal = b.write(h.normal, Access::TransferWrite);
                    d.h.flux = b.write(h.flux, Access::TransferWrite);
                }
            }
        },
        recordSetup);
    h = pass.h;
    views = pass.views;
    lightShadows = pass.lightShadows;
}

struct LightPassInfo {
    const Pipeline* pipeline = nullptr;
    const GpuScene* scene = nullptr;
    VkSampler textureSampler = VK_NULL_HANDLE;
    SceneHandles sceneHandles;
    std::vector<gpu::RasterPush> faces; // one per layer, from firstLayer on
    AtlasHandles targets;               // rendered one layer at a time through PassContext::layerView
    rg::ImageHandle windowDepth;        // an RSM window's own depth target (its layer 0) instead of the atlas
    uint32_t firstLayer = 0;
    uint32_t faceMask = 0;
    uint32_t resolution = 0;
    bool rsm = false;
};

void recordLightPass(const LightPassInfo& info, rg::PassContext& pc) {
    VkCommandBuffer cmd = pc.cmd();
    VkExtent2D extent{info.resolution, info.resolution};
    for (size_t f = 0; f < info.faces.size(); ++f) {
        const uint32_t layer = info.firstLayer + uint32_t(f);
        const AtlasHandles& t = info.targets;
        std::vector<VkImageView> colors;
        if (info.rsm)
            colors = {pc.layerView(t.position, layer), pc.layerView(t.normal, layer), pc.layerView(t.flux, layer)};
        beginRendering(cmd, extent, colors,
                       info.windowDepth.valid() ? pc.layerView(info.windowDepth, 0) : pc.layerView(t.atlas, layer));
        if (info.faceMask & (1u << f)) { // faces that cannot see the cone are only cleared
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, info.pipeline->pipeline);
            const SceneHandles& s = info.sceneHandles;
            if (info.rsm) {
                DescriptorItem items[5] = {pc.buffer(DIRECT_RASTER_BINDING_VERTICES, s.vertices),
                                           pc.buffer(DIRECT_RASTER_BINDING_INSTANCES, s.instances),
                                           pc.buffer(DIRECT_RASTER_BINDING_MATERIALS, s.materials),
                                           pc.sampled(DIRECT_RASTER_BINDING_TEXTURES, s.textures, info.textureSampler),
                                           pc.buffer(DIRECT_RASTER_BINDING_LIGHTS, s.lights)};
                pushDescriptors(pc.context(), cmd, *info.pipeline, items);
            } else {
                DescriptorItem items[3] = {pc.buffer(DIRECT_RASTER_BINDING_VERTICES, s.vertices),
                                           pc.buffer(DIRECT_RASTER_BINDING_INSTANCES, s.instances),
                                           pc.buffer(DIRECT_RASTER_BINDING_MATERIALS, s.materials)};
                pushDescriptors(pc.context(), cmd, *info.pipeline, items);
            }
            drawScene(cmd, *info.pipeline, *info.scene, pc.buffer(s.indices).buffer, info.faces[f]);
        }
        vkCmdEndRendering(cmd);
    }
}

// What one light pass renders: the light's own layers (with the RSM when asked, unless the RSM
// is windowed), one cascade or shadow-window layer (depth only: the RSM is written for the
// light's own layers alone, so RSM consumers count each light's flux once), or a directional
// light's RSM window (the RSM layer from LightShadowPlan::rsmView, with a depth target of its own
// so that the atlas layer keeps the whole scene's depth for the shadow lookups). One pass per
// cascade and per shadow window: a camera move often changes the fine ones' matrices and not
// the coarse ones.
struct LightLayers {
    enum Kind { Own, Cascade, RsmWindow, ShadowWindow } kind = Own;
    uint32_t index = 0; // the cascade or shadow window
};

void addLightPass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame, const SceneHandles& scene,
                  const ShadowLayout& layout, const LightShadowPlan& plan, bool rsm, AtlasHandles& h,
                  LightLayers what = {}) {
    const bool cascade = what.kind == LightLayers::Cascade, window = what.kind == LightLayers::RsmWindow;
    const bool shadowWindow = what.kind == LightLayers::ShadowWindow;
    rsm = window || (rsm && what.kind == LightLayers::Own && !plan.rsmWindowed);
    const uint32_t first = cascade        ? plan.cascadeFirst + what.index
                           : shadowWindow ? plan.windowFirst + what.index
                                          : plan.firstLayer;
    const uint32_t count = what.kind == LightLayers::Own ? plan.layerCount : 1u;
    auto info = std::make_shared<LightPassInfo>();
    bool textured = !frame.scene->textures.empty();
    info->pipeline = !rsm ? &p.shadow : textured ? &p.rsm : &p.rsmUntextured;
    info->scene = frame.gpuScene;
    info->textureSampler = frame.gpuScene->textureSampler;
    info->sceneHandles = scene;
    info->faceMask = what.kind == LightLayers::Own ? plan.faceMask : 1u;
    info->resolution = layout.resolution;
    info->rsm = rsm;
    info->firstLayer = first;
    for (uint32_t f = 0; f < count; ++f) {
        uint32_t layer = first + f;
        const gpu::GpuShadowView& v = window ? plan.rsmView : layout.views[layer];
        info->faces.push_back({v.viewProj, v.eye, v.axisArea, glm::uvec4(0u, plan.light, layer, 0u)});
    }
    const Light& light = frame.scene->lights[plan.light];
    std::string name = cascade        ? cascadePassName(plan.light, what.index)
                       : shadowWindow ? windowPassName(plan.light, what.index)
                       : window       ? rsmWindowPassName(plan.light)
                                      : lightPassName(plan.light, light.type);
    graph.addPass(
        std::move(name),
        [&](rg::PassBuilder& b) {
            rg::SubresourceRange layers{0, 1, first, count};
            if (window) {
                ImageDesc desc;
                desc.format = kDepthFormat;
                desc.width = desc.height = layout.resolution;
                info->windowDepth = b.write(b.create("gi.rsm.window.depth", desc), Access::DepthAttachmentWrite);
            } else {
                h.atlas = b.write(h.atlas, Access::DepthAttachmentWrite, layers);
            }
            if (rsm) {
                h.position = b.write(h.position, Access::ColorAttachmentWrite, layers);
                h.normal = b.write(h.normal, Access::ColorAttachmentWrite, layers);
                h.flux = b.write(h.flux, Access::ColorAttachmentWrite, layers);
                b.read(scene.textures, Access::FragmentSampledRead);
                b.read(scene.lights, Access::VertexShaderStorageRead); // rsm.vert
            }
            b.read(scene.vertices, Access::VertexShaderStorageRead);
            b.read(scene.instances, Access::VertexShaderStorageRead);
            b.read(scene.materials, Access::VertexShaderStorageRead);
            b.read(scene.indices, Access::IndexBufferRead);
            info->targets = h;
        },
        [info](rg::PassContext& pc) { recordLightPass(*info, pc); });
}

} // namespace

void addLightPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard, const DirectPipelines& p,
                    const FrameData& frame, const SceneHandles& scene, const ShadowLayout& layout,
                    ShadowTargets& targets, bool rsm, const std::vector<bool>& keep,
                    const std::vector<uint32_t>& keepCascades, const std::vector<bool>& keepWindows,
                    const std::vector<uint32_t>& keepShadowWindows) {
    AtlasHandles h;
    h.atlas = graph.importImage("gi.shadow.atlas", targets.atlas);
    if (rsm) {
        h.position = graph.importImage("gi.rsm.position", targets.rsmPosition);
        h.normal = graph.importImage("gi.rsm.normal", targets.rsmNormal);
        h.flux = graph.importImage("gi.rsm.flux", targets.rsmFlux);
    }
    ShadowData shadow;
    addSetupPass(graph, layout, uint32_t(frame.scene->lights.size()), rsm, h, shadow.views, shadow.lightShadows);
    for (const LightShadowPlan& plan : layout.lights) {
        if (plan.kind != GI_SHADOW_NONE && !(plan.light < keep.size() && keep[plan.light]))
            addLightPass(graph, p, frame, scene, layout, plan, rsm, h);
        if (rsm && plan.rsmWindowed && !(plan.light < keepWindows.size() && keepWindows[plan.light]))
            addLightPass(graph, p, frame, scene, layout, plan, rsm, h, {LightLayers::RsmWindow});
    }
    for (const LightShadowPlan& plan : layout.lights)
        for (uint32_t k = 0; k < plan.cascadeCount; ++k)
            if (!(plan.light < keepCascades.size() && (keepCascades[plan.light] >> k) & 1u))
                addLightPass(graph, p, frame, scene, layout, plan, rsm, h, {LightLayers::Cascade, k});
    for (const LightShadowPlan& plan : layout.lights)
        for (uint32_t k = 0; k < plan.windowCount; ++k)
            if (!(plan.light < keepShadowWindows.size() && (keepShadowWindows[plan.light] >> k) & 1u))
                addLightPass(graph, p, frame, scene, layout, plan, rsm, h, {LightLayers::ShadowWindow, k});
    shadow.atlas = h.atlas;
    shadow.resolution = layout.resolution;
    shadow.layers = layout.layers;
    shadow.compareSampler = p.shadowSampler;
    shadow.pointSampler = p.pointSampler;
    blackboard.add(shadow);
    if (rsm) {
        std::vector<ShadowLayer> rsmLayers = layout.layers;
        for (const LightShadowPlan& plan : layout.lights)
            if (plan.rsmWindowed)
                rsmLayers[plan.firstLayer].viewProj = plan.rsmView.viewProj;
        blackboard.add(RsmData{h.position, h.normal, h.flux, layout.resolution, std::move(rsmLayers)});
    }
}

RsmImages addPointSourceRsmPass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                                const SceneHandles& scene, rg::BufferHandle lights,
                                const std::vector<gpu::GpuShadowView>& views, uint32_t resolution,
                                const std::string& name) {
    const uint32_t layers = uint32_t(views.size());
    const RsmImages images = createRsmImages(graph, name, resolution, layers);
    ImageDesc depthDesc;
    depthDesc.format = kDepthFormat;
    depthDesc.width = depthDesc.height = resolution;
    depthDesc.arrayLayers = std::max(layers, 2u);
    auto info = std::make_shared<LightPassInfo>();
    info->pipeline = frame.scene->textures.empty() ? &p.rsmUntextured : &p.rsm;
    info->scene = frame.gpuScene;
    info->textureSampler = frame.gpuScene->textureSampler;
    info->sceneHandles = scene;
    info->sceneHandles.lights = lights;
    info->faceMask = ~0u;
    info->resolution = resolution;
    info->rsm = true;
    for (uint32_t l = 0; l < layers; ++l)
        info->faces.push_back({views[l].viewProj, views[l].eye, views[l].axisArea, glm::uvec4(0u, l / 6u, l, 0u)});
    RsmImages out = images;
    graph.addPass(
        name,
        [&](rg::PassBuilder& b) {
            AtlasHandles& h = info->targets;
            h.atlas = b.write(b.create(name + ".depth", depthDesc), Access::DepthAttachmentWrite);
            h.position = out.position = b.write(images.position, Access::ColorAttachmentWrite);
            h.normal = out.normal = b.write(images.normal, Access::ColorAttachmentWrite);
            h.flux = out.flux = b.write(images.flux, Access::ColorAttachmentWrite);
            b.read(scene.textures, Access::FragmentSampledRead);
            b.read(lights, Access::VertexShaderStorageRead); // rsm.vert
            b.read(scene.vertices, Access::VertexShaderStorageRead);
            b.read(scene.instances, Access::VertexShaderStorageRead);
            b.read(scene.materials, Access::VertexShaderStorageRead);
            b.read(scene.indices, Access::IndexBufferRead);
        },
        [info](rg::PassContext& pc) { recordLightPass(*info, pc); });
    return out;
}

} // namespace vkgi::gi
