#include "vkgi/pipeline.hpp"

#include <algorithm>

#include "vkgi/context.hpp"
#include "engine/frame_constants.h"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi {

namespace {
// Head of the registered tables. Constant-initialised, so tables registering from other
// translation units' static initialisers never see it unset, whatever the order.
constinit SpirvTable* g_spirvTables = nullptr;
} // namespace

SpirvTable::SpirvTable(std::span<const EmbeddedSpirv> shaders) : m_shaders(shaders), m_next(g_spirvTables) {
    g_spirvTables = this;
}

SpirvTable::~SpirvTable() {
    for (SpirvTable** link = &g_spirvTables; *link; link = &(*link)->m_next)
        if (*link == this) {
            *link = m_next;
            break;
        }
}

Result<std::vector<uint32_t>> loadSpirv(const std::string& name) {
    for (const SpirvTable* table = g_spirvTables; table; table = table->m_next)
        for (const EmbeddedSpirv& shader : table->m_shaders) {
            if (name != shader.name)
                continue;
            if (shader.words <= 5 || shader.code[0] != 0x07230203u)
                return makeError(name + ": embedded SPIR-V is corrupt (" + std::to_string(shader.words) + " words)");
            return std::vector<uint32_t>(shader.code, shader.code + shader.words);
        }
    return makeError(name + ": no such shader embedded in this program (shaders are compiled into the library or "
                            "program that uses them: vkgi_embed_spirv in cmake/CompileShaders.cmake)");
}

const ReflectedBinding* Pipeline::findBinding(uint32_t set, uint32_t binding) const {
    for (const auto& b : bindings)
        if (b.set == set && b.binding == binding)
            return &b;
    return nullptr;
}

namespace {

struct Stage {
    std::vector<uint32_t> code;
    ShaderReflection refl;
    VkShaderModule module = VK_NULL_HANDLE;
};

Result<Stage> loadStage(Context& ctx, const std::string& name) {
    auto code = loadSpirv(name);
    if (!code)
        return code.error();
    auto refl = reflectSpirv(*code);
    if (!refl)
        return makeError(name + ": " + refl.error().message);
    Stage s{std::move(*code), std::move(*refl), VK_NULL_HANDLE};
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = s.code.size() * 4;
    info.pCode = s.code.data();
    VKGI_CHECK(vkCreateShaderModule(ctx.device(), &info, nullptr, &s.module));
    return s;
}

// Builds the two set layouts and the pipeline layout from the union of the stages' bindings.
Result<void> buildLayout(Context& ctx, Pipeline& p, std::vector<Stage>& stages) {
    for (const Stage& s : stages) {
        p.stages |= s.refl.stage;
        p.pushConstantSize = std::max(p.pushConstantSize, s.refl.pushConstantSize);
        for (const ReflectedBinding& b : s.refl.bindings) {
            if (b.set > 1)
                return makeError(p.name + ": binding " + b.name + " uses set " + std::to_string(b.set) +
                                 " (vkgi uses set 0 = frame globals, set 1 = push descriptors)");
            if (const ReflectedBinding* prev = p.findBinding(b.set, b.binding)) {
                if (prev->type != b.type)
                    return makeError(p.name + ": set " + std::to_string(b.set) + " binding " +
                                     std::to_string(b.binding) + " has different types in two stages");
                for (ReflectedBinding& merged : p.bindings)
                    if (merged.set == b.set && merged.binding == b.binding) {
                        merged.readable = merged.readable || b.readable;
                        merged.writable = merged.writable || b.writable;
                    }
                continue;
            }
            p.bindings.push_back(b);
        }
    }
    if (p.pushConstantSize > ctx.properties().limits.maxPushConstantsSize)
        return makeError(p.name + ": push constants of " + std::to_string(p.pushConstantSize) +
                         " bytes exceed the device limit");
    // Set 0 is the engine's one frame-constants layout (so one descriptor set serves every
    // pipeline); a shader that declares set 0 must declare exactly that block.
    for (const auto& b : p.bindings)
        if (b.set == GI_FRAME_SET && (b.binding != GI_FRAME_BINDING || b.type != VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER))
            return makeError(p.name + ": set 0 is reserved for FrameConstants (engine/frame_constants.h); binding " +
                             std::to_string(b.binding) + " does not match it");
    p.setLayouts[0] = ctx.frameSetLayout();
    std::vector<VkDescriptorSetLayoutBinding> lb;
    for (const auto& b : p.bindings)
        if (b.set == 1)
            lb.push_back({b.binding, b.type, b.count, p.stages, nullptr});
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    setInfo.bindingCount = uint32_t(lb.size());
    setInfo.pBindings = lb.data();
    VKGI_CHECK(vkCreateDescriptorSetLayout(ctx.device(), &setInfo, nullptr, &p.setLayouts[1]));
    VkPushConstantRange range{p.stages, 0, p.pushConstantSize};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = 2;
    info.pSetLayouts = p.setLayouts;
    info.pushConstantRangeCount = p.pushConstantSize ? 1 : 0;
    info.pPushConstantRanges = &range;
    VKGI_CHECK(vkCreatePipelineLayout(ctx.device(), &info, nullptr, &p.layout));
    return {};
}

struct SpecData {
    std::vector<VkSpecializationMapEntry> entries;
    std::vector<uint32_t> values;
    VkSpecializationInfo info{};
    explicit SpecData(const std::vector<SpecConstant>& spec) {
        for (const auto& s : spec) {
            entries.push_back({s.id, uint32_t(values.size() * 4), 4});
            values.push_back(s.value);
        }
        info.mapEntryCount = uint32_t(entries.size());
        info.pMapEntries = entries.data();
        info.dataSize = values.size() * 4;
        info.pData = values.data();
    }
};

void destroyModules(Context& ctx, std::vector<Stage>& stages) {
    for (auto& s : stages)
        vkDestroyShaderModule(ctx.device(), s.module, nullptr);
}

} // namespace

