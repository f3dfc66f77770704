#include "voxel/vct_passes.hpp"

#include <bit>
#include <cmath>
#include <initializer_list>
#include <string>

#include "engine/context.hpp"
#include "engine/vk_check.hpp"

namespace vkgi::gi {

namespace {

// The directional volume (vct_passes.h): N x N, GI_VOXEL_ANISO_DIRECTIONS * N layers.
Image createDirectionalVolume(Context& ctx, uint32_t n, uint32_t mips, const char* name) {
    ImageDesc d;
    d.type = VK_IMAGE_TYPE_2D;
    d.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    d.width = d.height = n;
    d.arrayLayers = GI_VOXEL_ANISO_DIRECTIONS * n;
    d.mipLevels = mips;
    d.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
              VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    return createImage(ctx, d, name);
}

DescriptorItem storage(uint32_t binding, VkImageView view) {
    DescriptorItem item;
    item.binding = binding;
    item.image = {VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL};
    return item;
}

DescriptorItem sampled(uint32_t binding, const Image& image, VkSampler sampler, VkImageLayout layout) {
    DescriptorItem item;
    item.binding = binding;
    item.image = {sampler, image.view, layout};
    return item;
}

template <typename Push>
void dispatch(const Context& ctx, VkCommandBuffer cmd, const Pipeline& p, const Push& push,
              std::initializer_list<DescriptorItem> items, glm::uvec3 threads) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
    pushConstants(cmd, p, &push, sizeof(push));
    pushDescriptors(ctx, cmd, p, std::span<const DescriptorItem>(items.begin(), items.size()));
    vkCmdDispatch(cmd, groupCount(threads.x, p.localSize[0]), groupCount(threads.y, p.localSize[1]),
                  groupCount(threads.z, p.localSize[2]));
}

DescriptorItem bufferItem(uint32_t binding, VkBuffer buffer) {
    DescriptorItem item;
    item.binding = binding;
    item.buffer = {buffer, 0, VK_WHOLE_SIZE};
    return item;
}

// As dispatch(), with the work-group counts read from `args` (VkDispatchIndirectCommand at 0).
template <typename Push>
void dispatchIndirect(const Context& ctx, VkCommandBuffer cmd, const Pipeline& p, const Push& push,
                      std::initializer_list<DescriptorItem> items, VkBuffer args, VkDeviceSize offset = 0) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
    pushConstants(cmd, p, &push, sizeof(push));
    pushDescriptors(ctx, cmd, p, std::span<const DescriptorItem>(items.begin(), items.size()));
    vkCmdDispatchIndirect(cmd, args, offset);
}

} // namespace

