// The persistent shadow atlas and RSM arrays. They are owned here rather than by the graph's
// transient pool because rendering one light needs 2D views of single layers, and the pool's
// images may be replaced between frames; the graph still derives all their barriers (imports).
#include "direct/direct_passes.hpp"

#include "engine/context.hpp"
#include "engine/vk_check.hpp"

namespace vkgi::gi {

namespace {

VkImageView makeView(Context& ctx, const Image& img, VkImageViewType type, uint32_t layer, uint32_t count) {
    VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    info.image = img.image;
    info.viewType = type;
    info.format = img.desc.format;
    info.subresourceRange = {aspectOf(img.desc.format), 0, 1, layer, count};
    VkImageView view;
    VK_CHECK(vkCreateImageView(ctx.device(), &info, nullptr, &view));
    return view;
}

// A layered image whose default view is always a 2D array (createImage gives a plain 2D view
// for one layer, which sampler2DArray bindings reject), plus one 2D view per layer.
rg::PersistentImage createLayered(Context& ctx, const char* name, VkFormat format, VkImageUsageFlags usage,
                                  uint32_t layers, uint32_t size, std::vector<VkImageView>& layerViews) {
    ImageDesc d;
    d.format = format;
    d.width = d.height = size;
    d.arrayLayers = layers;
    d.usage = usage | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    rg::PersistentImage p;
    p.image = createImage(ctx, d, name);
    if (layers == 1) {
        vkDestroyImageView(ctx.device(), p.image.view, nullptr);
        p.image.view = makeView(ctx, p.image, VK_IMAGE_VIEW_TYPE_2D_ARRAY, 0, 1);
    }
    for (uint32_t l = 0; l < layers; ++l)
        layerViews.push_back(makeView(ctx, p.image, VK_IMAGE_VIEW_TYPE_2D, l, 1));
    return p;
}

void destroyLayered(Context& ctx, rg::PersistentImage& p, std::vector<VkImageView>& layerViews) {
    for (VkImageView v : layerViews)
        vkDestroyImageView(ctx.device(), v, nullptr);
    layerViews.clear();
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

void ensureShadowTargets(Context& ctx, ShadowTargets& t, uint32_t layers, uint32_t resolution, bool rsm) {
    layers = std::max(layers, 1u); // the deferred pass always binds an atlas
    if (t.layers == layers && t.resolution == resolution && t.rsm == rsm && t.atlas.image)
        return;
    VK_CHECK(vkDeviceWaitIdle(ctx.device())); // the old targets may still be read by a frame
    destroyShadowTargets(ctx, t);
    t.atlas = createLayered(ctx, "gi.shadow.atlas", kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, layers,
                            resolution, t.atlasLayers);
    if (rsm) {
        const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
        t.rsmPosition = createLayered(ctx, "gi.rsm.position", kPositionFormat, usage, layers, resolution, t.rsmLayers[0]);
        t.rsmNormal = createLayered(ctx, "gi.rsm.normal", kNormalFormat, usage, layers, resolution, t.rsmLayers[1]);
        t.rsmFlux = createLayered(ctx, "gi.rsm.flux", kRsmFluxFormat, usage, layers, resolution, t.rsmLayers[2]);
    }
    t.layers = layers;
    t.resolution = resolution;
    t.rsm = rsm;
}

void destroyShadowTargets(Context& ctx, ShadowTargets& t) {
    destroyLayered(ctx, t.atlas, t.atlasLayers);
    destroyLayered(ctx, t.rsmPosition, t.rsmLayers[0]);
    destroyLayered(ctx, t.rsmNormal, t.rsmLayers[1]);
    destroyLayered(ctx, t.rsmFlux, t.rsmLayers[2]);
    t = ShadowTargets{};
}

} // namespace vkgi::gi