Result<Pipeline> createComputePipeline(Context& ctx, const ComputePipelineDesc& desc) {
    Pipeline p;
    p.name = desc.shader;
    p.bindPoint = VK_PIPELINE_BIND_POINT_COMPUTE;
    std::vector<Stage> stages;
    auto s = loadStage(ctx, desc.shader);
    if (!s)
        return s.error();
    stages.push_back(std::move(*s));
    if (stages[0].refl.stage != VK_SHADER_STAGE_COMPUTE_BIT) {
        destroyModules(ctx, stages);
        return makeError(desc.shader + ": not a compute shader");
    }
    if (auto ok = buildLayout(ctx, p, stages); !ok) {
        destroyModules(ctx, stages);
        destroyPipeline(ctx, p);
        return ok.error();
    }
    std::copy(std::begin(stages[0].refl.localSize), std::end(stages[0].refl.localSize), p.localSize);
    SpecData spec(desc.specialization);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = stages[0].module;
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = spec.entries.empty() ? nullptr : &spec.info;
    info.layout = p.layout;
    VKGI_CHECK(vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &info, nullptr, &p.pipeline));
    destroyModules(ctx, stages);
    ctx.setName(VK_OBJECT_TYPE_PIPELINE, uint64_t(p.pipeline), p.name.c_str());
    return p;
}

