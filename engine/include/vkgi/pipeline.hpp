#pragma once
// Compute and graphics pipelines from SPIR-V embedded at build time. Descriptor layouts are reflected
// from the SPIR-V itself, so a binding is declared once (in GLSL): set 0 holds per-frame
// globals, set 1 per-dispatch resources written with push descriptors. A failed Vulkan call
// throws std::runtime_error naming the call and the VkResult (missing SPIR-V is a Result error).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "vkgi/result.hpp"

namespace vkgi {

class Context;

// SPIR-V compiled into the program at build time (cmake/CompileShaders.cmake vkgi_embed_spirv):
// each library or program that uses shaders carries its own, so a host reads no file at run time.
struct EmbeddedSpirv {
    const char* name; // path under shaders/, e.g. "gi/lpv/inject.comp"
    const uint32_t* code;
    size_t words;
};
// A table of embedded shaders, registered for lookup by name while it lives. The generated code
// defines one static table per library or program; later tables are searched first.
class SpirvTable {
public:
    explicit SpirvTable(std::span<const EmbeddedSpirv> shaders);
    ~SpirvTable();
    SpirvTable(const SpirvTable&) = delete;
    SpirvTable& operator=(const SpirvTable&) = delete;

private:
    friend Result<std::vector<uint32_t>> loadSpirv(const std::string& name);
    std::span<const EmbeddedSpirv> m_shaders;
    SpirvTable* m_next = nullptr;
};

// The embedded SPIR-V named `name`, e.g. "engine/test/fill.comp"; checks the magic and size.
// A name no linked table holds is an error naming it.
Result<std::vector<uint32_t>> loadSpirv(const std::string& name);

struct ReflectedBinding {
    uint32_t set = 0;
    uint32_t binding = 0;
    VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
    uint32_t count = 1;
    std::string name;
    // What the shader may do with it: GLSL readonly clears `writable`, writeonly clears
    // `readable`; sampled images, samplers and uniform buffers are readable only. Render-graph
    // compute passes derive each binding's rg::Access from these (vkgi/rg/compute_pass.hpp).
    bool readable = true;
    bool writable = true;
};

struct ShaderReflection {
    VkShaderStageFlagBits stage = VK_SHADER_STAGE_ALL;
    std::vector<ReflectedBinding> bindings;
    uint32_t pushConstantSize = 0;
    uint32_t localSize[3] = {1, 1, 1};
};
Result<ShaderReflection> reflectSpirv(std::span<const uint32_t> code);

struct SpecConstant {
    uint32_t id = 0;
    uint32_t value = 0; // raw 32-bit value (use std::bit_cast for floats)
};

struct Pipeline {
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayouts[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE}; // [0] is Context::frameSetLayout()
    VkPipelineBindPoint bindPoint = VK_PIPELINE_BIND_POINT_COMPUTE;
    VkShaderStageFlags stages = 0;
    uint32_t pushConstantSize = 0;
    std::vector<ReflectedBinding> bindings; // union over stages, set 0 and set 1
    uint32_t localSize[3] = {1, 1, 1};
    std::string name;
    const ReflectedBinding* findBinding(uint32_t set, uint32_t binding) const;
};

struct ComputePipelineDesc {
    std::string shader; // SPIR-V name, e.g. "gi/lpv_propagate.comp"
    std::vector<SpecConstant> specialization;
};
Result<Pipeline> createComputePipeline(Context& ctx, const ComputePipelineDesc& desc);

struct GraphicsPipelineDesc {
    std::string vertexShader;
    std::string fragmentShader; // may be empty (depth-only)
    std::vector<SpecConstant> specialization;
    std::vector<VkVertexInputBindingDescription> vertexBindings;
    std::vector<VkVertexInputAttributeDescription> vertexAttributes;
    std::vector<VkFormat> colorFormats;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
    VkCullModeFlags cullMode = VK_CULL_MODE_NONE;
    bool depthTest = true;
    bool depthWrite = true;
    VkCompareOp depthCompare = VK_COMPARE_OP_LESS;
    float depthBiasConstant = 0.0f; // shadow maps
    float depthBiasSlope = 0.0f;
    uint32_t viewMask = 0;          // multiview (cube shadow maps); 0 = off
};
Result<Pipeline> createGraphicsPipeline(Context& ctx, const GraphicsPipelineDesc& desc);
void destroyPipeline(Context& ctx, Pipeline& pipeline);

// One resource bound to set 1 by push descriptor. Fill exactly one of image/buffer.
struct DescriptorItem {
    uint32_t binding = 0;
    VkDescriptorImageInfo image{};
    VkDescriptorBufferInfo buffer{};
    VkBufferView texelBuffer = VK_NULL_HANDLE; // uniform or storage texel buffer bindings
};
// Pushes set 1 for the bound pipeline; every binding the shaders declare in set 1 must be
// given exactly once (checked: a missing or unknown binding is a fatal programming error).
void pushDescriptors(const Context& ctx, VkCommandBuffer cmd, const Pipeline& pipeline,
                     std::span<const DescriptorItem> items);
// Push constants; `size` must equal the shader's push-constant block size (checked).
void pushConstants(VkCommandBuffer cmd, const Pipeline& pipeline, const void* data, uint32_t size);

inline uint32_t groupCount(uint32_t threads, uint32_t localSize) { return (threads + localSize - 1) / localSize; }

} // namespace vkgi
