#include "lpv/lpv_volume.hpp"

#include "vkgi/context.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"
#include "gi/lpv.h"

namespace vkgi::gi::lpv {

bool isSupportedShFormat(VkFormat format) {
    return format == VK_FORMAT_R16G16B16A16_SFLOAT || format == VK_FORMAT_R32G32B32A32_SFLOAT;
}

Result<Propagator> Propagator::create(Context& ctx) {
    Propagator p;
    const char* shaders[2] = {"gi/lpv/propagate_rgba16f.comp", "gi/lpv/propagate_rgba32f.comp"};
    for (int f = 0; f < 2; ++f)
        for (uint32_t occlusion = 0; occlusion < 2; ++occlusion)
            for (uint32_t bounce = 0; bounce < 2; ++bounce)
                for (uint32_t accumulate = 0; accumulate < 3; ++accumulate) {
                    auto pipeline = createComputePipeline(ctx, {shaders[f],
                                                                {{LPV_SPEC_OCCLUSION, occlusion},
                                                                 {LPV_SPEC_BOUNCE, bounce},
                                                                 {LPV_SPEC_ACCUMULATE, accumulate}}});
                    if (!pipeline) {
                        p.destroy(ctx);
                        return pipeline.error();
                    }
                    p.m_pipelines[f][occlusion][bounce][accumulate] = *pipeline;
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
    p.m_voxelSampler = createSampler(ctx, linear);
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
    if (m_voxelSampler != VK_NULL_HANDLE) {
        vkDestroySampler(ctx.device(), m_voxelSampler, nullptr);
        m_voxelSampler = VK_NULL_HANDLE;
    }
}

const Pipeline& Propagator::pipeline(VkFormat format, bool occlusion, bool bounce, uint32_t accumulate) const {
    VKGI_ASSERT(isSupportedShFormat(format), "lpv::Propagator::pipeline: SH format must be RGBA16F or RGBA32F");
    VKGI_ASSERT(accumulate <= LPV_ACCUMULATE_PAIR, "lpv::Propagator::pipeline: accumulate must be LPV_ACCUMULATE_*");
    return m_pipelines[format == VK_FORMAT_R32G32B32A32_SFLOAT][occlusion][bounce][accumulate];
}

} // namespace vkgi::gi::lpv