Result<Pipeline> createGraphicsPipeline(Context& ctx, const GraphicsPipelineDesc& desc) {
    Pipeline p;
    p.name = desc.vertexShader + (desc.fragmentShader.empty() ? "" : "+" + desc.fragmentShader);
    p.bindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    std::vector<Stage> stages;
    for (const std::string& name : {desc.vertexShader, desc.fragmentShader}) {
        if (name.empty())
            continue;
        auto s = loadStage(ctx, name);
        if (!s) {
            destroyModules(ctx, stages);
            return s.error();
        }
        stages.push_back(std::move(*s));
    }
    if (auto ok = buildLayout(ctx, p, stages); !ok) {
        destroyModules(ctx, stages);
        destroyPipeline(ctx, p);
        return ok.error();
    }
    SpecData spec(desc.specialization);
    std::vector<VkPipelineShaderStageCreateInfo> ssci;
    for (const Stage& s : stages) {
        VkPipelineShaderStageCreateInfo si{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        si.stage = s.refl.stage;
        si.module = s.module;
        si.pName = "main";
        si.pSpecializationInfo = spec.entries.empty() ? nullptr : &spec.info;
        ssci.push_back(si);
    }
    VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vi.vertexBindingDescriptionCount = uint32_t(desc.vertexBindings.size());
    vi.pVertexBindingDescriptions = desc.vertexBindings.data();
    vi.vertexAttributeDescriptionCount = uint32_t(desc.vertexAttributes.size());
    vi.pVertexAttributeDescriptions = desc.vertexAttributes.data();
    VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = desc.cullMode;
    rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    rs.lineWidth = 1.0f;
    rs.depthBiasEnable = (desc.depthBiasConstant != 0.0f || desc.depthBiasSlope != 0.0f) ? VK_TRUE : VK_FALSE;
    rs.depthBiasConstantFactor = desc.depthBiasConstant;
    rs.depthBiasSlopeFactor = desc.depthBiasSlope;
    VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = desc.depthTest;
    ds.depthWriteEnable = desc.depthWrite;
    ds.depthCompareOp = desc.depthCompare;
    std::vector<VkPipelineColorBlendAttachmentState> blend(desc.colorFormats.size());
    for (auto& b : blend)
        b.colorWriteMask = 0xf;
    VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cb.attachmentCount = uint32_t(blend.size());
    cb.pAttachments = blend.data();
    VkDynamicState dyn[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dy.dynamicStateCount = 2;
    dy.pDynamicStates = dyn;
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.viewMask = desc.viewMask;
    rendering.colorAttachmentCount = uint32_t(desc.colorFormats.size());
    rendering.pColorAttachmentFormats = desc.colorFormats.data();
    rendering.depthAttachmentFormat = desc.depthFormat;
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &rendering;
    info.stageCount = uint32_t(ssci.size());
    info.pStages = ssci.data();
    info.pVertexInputState = &vi;
    info.pInputAssemblyState = &ia;
    info.pViewportState = &vp;
    info.pRasterizationState = &rs;
    info.pMultisampleState = &ms;
    info.pDepthStencilState = &ds;
    info.pColorBlendState = &cb;
    info.pDynamicState = &dy;
    info.layout = p.layout;
    VKGI_CHECK(vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &info, nullptr, &p.pipeline));
    destroyModules(ctx, stages);
    ctx.setName(VK_OBJECT_TYPE_PIPELINE, uint64_t(p.pipeline), p.name.c_str());
    return p;
}

void destroyPipeline(Context& ctx, Pipeline& p) {
    if (p.pipeline)
        vkDestroyPipeline(ctx.device(), p.pipeline, nullptr);
    if (p.layout)
        vkDestroyPipelineLayout(ctx.device(), p.layout, nullptr);
    // setLayouts[0] is the context's shared frame layout; only set 1 belongs to the pipeline.
    if (p.setLayouts[1])
        vkDestroyDescriptorSetLayout(ctx.device(), p.setLayouts[1], nullptr);
    p = Pipeline{};
}

void pushDescriptors(const Context& ctx, VkCommandBuffer cmd, const Pipeline& p, std::span<const DescriptorItem> items) {
    std::vector<VkWriteDescriptorSet> writes;
    writes.reserve(items.size());
    size_t expected = 0;
    for (const auto& b : p.bindings)
        expected += b.set == 1 ? 1 : 0;
    for (const DescriptorItem& it : items) {
        const ReflectedBinding* b = p.findBinding(1, it.binding);
        if (!b) {
            std::string msg = p.name + ": set 1 has no binding " + std::to_string(it.binding);
            fatal(__FILE__, __LINE__, msg.c_str());
        }
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstBinding = it.binding;
        w.descriptorCount = 1;
        w.descriptorType = b->type;
        bool isBuffer = b->type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER || b->type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        bool isTexelBuffer =
            b->type == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER || b->type == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        if (isBuffer)
            w.pBufferInfo = &it.buffer;
        else if (isTexelBuffer)
            w.pTexelBufferView = &it.texelBuffer;
        else
            w.pImageInfo = &it.image;
        writes.push_back(w);
    }
    if (writes.size() != expected) {
        std::string msg = p.name + ": " + std::to_string(writes.size()) + " descriptors pushed, shader declares " +
                          std::to_string(expected) + " in set 1";
        fatal(__FILE__, __LINE__, msg.c_str());
    }
    if (!writes.empty())
        ctx.fn().cmdPushDescriptorSet(cmd, p.bindPoint, p.layout, 1, uint32_t(writes.size()), writes.data());
}

void pushConstants(VkCommandBuffer cmd, const Pipeline& p, const void* data, uint32_t size) {
    if (size != p.pushConstantSize) {
        std::string msg = p.name + ": push constants of " + std::to_string(size) + " bytes, shader expects " +
                          std::to_string(p.pushConstantSize);
        fatal(__FILE__, __LINE__, msg.c_str());
    }
    if (size)
        vkCmdPushConstants(cmd, p.layout, p.stages, 0, size, data);
}

} // namespace vkgi