Result<std::unique_ptr<VctVolumes>> VctVolumes::create(Context& ctx, const VoxelGrid& grid) {
    std::unique_ptr<VctVolumes> v(new VctVolumes(ctx, grid));
    struct Named {
        Pipeline* pipeline;
        const char* shader;
    } shaders[] = {{&v->m_compact, "gi/voxel/voxel_compact.comp"},
                   {&v->m_listAppend, "gi/voxel/voxel_list_append.comp"},
                   {&v->m_listStale, "gi/voxel/voxel_list_stale.comp"},
                   {&v->m_light, "gi/voxel/voxel_light.comp"},
                   {&v->m_lightSoft, "gi/voxel/voxel_light_soft.comp"},
                   {&v->m_lightShadowMap, "gi/voxel/voxel_light_shadow_map.comp"},
                   {&v->m_mip, "gi/voxel/voxel_mip.comp"},
                   {&v->m_mipList, "gi/voxel/voxel_mip_list.comp"},
                   {&v->m_mipListJobs, "gi/voxel/voxel_mip_list_jobs.comp"},
                   {&v->m_mipTail, "gi/voxel/voxel_mip_tail.comp"},
                   {&v->m_bounce, "gi/voxel/voxel_bounce.comp"},
                   {&v->m_bounceApply, "gi/voxel/voxel_bounce_apply.comp"},
                   {&v->m_bounceMisfits, "gi/voxel/voxel_bounce_misfits.comp"},
                   {&v->m_trace, "gi/voxel/vct_trace.comp"},
                   {&v->m_traceRefine, "gi/voxel/vct_trace_refine.comp"},
                   {&v->m_upsample, "gi/voxel/vct_upsample.comp"},
                   {&v->m_softShadow, "gi/voxel/vct_soft_shadow.comp"}};
    for (const Named& s : shaders) {
        auto p = createComputePipeline(ctx, {s.shader, {}});
        if (!p)
            return p.error();
        *s.pipeline = std::move(*p);
    }
    uint32_t n = grid.resolution();
    v->m_levels = uint32_t(std::countr_zero(n)) + 1; // N^3 down to 1^3
    v->m_aniso.image = createDirectionalVolume(ctx, n, v->m_levels, "vct.aniso");
    BufferDesc list;
    // Header, voxel and block slots, the voxels' and blocks' "listed" bits, the 4^3 blocks' bits.
    list.size = VkDeviceSize(GI_VOXEL_LIST_HEADER + gpu::voxelListWords(n)) * sizeof(uint32_t);
    list.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                 VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    v->m_list.buffer = createBuffer(ctx, list, "vct.voxel_list");
    // The hard voxel-light march reads the list's occupancy bits through an R32_UINT storage texel
    // buffer: lavapipe loads a texel per lane without the per-lane branches of an SSBO load
    // (voxel_light_body.glsl). 4 (N^3 + ...) bytes: 78 MB at 256^3, within lavapipe's 2^27 texels.
    VkBufferViewCreateInfo words{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    words.buffer = v->m_list.buffer.buffer;
    words.format = VK_FORMAT_R32_UINT;
    words.offset = 0;
    words.range = VK_WHOLE_SIZE;
    VK_CHECK(vkCreateBufferView(ctx.device(), &words, nullptr, &v->m_listWords));
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
    // Outside the grid is empty space: sampleAniso (voxel_cone.glsl) turns the clamped edge
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
    for (rg::PersistentBuffer* b : {&m_jobBuffer, &m_resultBuffer})
        if (b->buffer.buffer)
            destroyBuffer(m_ctx, b->buffer);
    for (Pipeline* p : {&m_compact, &m_listAppend, &m_listStale, &m_light, &m_lightSoft, &m_lightShadowMap, &m_mip, &m_mipList, &m_mipTail, &m_mipListJobs, &m_bounce, &m_bounceApply, &m_bounceMisfits,
                        &m_trace, &m_traceRefine, &m_upsample, &m_softShadow})
        destroyPipeline(m_ctx, *p);
    destroyImage(m_ctx, m_aniso.image);
    for (VkSampler sampler : {m_sampler, m_occupancySampler})
        if (sampler)
            vkDestroySampler(m_ctx.device(), sampler, nullptr);
}

VkDeviceSize VctVolumes::bytes() const {
    return imageBytes(m_aniso.image.desc) + imageBytes(m_written.image.desc) + m_list.buffer.desc.size +
           m_writtenBits.buffer.desc.size +
           m_jobBuffer.buffer.desc.size +
           m_resultBuffer.buffer.desc.size;
}

gpu::ConeParams VctVolumes::coneParams(const VctSettings& s, uint32_t width, uint32_t height) const {
    gpu::ConeParams c{};
    float voxel = m_grid.params().originSize.w;
    uint32_t n = m_grid.resolution();
    // Default AO distance: an eighth of the grid, Villegas' "nearby geometry" scale.
    float aoDistance = s.aoDistance > 0.0f ? s.aoDistance / voxel : float(n) / 8.0f;
    c.cone = glm::vec4(std::tan(s.diffuseAperture), s.stepFactor, 1.0f / aoDistance, std::tan(s.shadowAperture));
    c.info = glm::uvec4(s.diffuseCones, (s.glossy ? GI_VCT_FLAG_GLOSSY : 0u) | (s.ambientOcclusion ? GI_VCT_FLAG_AO : 0u),
                        width, height);
    return c;
}

void VctVolumes::recordClearList(VkCommandBuffer cmd, VkBuffer list) const {
    uint32_t n = m_grid.resolution();
    VkDeviceSize slots = VkDeviceSize(n) * n * n + (n / 2) * (n / 2) * (n / 2);
    vkCmdFillBuffer(cmd, list, 0, GI_VOXEL_LIST_HEADER * sizeof(uint32_t), 0);
    vkCmdFillBuffer(cmd, list, (GI_VOXEL_LIST_HEADER + slots) * sizeof(uint32_t), VK_WHOLE_SIZE, 0);
}

void VctVolumes::recordCompact(VkCommandBuffer cmd, VkBuffer touched) const {
    gpu::VoxelGridPush push{m_grid.params()};
    dispatchIndirect(m_ctx, cmd, m_compact, push, {bufferItem(VCT_COMPACT_BINDING_TOUCHED, touched), bufferItem(VCT_COMPACT_BINDING_LIST, m_list.buffer.buffer)},
                     touched);
}

void VctVolumes::recordListAppend(VkCommandBuffer cmd) const {
    uint32_t n = m_grid.resolution();
    uint32_t words = (n * n * n + (n / 2) * (n / 2) * (n / 2)) / 32; // voxel and block bit words
    gpu::VoxelGridPush push{m_grid.params()};
    dispatch(m_ctx, cmd, m_listAppend, push, {bufferItem(VCT_APPEND_BINDING_LIST, m_list.buffer.buffer)}, glm::uvec3(words, 1u, 1u));
}

void VctVolumes::recordListStale(VkCommandBuffer cmd) const {
    gpu::VoxelGridPush push{m_grid.params()};
    dispatch(m_ctx, cmd, m_listStale, push,
             {bufferItem(VCT_STALE_BINDING_LIST, m_list.buffer.buffer),
              bufferItem(VCT_STALE_BINDING_WRITTEN_BITS, m_writtenBits.buffer.buffer),
              storage(VCT_STALE_BINDING_WRITTEN, m_written.image.view),
              storage(VCT_STALE_BINDING_LEVEL0, m_aniso.image.mipViews[0]),
              storage(VCT_STALE_BINDING_LEVEL1, m_aniso.image.mipViews[1])},
             glm::uvec3(gpu::voxelWrittenBitsWords(m_grid.resolution()), 1u, 1u));
}

void VctVolumes::recordClearLevels01(VkCommandBuffer cmd, VkImageLayout layout, VkImageLayout writtenLayout) const {
    vkCmdFillBuffer(cmd, m_writtenBits.buffer.buffer, 0, VK_WHOLE_SIZE, 0);
    VkClearColorValue none{};
    VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, m_written.image.image, writtenLayout, &none, 1, &all);
    // Level 0 whole; level 1 only the first N/2 layers of each direction, the ones it uses.
    VkClearColorValue zero{};
    uint32_t n = m_grid.resolution();
    VkImageSubresourceRange ranges[1 + GI_VOXEL_ANISO_DIRECTIONS];
    ranges[0] = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, VK_REMAINING_ARRAY_LAYERS};
    for (uint32_t d = 0; d < GI_VOXEL_ANISO_DIRECTIONS; ++d)
        ranges[1 + d] = {VK_IMAGE_ASPECT_COLOR_BIT, 1, 1, d * n, n / 2};
    vkCmdClearColorImage(cmd, m_aniso.image.image, layout, &zero, 1 + GI_VOXEL_ANISO_DIRECTIONS, ranges);
}

