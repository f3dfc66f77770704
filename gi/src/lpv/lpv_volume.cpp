#include "lpv/lpv_volume.hpp"

#include <string>

#include "engine/context.hpp"
#include "engine/vk_check.hpp"
#include "gi/lpv.h"
#include "lpv/lpv_passes.hpp"

namespace vkgi::gi::lpv {

bool isSupportedShFormat(VkFormat format) {
    return format == VK_FORMAT_R16G16B16A16_SFLOAT || format == VK_FORMAT_R32G32B32A32_SFLOAT;
}

ShImages createShImages(Context& ctx, glm::ivec3 cells, VkFormat format, const char* name) {
    ShImages images;
    ImageDesc desc = shImageDesc(cells, format);
    const char* suffix[3] = {".r", ".g", ".b"};
    for (int c = 0; c < 3; ++c)
        images.channel[c] = createImage(ctx, desc, (std::string(name) + suffix[c]).c_str());
    return images;
}

void destroyShImages(Context& ctx, ShImages& images) {
    for (Image& image : images.channel)
        destroyImage(ctx, image);
}

Result<Propagator> Propagator::create(Context& ctx) {
    Propagator p;
    const char* shaders[2] = {"gi/lpv/propagate_rgba16f.comp", "gi/lpv/propagate_rgba32f.comp"};
    for (int f = 0; f < 2; ++f)
        for (uint32_t occlusion = 0; occlusion < 2; ++occlusion)
            for (uint32_t bounce = 0; bounce < 2; ++bounce)
                for (uint32_t acc = 0; acc < 3; ++acc) {
                    auto pipeline = createComputePipeline(
                        ctx, {shaders[f],
                              {{LPV_SPEC_OCCLUSION, occlusion}, {LPV_SPEC_BOUNCE, bounce}, {LPV_SPEC_ACCUMULATE, acc}}});
                    if (!pipeline) {
                        p.destroy(ctx);
                        return pipeline.error();
                    }
                    p.m_pipelines[f][occlusion][bounce][acc] = *pipeline;
                }
    ImageDesc desc;
    desc.type = VK_IMAGE_TYPE_3D;
    desc.format = kGeometryVolumeFormat;
    desc.usage = VK_IMAGE_USAGE_STORAGE_BIT;
    p.m_noGeometry = createImage(ctx, desc, "gi.lpv.gv.none");
    const uint64_t zero = 0;
    uploadImage(ctx, p.m_noGeometry, &zero, sizeof(zero), VK_IMAGE_LAYOUT_GENERAL);
    desc.format = VK_FORMAT_R8G8B8A8_UNORM;
    desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT;
    p.m_noVoxels = createImage(ctx, desc, "gi.lpv.voxels.none");
    uploadImage(ctx, p.m_noVoxels, &zero, 4, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    SamplerDesc linear;
    linear.mipmap = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    p.m_linear = createSampler(ctx, linear);
    return p;
}

void Propagator::destroy(Context& ctx) {
    for (auto& byFormat : m_pipelines)
        for (auto& byOcclusion : byFormat)
            for (auto& byBounce : byOcclusion)
                for (Pipeline& pipeline : byBounce)
                    if (pipeline.pipeline != VK_NULL_HANDLE)
                        destroyPipeline(ctx, pipeline);
    if (m_noGeometry)
        destroyImage(ctx, m_noGeometry);
    if (m_noVoxels)
        destroyImage(ctx, m_noVoxels);
    if (m_linear != VK_NULL_HANDLE) {
        vkDestroySampler(ctx.device(), m_linear, nullptr);
        m_linear = VK_NULL_HANDLE;
    }
}

void Propagator::record(const Context& ctx, VkCommandBuffer cmd, const PropagateStep& step, const ShViews& src,
                        const ShViews& dst, const ShViews& acc) const {
    GI_ASSERT(isSupportedShFormat(step.format), "lpv::Propagator::record: SH format must be RGBA16F or RGBA32F");
    const Pipeline& pipeline =
        m_pipelines[step.format == VK_FORMAT_R32G32B32A32_SFLOAT][step.occlusion][step.bounce][step.accumulate];
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline);
    gpu::LpvPropagatePush push{};
    push.gridSize = glm::ivec4(step.cells, 0);
    push.lpvOrigin = step.lpvOrigin;
    push.voxelOrigin = step.voxelOrigin;
    pushConstants(cmd, pipeline, &push, sizeof(push));
    DescriptorItem items[12];
    auto storage = [](uint32_t binding, VkImageView view) {
        DescriptorItem item;
        item.binding = binding;
        item.image = {VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL};
        return item;
    };
    for (uint32_t c = 0; c < 3; ++c) {
        items[c] = storage(LPV_PROPAGATE_BINDING_SOURCE_R + c, src.channel[c]);
        items[3 + c] = storage(LPV_PROPAGATE_BINDING_TARGET_R + c, dst.channel[c]);
        items[6 + c] = storage(LPV_PROPAGATE_BINDING_ACCUMULATION_R + c, acc.channel[c]);
    }
    items[9] = storage(LPV_PROPAGATE_BINDING_GEOMETRY_VOLUME, step.geometryVolume);
    items[10].binding = LPV_PROPAGATE_BINDING_VOXEL_ALBEDO;
    items[10].image = {m_linear, step.voxelAlbedo, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    items[11].binding = LPV_PROPAGATE_BINDING_VOXEL_NORMAL;
    items[11].image = {m_linear, step.voxelNormal, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    pushDescriptors(ctx, cmd, pipeline, items);
    vkCmdDispatch(cmd, groupCount(uint32_t(step.cells.x), LPV_LOCAL_SIZE_X),
                  groupCount(uint32_t(step.cells.y), LPV_LOCAL_SIZE_Y),
                  groupCount(uint32_t(step.cells.z), LPV_LOCAL_SIZE_Z));
}

} // namespace vkgi::gi::lpv
