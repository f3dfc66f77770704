#pragma once
// Set 0 of every pipeline: the per-frame constants uniform buffer. A small ring of buffers
// and descriptor sets lets the CPU fill frame N+1 while frame N may still be in flight.
// Creation throws std::runtime_error when a Vulkan call fails.
#include <vector>

#include <vulkan/vulkan.h>

#include "engine/frame_constants.h"
#include "vkgi/resources.hpp"

namespace vkgi {

struct Pipeline;

class FrameConstantsRing {
public:
    // `frames` = how many frames may be in flight at once.
    FrameConstantsRing(Context& ctx, uint32_t frames = 2);
    ~FrameConstantsRing();
    FrameConstantsRing(const FrameConstantsRing&) = delete;
    FrameConstantsRing& operator=(const FrameConstantsRing&) = delete;

    // Writes the constants of the next frame and returns its descriptor set.
    VkDescriptorSet next(const gpu::FrameConstants& constants);
    VkDescriptorSet current() const { return m_sets[m_index]; }

private:
    Context& m_ctx;
    VkDescriptorPool m_pool = VK_NULL_HANDLE;
    std::vector<Buffer> m_buffers;
    std::vector<VkDescriptorSet> m_sets;
    uint32_t m_index = 0;
};

// Binds `set` as set 0 of `pipeline` (every vkgi pipeline layout shares that set layout).
void bindFrameSet(VkCommandBuffer cmd, const Pipeline& pipeline, VkDescriptorSet set);

} // namespace vkgi