void VctVolumes::recordLight(VkCommandBuffer cmd, VkBuffer lights, uint32_t lightCount, VctOcclusion occlusion,
                             VkImageLayout sampledLayout, bool emission, const VctShadowInputs* shadow) const {
    const VoxelVolumes& g = m_grid.volumes();
    uint32_t mode = occlusion == VctOcclusion::RayMarchSoft ? GI_VCT_OCCLUSION_SOFT : GI_VCT_OCCLUSION_HARD;
    gpu::VoxelLightPush push{m_grid.params(), glm::uvec4(lightCount, mode, emission ? GI_VOXEL_LIGHT_EMISSION : 0u, 0u)};
    DescriptorItem lightItem;
    lightItem.binding = VCT_LIGHT_BINDING_LIGHTS;
    lightItem.buffer = {lights, 0, VK_WHOLE_SIZE};
    if (shadow) {
        dispatchIndirect(m_ctx, cmd, m_lightShadowMap, push,
                         {lightItem, storage(VCT_LIGHT_BINDING_EMISSION, g.emission.image.view),
                          storage(VCT_LIGHT_BINDING_OCCUPANCY, g.albedo.image.view),
                          storage(VCT_LIGHT_BINDING_DIRECTIONAL, m_aniso.image.mipViews[0]),
                          bufferItem(VCT_LIGHT_BINDING_LIST, m_list.buffer.buffer),
                          bufferItem(VCT_LIGHT_BINDING_LIGHT_SHADOWS, shadow->lightShadows),
                          bufferItem(VCT_LIGHT_BINDING_SHADOW_VIEWS, shadow->views),
                          sampled(VCT_LIGHT_BINDING_SHADOW_ATLAS, *shadow->atlas, shadow->compareSampler,
                                  shadow->atlasLayout),
                          storage(VCT_LIGHT_BINDING_FACES, g.faces.image.view),
                          storage(VCT_LIGHT_BINDING_WRITTEN, m_written.image.view)},
                         m_list.buffer.buffer);
        return;
    }
    // The soft march filters the occupancy (sampler); the hard one loads texels (storage image).
    if (mode == GI_VCT_OCCLUSION_SOFT) {
        dispatchIndirect(m_ctx, cmd, m_lightSoft, push,
                         {lightItem, storage(VCT_LIGHT_BINDING_EMISSION, g.emission.image.view),
                          sampled(VCT_LIGHT_BINDING_OCCUPANCY, g.albedo.image, m_occupancySampler, sampledLayout),
                          storage(VCT_LIGHT_BINDING_DIRECTIONAL, m_aniso.image.mipViews[0]),
                          bufferItem(VCT_LIGHT_BINDING_LIST, m_list.buffer.buffer),
                          storage(VCT_LIGHT_BINDING_FACES, g.faces.image.view),
                          storage(VCT_LIGHT_BINDING_WRITTEN, m_written.image.view)},
                         m_list.buffer.buffer);
        return;
    }
    DescriptorItem listWords;
    listWords.binding = VCT_LIGHT_BINDING_LIST_WORDS;
    listWords.texelBuffer = m_listWords;
    dispatchIndirect(m_ctx, cmd, m_light, push,
                     {lightItem, storage(VCT_LIGHT_BINDING_EMISSION, g.emission.image.view),
                      storage(VCT_LIGHT_BINDING_OCCUPANCY, g.albedo.image.view),
                      storage(VCT_LIGHT_BINDING_DIRECTIONAL, m_aniso.image.mipViews[0]),
                      bufferItem(VCT_LIGHT_BINDING_LIST, m_list.buffer.buffer),
                      storage(VCT_LIGHT_BINDING_FACES, g.faces.image.view),
                      storage(VCT_LIGHT_BINDING_WRITTEN, m_written.image.view), listWords},
                     m_list.buffer.buffer);
}

