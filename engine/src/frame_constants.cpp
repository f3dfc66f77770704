#include "vkgi/frame_constants.hpp"

#include <cstring>

#include "vkgi/context.hpp"
#include "vkgi/pipeline.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi {

FrameConstantsRing::FrameConstantsRing(Context& ctx, uint32_t frames) : m_ctx(ctx) {
    VKGI_ASSERT(frames > 0, "FrameConstantsRing needs at least one frame");
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frames};
    VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool.maxSets = frames;
    pool.poolSizeCount = 1;
    pool.pPoolSizes = &size;
    VKGI_CHECK(vkCreateDescriptorPool(ctx.device(), &pool, nullptr, &m_pool));
    std::vector<VkDescriptorSetLayout> layouts(frames, ctx.frameSetLayout());
    m_sets.resize(frames);
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = m_pool;
    alloc.descriptorSetCount = frames;
    alloc.pSetLayouts = layouts.data();
    VKGI_CHECK(vkAllocateDescriptorSets(ctx.device(), &alloc, m_sets.data()));
    for (uint32_t i = 0; i < frames; ++i) {
        m_buffers.push_back(createBuffer(
            ctx, {sizeof(gpu::FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemoryUsage::CpuToGpu},
            "vkgi.frame_constants"));
        VkDescriptorBufferInfo info{m_buffers[i].buffer, 0, sizeof(gpu::FrameConstants)};
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = m_sets[i];
        w.dstBinding = GI_FRAME_BINDING;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        w.pBufferInfo = &info;
        vkUpdateDescriptorSets(ctx.device(), 1, &w, 0, nullptr);
    }
    m_index = frames - 1;
}

FrameConstantsRing::~FrameConstantsRing() {
    for (Buffer& b : m_buffers)
        destroyBuffer(m_ctx, b);
    vkDestroyDescriptorPool(m_ctx.device(), m_pool, nullptr);
}

VkDescriptorSet FrameConstantsRing::next(const gpu::FrameConstants& constants) {
    m_index = (m_index + 1) % uint32_t(m_sets.size());
    std::memcpy(m_buffers[m_index].mapped(), &constants, sizeof(constants));
    return m_sets[m_index];
}

void bindFrameSet(VkCommandBuffer cmd, const Pipeline& pipeline, VkDescriptorSet set) {
    vkCmdBindDescriptorSets(cmd, pipeline.bindPoint, pipeline.layout, GI_FRAME_SET, 1, &set, 0, nullptr);
}

} // namespace vkgi
