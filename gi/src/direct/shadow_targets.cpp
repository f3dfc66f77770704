// The persistent shadow atlas and RSM arrays. They are owned here rather than by the graph's
// transient pool because a light's layers that did not change keep last frame's content, and the
// pool's images may be replaced between frames; the graph still derives all their barriers
// (imports), and the light passes render into single layers through PassContext::layerView.
#include <algorithm>

#include "direct/direct_passes.hpp"

#include "vkgi/context.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

// A layered image whose default view is always a 2D array (sampler2DArray bindings), also with
// one layer; createImage gives it one 2D view per layer for rendering.
rg::PersistentImage createLayered(Context& ctx, const char* name, VkFormat format, VkImageUsageFlags usage,
                                  uint32_t layers, uint32_t size) {
    ImageDesc d;
    d.format = format;
    d.width = d.height = size;
    d.arrayLayers = layers;
    d.arrayView = true;
    d.usage = usage | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    rg::PersistentImage p;
    p.image = createImage(ctx, d, name);
    return p;
}

void destroyLayered(Context& ctx, rg::PersistentImage& p) {
    if (p.image)
        destroyImage(ctx, p.image);
    p = rg::PersistentImage{};
}

} // namespace

VkDeviceSize ShadowTargets::bytes() const {
    VkDeviceSize n = 0;
    for (const rg::PersistentImage* p : {&atlas, &rsmPosition, &rsmNormal, &rsmFlux})
        n += p->image ? imageBytes(p->image.desc) : 0;
    return n;
}

void ensureShadowTargets(Context& ctx, ShadowTargets& t, uint32_t layers, uint32_t rsmLayers, uint32_t resolution,
                         bool rsm) {
    layers = std::max(layers, 1u); // the deferred pass always binds an atlas
    rsmLayers = std::max(std::min(rsmLayers, layers), 1u);
    if (t.layers == layers && t.rsmLayers == rsmLayers && t.resolution == resolution && t.rsm == rsm && t.atlas.image)
        return;
    VKGI_CHECK(vkDeviceWaitIdle(ctx.device())); // the old targets may still be read by a frame
    destroyShadowTargets(ctx, t);
    t.atlas = createLayered(ctx, "gi.shadow.atlas", kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, layers,
                            resolution);
    if (rsm) {
        const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
        t.rsmPosition = createLayered(ctx, "gi.rsm.position", kPositionFormat, usage, rsmLayers, resolution);
        t.rsmNormal = createLayered(ctx, "gi.rsm.normal", kNormalFormat, usage, rsmLayers, resolution);
        t.rsmFlux = createLayered(ctx, "gi.rsm.flux", kRsmFluxFormat, usage, rsmLayers, resolution);
    }
    t.layers = layers;
    t.rsmLayers = rsmLayers;
    t.resolution = resolution;
    t.rsm = rsm;
}

void destroyShadowTargets(Context& ctx, ShadowTargets& t) {
    for (rg::PersistentImage* p : {&t.atlas, &t.rsmPosition, &t.rsmNormal, &t.rsmFlux})
        destroyLayered(ctx, *p);
    t = ShadowTargets{};
}

RsmImages createRsmImages(rg::RenderGraph& graph, const std::string& prefix, uint32_t resolution, uint32_t layers) {
    ImageDesc desc;
    desc.width = desc.height = resolution;
    desc.arrayLayers = std::max(layers, 2u);
    desc.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    RsmImages out;
    desc.format = kPositionFormat;
    out.position = graph.createImage(prefix + ".position", desc);
    desc.format = kNormalFormat;
    out.normal = graph.createImage(prefix + ".normal", desc);
    desc.format = kRsmFluxFormat;
    out.flux = graph.createImage(prefix + ".flux", desc);
    return out;
}

} // namespace vkgi::gi