void VctVolumes::recordMip(VkCommandBuffer cmd, uint32_t level, VkBuffer jobs) const {
    uint32_t size = std::max(1u, m_grid.resolution() >> level);
    gpu::VoxelMipPush push{m_grid.params(), glm::uvec4(level, size, 0u, 0u)};
    if (level == 1 && jobs) { // and the bounce jobs (voxel_mip_body.glsl)
        dispatchIndirect(m_ctx, cmd, m_mipListJobs, push,
                         {storage(VCT_MIP_BINDING_SOURCE, m_aniso.image.mipViews[0]),
                          storage(VCT_MIP_BINDING_TARGET, m_aniso.image.mipViews[1]),
                          bufferItem(VCT_MIP_BINDING_LIST, m_list.buffer.buffer),
                          storage(VCT_MIP_BINDING_NORMAL, m_grid.volumes().normal.image.view),
                          bufferItem(VCT_MIP_BINDING_JOBS, jobs)},
                         m_list.buffer.buffer, GI_VOXEL_LIST_BLOCKS * sizeof(uint32_t));
        return;
    }
    if (level == 1) { // the listed occupied blocks only (voxel_mip_body.glsl)
        dispatchIndirect(m_ctx, cmd, m_mipList, push,
                         {storage(VCT_MIP_BINDING_SOURCE, m_aniso.image.mipViews[0]),
                          storage(VCT_MIP_BINDING_TARGET, m_aniso.image.mipViews[1]),
                          bufferItem(VCT_MIP_BINDING_LIST, m_list.buffer.buffer)},
                         m_list.buffer.buffer, GI_VOXEL_LIST_BLOCKS * sizeof(uint32_t));
        return;
    }
    if (level >= mipTailLevel()) { // this level and all coarser ones, four at most (VCT_MIP_BINDING_TAIL + 0..3)
        uint32_t count = m_levels - level;
        GI_ASSERT(level == mipTailLevel() && count <= 4, "the mip tail starts at mipTailLevel()");
        push.info.z = count;
        auto view = [&](uint32_t i) { return m_aniso.image.mipViews[std::min(level + i, m_levels - 1)]; };
        dispatch(m_ctx, cmd, m_mipTail, push,
                 {storage(VCT_MIP_BINDING_SOURCE, m_aniso.image.mipViews[level - 1]),
                  storage(VCT_MIP_BINDING_TAIL + 0, view(0)), storage(VCT_MIP_BINDING_TAIL + 1, view(1)),
                  storage(VCT_MIP_BINDING_TAIL + 2, view(2)), storage(VCT_MIP_BINDING_TAIL + 3, view(3))},
                 glm::uvec3(m_mipTail.localSize[0], m_mipTail.localSize[1], m_mipTail.localSize[2]));
        return;
    }
    dispatch(m_ctx, cmd, m_mip, push,
             {storage(VCT_MIP_BINDING_SOURCE, m_aniso.image.mipViews[level - 1]),
              storage(VCT_MIP_BINDING_TARGET, m_aniso.image.mipViews[level])},
             glm::uvec3(size));
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

rg::PersistentBuffer& VctVolumes::bounceResultsState() {
    createOnce(m_ctx, m_resultBuffer, gpu::bounceResultWords(m_grid.resolution()), "vct.bounce_results");
    return m_resultBuffer;
}

void VctVolumes::recordClearBounceJobs(VkCommandBuffer cmd, VkBuffer jobs) const {
    // Header: the gathers' dispatch (x = 0, one work-group row per class), the misfits' (x = 0),
    // zero counts; then every block's class mask, the misfit bits and the sums 0 (gi/vct_passes.h).
    uint32_t header[GI_BOUNCE_HEADER] = {0u, GI_BOUNCE_CLASSES, 1u, 0u, 0u, 1u, 1u, 0u};
    vkCmdUpdateBuffer(cmd, jobs, 0, sizeof(header), header);
    uint32_t n = m_grid.resolution();
    vkCmdFillBuffer(cmd, jobs, sizeof(header), VkDeviceSize(gpu::bounceBlockCount(n)) * sizeof(uint32_t), 0);
    vkCmdFillBuffer(cmd, jobs, sizeof(header) + VkDeviceSize(gpu::bounceMisfitBitsOffset(n)) * sizeof(uint32_t),
                    VkDeviceSize(n * n * n / 32 + gpu::bounceGeometryWords(n)) * sizeof(uint32_t), 0);
}

void VctVolumes::recordBounceBlocks(VkCommandBuffer cmd, const gpu::ConeParams& cones, VkBuffer jobs,
                                    VkBuffer results, VkImageLayout sampledLayout) const {
    gpu::VoxelBouncePush push{m_grid.params(), cones};
    dispatchIndirect(m_ctx, cmd, m_bounce, push,
                     {sampled(VCT_CONE_BINDING_DIRECTIONAL, m_aniso.image, m_sampler, sampledLayout),
                      storage(VCT_BOUNCE_BINDING_NORMAL, m_grid.volumes().normal.image.view),
                      bufferItem(VCT_BOUNCE_BINDING_JOBS, jobs), bufferItem(VCT_BOUNCE_BINDING_RESULTS, results),
                      bufferItem(VCT_BOUNCE_BINDING_LIST, m_list.buffer.buffer)},
                     jobs);
}

void VctVolumes::recordBounceApply(VkCommandBuffer cmd, VkBuffer jobs, VkBuffer results, const Image& misfits) const {
    const VoxelVolumes& g = m_grid.volumes();
    gpu::VoxelGridPush push{m_grid.params()};
    dispatchIndirect(m_ctx, cmd, m_bounceApply, push,
                     {storage(VCT_APPLY_BINDING_ALBEDO, g.albedo.image.view),
                      storage(VCT_APPLY_BINDING_NORMAL, g.normal.image.view), bufferItem(VCT_APPLY_BINDING_JOBS, jobs),
                      storage(VCT_APPLY_BINDING_MISFITS, misfits.view),
                      bufferItem(VCT_APPLY_BINDING_LIST, m_list.buffer.buffer),
                      bufferItem(VCT_APPLY_BINDING_RESULTS, results), storage(VCT_APPLY_BINDING_FACES, g.faces.image.view),
                      storage(VCT_APPLY_BINDING_DIRECTIONAL, m_aniso.image.mipViews[0])},
                     m_list.buffer.buffer);
}

void VctVolumes::recordBounceMisfits(VkCommandBuffer cmd, const gpu::ConeParams& cones, VkBuffer jobs,
                                     const Image& bounce, VkImageLayout sampledLayout) const {
    const VoxelVolumes& g = m_grid.volumes();
    gpu::VoxelBouncePush push{m_grid.params(), cones};
    dispatchIndirect(m_ctx, cmd, m_bounceMisfits, push,
                     {sampled(VCT_CONE_BINDING_DIRECTIONAL, m_aniso.image, m_sampler, sampledLayout),
                      storage(VCT_MISFITS_BINDING_ALBEDO, g.albedo.image.view),
                      storage(VCT_MISFITS_BINDING_NORMAL, g.normal.image.view),
                      storage(VCT_MISFITS_BINDING_OUTPUT, bounce.view), bufferItem(VCT_MISFITS_BINDING_JOBS, jobs)},
                     jobs, GI_BOUNCE_MISFITS * sizeof(uint32_t));
}

void VctVolumes::recordTrace(VkCommandBuffer cmd, VctTraceMode mode, const gpu::VctTracePush& push,
                             const VctTraceTargets& t, VkImageLayout sampledLayout) const {
    DescriptorItem common[] = {sampled(VCT_CONE_BINDING_DIRECTIONAL, m_aniso.image, m_sampler, sampledLayout),
                               storage(VCT_TRACE_BINDING_POSITION, t.position->view),
                               storage(VCT_TRACE_BINDING_NORMAL, t.normal->view),
                               storage(VCT_TRACE_BINDING_ALBEDO, t.albedo->view),
                               storage(VCT_TRACE_BINDING_INDIRECT, t.indirect->view),
                               storage(VCT_TRACE_BINDING_GLOSSY, t.glossy->view)};
    if (mode == VctTraceMode::Grid) {
        dispatch(m_ctx, cmd, m_trace, push,
                 {common[0], common[1], common[2], common[3], common[4], common[5], bufferItem(VCT_TRACE_BINDING_REFINE_LIST, t.refineList)},
                 glm::uvec3(push.lowRes.y, push.lowRes.z, 1u));
        return;
    }
    // Work groups counted by the upsample (header words 1..3, vct_passes.h).
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_traceRefine.pipeline);
    pushConstants(cmd, m_traceRefine, &push, sizeof(push));
    DescriptorItem items[] = {common[0], common[1], common[2], common[3], common[4], common[5],
                              bufferItem(VCT_TRACE_BINDING_REFINE_LIST, t.refineList)};
    pushDescriptors(m_ctx, cmd, m_traceRefine, std::span<const DescriptorItem>(items));
    vkCmdDispatchIndirect(cmd, t.refineList, sizeof(uint32_t));
}

