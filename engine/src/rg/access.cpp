#include "vkgi/rg/access.hpp"

#include <array>
#include <string_view>

namespace vkgi::rg {
namespace {

constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 kFragment = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkPipelineStageFlags2 kVertex = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT;
constexpr VkPipelineStageFlags2 kDepthTests =
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
constexpr VkAccessFlags2 kStorageRead = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr VkAccessFlags2 kStorageWrite = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
constexpr VkImageUsageFlags kStorageImage = VK_IMAGE_USAGE_STORAGE_BIT;
constexpr VkBufferUsageFlags kStorageBuffer = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
// Combined depth/stencil layouts work for every depth format without separate-layout rules.
constexpr VkImageLayout kDepthWriteLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
constexpr VkImageLayout kDepthReadLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL;

// Columns: name, stages, access, layout, image usage, buffer usage, write, discard, image, buffer.
constexpr std::array<AccessInfo, size_t(Access::Count)> kTable{{
    {"None", VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_IMAGE_LAYOUT_UNDEFINED, 0, 0, false, false, true, true},
    {"ComputeSampledRead", kCompute, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
     VK_IMAGE_USAGE_SAMPLED_BIT, 0, false, false, true, false},
    {"ComputeStorageRead", kCompute, kStorageRead, VK_IMAGE_LAYOUT_GENERAL, kStorageImage, kStorageBuffer, false, false,
     true, true},
    {"ComputeStorageWrite", kCompute, kStorageWrite, VK_IMAGE_LAYOUT_GENERAL, kStorageImage, kStorageBuffer, true,
     false, true, true},
    {"ComputeStorageReadWrite", kCompute, kStorageRead | kStorageWrite, VK_IMAGE_LAYOUT_GENERAL, kStorageImage,
     kStorageBuffer, true, false, true, true},
    {"ComputeStorageWriteDiscard", kCompute, kStorageWrite, VK_IMAGE_LAYOUT_GENERAL, kStorageImage, kStorageBuffer,
     true, true, true, true},
    {"ComputeUniformRead", kCompute, VK_ACCESS_2_UNIFORM_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED, 0,
     VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, false, false, false, true},
    {"VertexShaderStorageRead", kVertex, kStorageRead, VK_IMAGE_LAYOUT_GENERAL, kStorageImage, kStorageBuffer, false,
     false, true, true},
    {"FragmentSampledRead", kFragment, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
     VK_IMAGE_USAGE_SAMPLED_BIT, 0, false, false, true, false},
    {"FragmentStorageRead", kFragment, kStorageRead, VK_IMAGE_LAYOUT_GENERAL, kStorageImage, kStorageBuffer, false,
     false, true, true},
    {"GraphicsUniformRead", kVertex | kFragment, VK_ACCESS_2_UNIFORM_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED, 0,
     VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, false, false, false, true},
    {"ColorAttachmentWrite", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, 0, true, false, true, false},
    {"ColorAttachmentReadWrite", VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
     VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, 0, true, false, true, false},
    {"DepthAttachmentWrite", kDepthTests,
     VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, kDepthWriteLayout,
     VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, 0, true, false, true, false},
    {"DepthAttachmentRead", kDepthTests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, kDepthReadLayout,
     VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, 0, false, false, true, false},
    {"VertexBufferRead", VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT,
     VK_IMAGE_LAYOUT_UNDEFINED, 0, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, false, false, false, true},
    {"IndexBufferRead", VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED, 0,
     VK_BUFFER_USAGE_INDEX_BUFFER_BIT, false, false, false, true},
    {"IndirectRead", VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT,
     VK_IMAGE_LAYOUT_UNDEFINED, 0, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT, false, false, false, true},
    {"TransferRead", VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
     VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false,
     false, true, true},
    {"TransferWrite", VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true,
     false, true, true},
    // Host reads of images need linear tiling, which vkgi never creates: buffers only.
    {"HostRead", VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT, VK_IMAGE_LAYOUT_UNDEFINED, 0, 0, false, false,
     false, true},
    // Presentation is synchronised by the semaphore; the barrier only needs the layout.
    {"Present", VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, 0, 0, false, false, true,
     false},
}};

// The table is indexed by the enum: catch a row added or moved out of order at compile time.
constexpr bool rowIs(Access a, std::string_view name) {
    return kTable[size_t(a)].name == name;
}
static_assert(rowIs(Access::ComputeStorageWriteDiscard, "ComputeStorageWriteDiscard"));
static_assert(rowIs(Access::GraphicsUniformRead, "GraphicsUniformRead"));
static_assert(rowIs(Access::DepthAttachmentRead, "DepthAttachmentRead"));
static_assert(rowIs(Access::HostRead, "HostRead") && rowIs(Access::Present, "Present"));

} // namespace

const AccessInfo& accessInfo(Access access) {
    return kTable[size_t(access) < kTable.size() ? size_t(access) : 0];
}

const char* toString(Access access) {
    return accessInfo(access).name;
}

} // namespace vkgi::rg
