#include "vct/vct_volumes.hpp"

#include <bit>
#include <cmath>
#include <string>

#include "vkgi/context.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

// The directional volume (vct_passes.h): N x N, GI_VCT_DIRECTIONS * N layers.
Image createDirectionalVolume(Context& ctx, uint32_t n, uint32_t mips, const char* name) {
    ImageDesc d;
    d.type = VK_IMAGE_TYPE_2D;
    d.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    d.width = d.height = n;
    d.arrayLayers = GI_VCT_DIRECTIONS * n;
    d.mipLevels = mips;
    d.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
              VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    return createImage(ctx, d, name);
}

} // namespace

Result<std::unique_ptr<VctVolumes>> VctVolumes::create(Context& ctx, const VoxelGrid& grid) {
    std::unique_ptr<VctVolumes> v(new VctVolumes(ctx, grid));
    struct Named {
        Pipeline* pipeline;
        const char* shader;
    } shaders[] = {{&v->m_pipelines.compact, "gi/vct/voxel_compact.comp"},
                   {&v->m_pipelines.listAppend, "gi/vct/voxel_list_append.comp"},
                   {&v->m_pipelines.listStale, "gi/vct/voxel_list_stale.comp"},
                   {&v->m_pipelines.light, "gi/vct/voxel_light.comp"},
                   {&v->m_pipelines.lightSoft, "gi/vct/voxel_light_soft.comp"},
                   {&v->m_pipelines.lightShadowMap, "gi/vct/voxel_light_shadow_map.comp"},
                   {&v->m_pipelines.mip, "gi/vct/voxel_mip.comp"},
                   {&v->m_pipelines.mipList, "gi/vct/voxel_mip_list.comp"},
                   {&v->m_pipelines.mipListJobs, "gi/vct/voxel_mip_list_jobs.comp"},
                   {&v->m_pipelines.mipTail, "gi/vct/voxel_mip_tail.comp"},
                   {&v->m_pipelines.bounce, "gi/vct/voxel_bounce.comp"},
                   {&v->m_pipelines.bounceApply, "gi/vct/voxel_bounce_apply.comp"},
                   {&v->m_pipelines.bounceMisfits, "gi/vct/voxel_bounce_misfits.comp"},
                   {&v->m_pipelines.bounceClip, "gi/vct/voxel_bounce_clip.comp"},
                   {&v->m_pipelines.bounceMisfitsClip, "gi/vct/voxel_bounce_misfits_clip.comp"},
                   {&v->m_pipelines.trace, "gi/vct/vct_trace.comp"},
                   {&v->m_pipelines.traceRefine, "gi/vct/vct_trace_refine.comp"},
                   {&v->m_pipelines.upsample, "gi/vct/vct_upsample.comp"},
                   {&v->m_pipelines.filter, "gi/vct/vct_filter.comp"},
                   {&v->m_pipelines.softShadow, "gi/vct/vct_soft_shadow.comp"},
                   {&v->m_pipelines.traceClip, "gi/vct/vct_trace_clip.comp"},
                   {&v->m_pipelines.traceRefineClip, "gi/vct/vct_trace_refine_clip.comp"}};
    for (const Named& s : shaders) {
        auto p = createComputePipeline(ctx, {s.shader, {}});
        if (!p)
            return p.error();
        *s.pipeline = std::move(*p);
    }
    uint32_t n = grid.resolution();
    v->m_levels = uint32_t(std::countr_zero(n)) + 1; // N^3 down to 1^3
    v->m_directional.image = createDirectionalVolume(ctx, n, v->m_levels, "vct.directional");
    BufferDesc list;
    // Header, voxel and block slots, the voxels' and blocks' "listed" bits, the 4^3 blocks' bits.
    list.size = VkDeviceSize(GI_VOXEL_LIST_HEADER + gpu::voxelListWords(n)) * sizeof(uint32_t);
    list.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                 VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    v->m_list.buffer = createBuffer(ctx, list, "vct.voxel_list");
    // The hard voxel-light march reads the list's occupancy bits through an R32_UINT storage texel
    // buffer: lavapipe loads a texel per lane without the per-lane branches of an SSBO load
    // (voxel_light_body.glsl). Its 4 (N^3 + ...) bytes stay within lavapipe's 2^27 texels up to
    // GI_VOXEL_MAX_RESOLUTION.
    VkBufferViewCreateInfo words{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    words.buffer = v->m_list.buffer.buffer;
    words.format = VK_FORMAT_R32_UINT;
    words.offset = 0;
    words.range = VK_WHOLE_SIZE;
    VKGI_CHECK(vkCreateBufferView(ctx.device(), &words, nullptr, &v->m_listWords));
    ImageDesc written;
    written.type = VK_IMAGE_TYPE_3D;
    written.format = VK_FORMAT_R8_UINT;
    written.width = written.height = written.depth = n;
    written.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    v->m_written.image = createImage(ctx, written, "vct.written");
    BufferDesc bits;
    bits.size = VkDeviceSize(gpu::voxelWrittenBitsWords(n)) * sizeof(uint32_t);
    bits.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    v->m_writtenBits.buffer = createBuffer(ctx, bits, "vct.written_bits");
    SamplerDesc s;
    // Outside the grid is empty space: sampleDirectional (voxel_cone.glsl) turns the clamped edge
    // into the transparent border (exactly, and faster on lavapipe than a border colour).
    s.address = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    s.mipmap = VK_SAMPLER_MIPMAP_MODE_NEAREST; // one level per cone sample (voxel_cone.glsl)
    v->m_sampler = createSampler(ctx, s);
    // The soft voxel-light march filters the occupancy trilinearly: beyond the grid is empty.
    SamplerDesc occupancy;
    occupancy.address = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER;
    occupancy.border = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
    v->m_occupancySampler = createSampler(ctx, occupancy);
    return v;
}

VctVolumes::~VctVolumes() {
    if (m_listWords)
        vkDestroyBufferView(m_ctx.device(), m_listWords, nullptr);
    destroyBuffer(m_ctx, m_list.buffer);
    destroyBuffer(m_ctx, m_writtenBits.buffer);
    destroyImage(m_ctx, m_written.image);
    for (rg::PersistentImage* image : {&m_lit, &m_bounce, &m_keptStandIn})
        if (image->image.image)
            destroyImage(m_ctx, image->image);
    for (rg::PersistentBuffer* b : {&m_jobBuffer, &m_resultBuffer})
        if (b->buffer.buffer)
            destroyBuffer(m_ctx, b->buffer);
    Pipelines& p = m_pipelines;
    for (Pipeline* pipeline : {&p.compact, &p.listAppend, &p.listStale, &p.light, &p.lightSoft, &p.lightShadowMap,
                               &p.mip, &p.mipList, &p.mipListJobs, &p.mipTail, &p.bounce, &p.bounceMisfits,
                               &p.bounceApply, &p.trace, &p.traceRefine, &p.upsample, &p.filter, &p.softShadow,
                               &p.traceClip, &p.traceRefineClip, &p.bounceClip, &p.bounceMisfitsClip})
        destroyPipeline(m_ctx, *pipeline);
    destroyImage(m_ctx, m_directional.image);
    for (VkSampler sampler : {m_sampler, m_occupancySampler})
        if (sampler)
            vkDestroySampler(m_ctx.device(), sampler, nullptr);
}

VkDeviceSize VctVolumes::bytes() const {
    return imageBytes(m_directional.image.desc) + imageBytes(m_written.image.desc) +
           (m_lit.image.image ? imageBytes(m_lit.image.desc) : 0) +
           (m_bounce.image.image ? imageBytes(m_bounce.image.desc) : 0) +
           (m_keptStandIn.image.image ? imageBytes(m_keptStandIn.image.desc) : 0) + m_list.buffer.desc.size +
           m_writtenBits.buffer.desc.size + m_jobBuffer.buffer.desc.size + m_resultBuffer.buffer.desc.size;
}

gpu::ConeParams VctVolumes::coneParams(const VctSettings& s, uint32_t width, uint32_t height) const {
    gpu::ConeParams c{};
    float voxel = m_grid.params().originSize.w;
    uint32_t n = m_grid.resolution();
    // Default AO distance: an eighth of the grid, Villegas' "nearby geometry" scale.
    float aoDistance = s.aoDistance > 0.0f ? s.aoDistance / voxel : float(n) / 8.0f;
    c.cone = glm::vec4(std::tan(s.diffuseAperture), s.stepFactor, 1.0f / aoDistance, std::tan(s.shadowAperture));
    c.info =
        glm::uvec4(s.diffuseCones, (s.glossy ? GI_VCT_FLAG_GLOSSY : 0u) | (s.ambientOcclusion ? GI_VCT_FLAG_AO : 0u),
                   width, height);
    return c;
}

namespace {

void createOnce(Context& ctx, rg::PersistentBuffer& b, uint32_t words, const char* name) {
    if (b.buffer.buffer)
        return;
    BufferDesc desc;
    desc.size = VkDeviceSize(words) * sizeof(uint32_t);
    desc.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                 VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    b.buffer = createBuffer(ctx, desc, name);
}

} // namespace

rg::PersistentBuffer& VctVolumes::bounceJobsState() {
    createOnce(m_ctx, m_jobBuffer, GI_BOUNCE_HEADER + gpu::bounceJobWords(m_grid.resolution()), "vct.bounce_jobs");
    return m_jobBuffer;
}

rg::PersistentImage& VctVolumes::litState() {
    if (!m_lit.image.image)
        m_lit.image = createDirectionalVolume(m_ctx, m_grid.resolution(), 1, "vct.lit");
    return m_lit;
}

rg::PersistentImage& VctVolumes::bounceState() {
    if (!m_bounce.image.image) {
        ImageDesc d;
        d.type = VK_IMAGE_TYPE_3D;
        d.format = VK_FORMAT_R32G32B32A32_UINT; // voxel_bounce_apply.comp: float bits, or four sides' rgb9e5
        d.width = d.height = d.depth = m_grid.resolution();
        d.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
        m_bounce.image = createImage(m_ctx, d, "vct.bounce");
    }
    return m_bounce;
}

rg::PersistentImage& VctVolumes::keptStandIn() {
    if (!m_keptStandIn.image.image) {
        ImageDesc d;
        d.type = VK_IMAGE_TYPE_3D;
        d.format = VK_FORMAT_R32G32B32A32_UINT;
        d.width = d.height = d.depth = 1;
        d.usage = VK_IMAGE_USAGE_STORAGE_BIT;
        m_keptStandIn.image = createImage(m_ctx, d, "vct.bounce_kept_stand_in");
    }
    return m_keptStandIn;
}

rg::PersistentBuffer& VctVolumes::bounceResultsState() {
    createOnce(m_ctx, m_resultBuffer, gpu::bounceResultWords(m_grid.resolution()), "vct.bounce_results");
    return m_resultBuffer;
}

} // namespace vkgi::gi
