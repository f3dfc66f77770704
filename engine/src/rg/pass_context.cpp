// PassContext: physical resources and descriptor helpers for execute callbacks. Layouts come
// from the accesses the pass declared, so a descriptor can never disagree with the barriers.
#include <span>

#include "vkgi/context.hpp"
#include "vkgi/frame_constants.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::rg {

namespace {
bool covers(uint32_t base, uint32_t count, uint32_t index) {
    return index == kAll || (index >= base && (count == kAll || index < base + count));
}
} // namespace

// The pass's declared use of `resource` covering `mip` and `layer`; kAll accepts any mip or layer.
const detail::Use* PassContext::findUse(uint32_t resource, uint32_t mip, uint32_t layer) const {
    for (const detail::Use& u : m_graph.m_passes[m_pass].uses)
        if (u.resource == resource && covers(u.range.baseMip, u.range.mipCount, mip) &&
            covers(u.range.baseLayer, u.range.layerCount, layer))
            return &u;
    return nullptr;
}

const Image& PassContext::image(ImageHandle h) const {
    VKGI_ASSERT(findUse(h.index, kAll) != nullptr, "PassContext::image: the pass did not declare this image");
    VKGI_ASSERT(m_graph.m_physImages[h.index] != nullptr, "PassContext::image: image has no physical resource");
    return *m_graph.m_physImages[h.index];
}

const Buffer& PassContext::buffer(BufferHandle h) const {
    VKGI_ASSERT(findUse(h.index, kAll) != nullptr, "PassContext::buffer: the pass did not declare this buffer");
    VKGI_ASSERT(m_graph.m_physBuffers[h.index] != nullptr, "PassContext::buffer: buffer has no physical resource");
    return *m_graph.m_physBuffers[h.index];
}

VkImageView PassContext::mipView(ImageHandle h, uint32_t mip) const {
    const Image& img = image(h);
    VKGI_ASSERT(mip < img.mipViews.size(), "PassContext::mipView: mip level out of range");
    return img.mipViews[mip];
}

VkImageView PassContext::layerView(ImageHandle h, uint32_t layer) const {
    VKGI_ASSERT(findUse(h.index, 0, layer) != nullptr, "PassContext::layerView: the pass did not declare this layer");
    const Image& img = image(h);
    VKGI_ASSERT(layer < img.layerViews.size(), "PassContext::layerView: layer out of range (or not a 2D image)");
    return img.layerViews[layer];
}

VkImageLayout PassContext::layout(ImageHandle h, uint32_t mip) const {
    const detail::Use* use = findUse(h.index, mip);
    VKGI_ASSERT(use != nullptr, "PassContext::layout: the pass did not declare this mip of the image");
    return accessInfo(use->access).layout;
}

DescriptorItem PassContext::storage(uint32_t binding, ImageHandle h, uint32_t mip) const {
    DescriptorItem item;
    item.binding = binding;
    item.image = {VK_NULL_HANDLE, mip == kAll ? view(h) : mipView(h, mip), layout(h, mip)};
    return item;
}

DescriptorItem PassContext::sampled(uint32_t binding, ImageHandle h, VkSampler sampler, uint32_t mip) const {
    DescriptorItem item;
    item.binding = binding;
    item.image = {sampler, mip == kAll ? view(h) : mipView(h, mip), layout(h, mip)};
    return item;
}

DescriptorItem PassContext::buffer(uint32_t binding, BufferHandle h) const {
    DescriptorItem item;
    item.binding = binding;
    item.buffer = {buffer(h).buffer, 0, VK_WHOLE_SIZE};
    return item;
}

void PassContext::bindForDispatch(const Pipeline& pipeline, const void* push, uint32_t pushSize,
                                  std::span<const DescriptorItem> items) const {
    vkCmdBindPipeline(m_cmd, pipeline.bindPoint, pipeline.pipeline);
    if (pipeline.findBinding(GI_FRAME_SET, GI_FRAME_BINDING))
        bindFrameSet(pipeline);
    if (!items.empty())
        pushDescriptors(m_ctx, m_cmd, pipeline, items);
    if (pushSize > 0 || pipeline.pushConstantSize > 0)
        pushConstants(m_cmd, pipeline, push, pushSize);
}

void PassContext::dispatchRaw(const Pipeline& pipeline, glm::uvec3 groups, const void* push, uint32_t pushSize,
                              std::initializer_list<DescriptorItem> items) const {
    dispatch(pipeline, groups, push, pushSize, std::span<const DescriptorItem>(items.begin(), items.size()));
}

void PassContext::dispatch(const Pipeline& pipeline, glm::uvec3 groups, const void* push, uint32_t pushSize,
                           std::span<const DescriptorItem> items) const {
    bindForDispatch(pipeline, push, pushSize, items);
    vkCmdDispatch(m_cmd, groups.x, groups.y, groups.z);
}

void PassContext::dispatchIndirect(const Pipeline& pipeline, BufferHandle args, VkDeviceSize offset, const void* push,
                                   uint32_t pushSize, std::span<const DescriptorItem> items) const {
    bool declared = false;
    for (const detail::Use& u : m_graph.m_passes[m_pass].uses)
        declared = declared || (u.resource == args.index && u.access == Access::IndirectRead);
    VKGI_ASSERT(declared, "PassContext::dispatchIndirect: the pass did not declare IndirectRead of its arguments");
    bindForDispatch(pipeline, push, pushSize, items);
    vkCmdDispatchIndirect(m_cmd, buffer(args).buffer, offset);
}

void PassContext::bindFrameSet(const Pipeline& pipeline) const {
    VKGI_ASSERT(m_graph.frameSet() != VK_NULL_HANDLE,
              "a pass uses FrameConstants but RenderGraph::setFrameSet was not called");
    vkgi::bindFrameSet(m_cmd, pipeline, m_graph.frameSet());
}

glm::uvec3 PassContext::groupsFor(const Pipeline& pipeline, glm::uvec3 threads) {
    return {groupCount(threads.x, pipeline.localSize[0]), groupCount(threads.y, pipeline.localSize[1]),
            groupCount(threads.z, pipeline.localSize[2])};
}

} // namespace vkgi::rg