void VctVolumes::recordSoftShadow(VkCommandBuffer cmd, const gpu::VctShadowPush& push, VkBuffer lights,
                                  const VctTraceTargets& t, VkImageLayout sampledLayout) const {
    dispatch(m_ctx, cmd, m_softShadow, push,
             {sampled(VCT_CONE_BINDING_DIRECTIONAL, m_aniso.image, m_sampler, sampledLayout),
              storage(VCT_SHADOW_BINDING_POSITION, t.position->view), storage(VCT_SHADOW_BINDING_NORMAL, t.normal->view),
              storage(VCT_SHADOW_BINDING_ALBEDO, t.albedo->view), storage(VCT_SHADOW_BINDING_EMISSION, t.emission->view),
              bufferItem(VCT_SHADOW_BINDING_LIGHTS, lights), storage(VCT_SHADOW_BINDING_DIRECT, t.direct->view)},
             glm::uvec3(push.info.y, push.info.z, 1u));
}

void VctVolumes::recordUpsample(VkCommandBuffer cmd, const gpu::VctTracePush& push, const Image& lowIndirect,
                                const Image& lowGlossy, const VctTraceTargets& t) const {
    // 4x4 pixel blocks from -f / 2 on (vctRefineBlockOrigin in vct_refine.glsl).
    auto blocks = [shift = push.lowRes.x / 2u](uint32_t size) { return (size + shift + 3u) / 4u; };
    dispatch(m_ctx, cmd, m_upsample, push,
             {storage(VCT_UPSAMPLE_BINDING_POSITION, t.position->view), storage(VCT_UPSAMPLE_BINDING_NORMAL, t.normal->view),
              storage(VCT_UPSAMPLE_BINDING_LOW_INDIRECT, lowIndirect.view),
              storage(VCT_UPSAMPLE_BINDING_LOW_GLOSSY, lowGlossy.view),
              storage(VCT_UPSAMPLE_BINDING_INDIRECT, t.indirect->view),
              storage(VCT_UPSAMPLE_BINDING_GLOSSY, t.glossy->view),
              bufferItem(VCT_UPSAMPLE_BINDING_REFINE_LIST, t.refineList),
              storage(VCT_UPSAMPLE_BINDING_ALBEDO, t.albedo->view)},
             glm::uvec3(blocks(push.cones.info.z), blocks(push.cones.info.w), 1u));
}

} // namespace vkgi::gi
