#include "voxel/voxel_grid.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "engine/context.hpp"

namespace vkgi::gi {

namespace {

constexpr VkImageUsageFlags kVolumeUsage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                           VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;

Image createVolume(Context& ctx, uint32_t n, uint32_t depth, VkFormat format, const char* name) {
    ImageDesc d;
    d.type = VK_IMAGE_TYPE_3D;
    d.format = format;
    d.width = n;
    d.height = n;
    d.depth = depth;
    d.usage = kVolumeUsage;
    return createImage(ctx, d, name);
}

VoxelVolumes createVolumes(Context& ctx, uint32_t n, const char* prefix) {
    std::string p = prefix;
    VoxelVolumes v;
    v.albedo.image = createVolume(ctx, n, n, VK_FORMAT_R8G8B8A8_UNORM, (p + ".albedo").c_str());
    v.normal.image = createVolume(ctx, n, n, VK_FORMAT_R8G8B8A8_UNORM, (p + ".normal").c_str());
    v.emission.image = createVolume(ctx, n, n, VK_FORMAT_R16G16B16A16_SFLOAT, (p + ".emission").c_str());
    v.faces.image = createVolume(ctx, n, n, VK_FORMAT_R32_UINT, (p + ".faces").c_str());
    return v;
}

void destroyVolumes(Context& ctx, VoxelVolumes& v) {
    destroyImage(ctx, v.albedo.image);
    destroyImage(ctx, v.normal.image);
    destroyImage(ctx, v.emission.image);
    destroyImage(ctx, v.faces.image);
}

DescriptorItem storageImage(uint32_t binding, const Image& image) {
    DescriptorItem item;
    item.binding = binding;
    item.image = {VK_NULL_HANDLE, image.view, VK_IMAGE_LAYOUT_GENERAL};
    return item;
}

DescriptorItem storageBuffer(uint32_t binding, VkBuffer buffer, VkDeviceSize offset = 0,
                             VkDeviceSize range = VK_WHOLE_SIZE) {
    DescriptorItem item;
    item.binding = binding;
    item.buffer = {buffer, offset, range};
    return item;
}

// Bytes of the records of `layers` z-layers of an N^3 grid.
VkDeviceSize accumBytes(uint32_t n, uint32_t layers) {
    return VkDeviceSize(n) * n * layers * GI_VOXEL_ACC_STRIDE * sizeof(uint32_t);
}

} // namespace

Result<gpu::VoxelGridParams> fitVoxelGrid(const Aabb& box, uint32_t resolution, float radianceScale) {
    glm::vec3 extent = box.extent();
    float longest = std::max(extent.x, std::max(extent.y, extent.z));
    if (!box.valid() || !std::isfinite(longest) || !std::isfinite(box.min.x + box.min.y + box.min.z))
        return makeError("voxel grid: the box to fit is empty or not finite");
    if (resolution < 2 || (resolution & (resolution - 1)) != 0)
        return makeError("voxel grid: resolution " + std::to_string(resolution) + " is not a power of two >= 2");
    if (!(radianceScale > 0.0f) || !std::isfinite(radianceScale))
        return makeError("voxel grid: radianceScale must be positive and finite");
    // A flat or point-like box still needs a positive voxel: take a 1e-6 relative floor.
    float floorSize = 1e-6f * std::max(1.0f, glm::length(box.centre()));
    float voxel = std::max(longest, floorSize) / float(resolution - 1);
    gpu::VoxelGridParams p{};
    p.originSize = glm::vec4(box.centre() - 0.5f * voxel * float(resolution), voxel);
    p.scales = glm::vec4(1.0f / voxel, radianceScale, 1.0f / radianceScale, 0.0f);
    p.dims = glm::uvec4(resolution, uint32_t(std::countr_zero(resolution)), 0u, 0u);
    return p;
}

float chooseRadianceScale(float maxRadiance) {
    if (!(maxRadiance > 0.0f) || !std::isfinite(maxRadiance))
        return 1.0f;
    // target * exp2(-ceil(log2(L))): exact power of two, so scaling and unscaling lose no bits.
    return std::ldexp(float(GI_VOXEL_RADIANCE_TARGET), -int(std::ceil(std::log2(maxRadiance))));
}

float sceneMaxRadiance(const Scene& scene, float voxelSize) {
    constexpr float kInvPi = 0.318309886f;
    float maxRadiance = 0.0f;
    for (const Material& m : scene.materials)
        maxRadiance = std::max(maxRadiance, std::max(m.emission.x, std::max(m.emission.y, m.emission.z)));
    float halfVoxel2 = 0.25f * voxelSize * voxelSize;
    for (const Light& l : scene.lights) {
        float c = l.intensity * std::max(l.color.x, std::max(l.color.y, l.color.z));
        float e = l.type == LightType::Directional ? c : c / halfVoxel2;
        maxRadiance = std::max(maxRadiance, e * kInvPi);
    }
    return maxRadiance;
}

Result<std::unique_ptr<VoxelGrid>> VoxelGrid::create(Context& ctx, const gpu::VoxelGridParams& params) {
    uint32_t n = params.dims.x;
    if (n < GI_VOXEL_MIN_RESOLUTION || n > GI_VOXEL_MAX_RESOLUTION || (n & (n - 1)) != 0)
        return makeError("voxel grid: resolution " + std::to_string(n) + " must be a power of two in [16, 256]");
    // The accumulation records are bound as GI_VOXEL_ACC_SLABS ranges of whole z-layers, each
    // within the spec's minimum maxStorageBufferRange (gi/voxel_grid.h).
    const VkDeviceSize slabBytes = accumBytes(n, gpu::voxelAccSlabLayers(n));
    if (slabBytes > ctx.properties().limits.maxStorageBufferRange)
        return makeError("voxel grid: resolution " + std::to_string(n) + " binds " + std::to_string(slabBytes >> 20) +
                         " MiB of accumulation records per range, more than the device's maxStorageBufferRange");
    std::unique_ptr<VoxelGrid> g(new VoxelGrid(ctx));
    g->m_params = params;
    struct Named {
        Pipeline* pipeline;
        const char* shader;
    } shaders[] = {{&g->m_voxelize, "gi/voxel/voxelize.comp"},
                   {&g->m_resolve, "gi/voxel/voxel_resolve.comp"},
                   {&g->m_resolveMerge, "gi/voxel/voxel_resolve_merge.comp"},
                   {&g->m_stale, "gi/voxel/voxel_resolve_stale.comp"},
                   {&g->m_touchedList, "gi/voxel/voxel_touched_list.comp"}};
    // Records in slabs (voxel_acc.glsl's kVoxelAccSlabs) only where one range cannot hold them.
    const std::vector<SpecConstant> slabs{{0, gpu::voxelAccSlabLayers(n) < n ? 1u : 0u}};
    for (const Named& s : shaders) {
        auto p = createComputePipeline(ctx, {s.shader, slabs});
        if (!p)
            return p.error();
        *s.pipeline = std::move(*p);
    }
    g->m_volumes = createVolumes(ctx, n, "voxel.grid");
    g->m_static = createVolumes(ctx, n, "voxel.static");
    BufferDesc accum;
    accum.size = accumBytes(n, n);
    accum.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    g->m_accum.buffer = createBuffer(ctx, accum, "voxel.accumulation");
    accum.size = VkDeviceSize(n) * n * n / 8; // one bit per voxel
    g->m_bits.buffer = createBuffer(ctx, accum, "voxel.touched_bits");
    BufferDesc list;
    list.size = VkDeviceSize(GI_VOXEL_TOUCHED_HEADER + n * n * n) * sizeof(uint32_t);
    list.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                 VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    g->m_lists[0].buffer = createBuffer(ctx, list, "voxel.touched.a");
    g->m_lists[1].buffer = createBuffer(ctx, list, "voxel.touched.b");
    g->m_lists[2].buffer = createBuffer(ctx, list, "voxel.touched.dynamic");
    return g;
}

VoxelGrid::~VoxelGrid() {
    for (Pipeline* p : {&m_voxelize, &m_resolve, &m_resolveMerge, &m_stale, &m_touchedList})
        destroyPipeline(m_ctx, *p);
    destroyVolumes(m_ctx, m_volumes);
    destroyVolumes(m_ctx, m_static);
    destroyBuffer(m_ctx, m_accum.buffer);
    destroyBuffer(m_ctx, m_bits.buffer);
    for (rg::PersistentBuffer& b : m_lists)
        destroyBuffer(m_ctx, b.buffer);
}

VkDeviceSize VoxelGrid::bytes() const {
    VkDeviceSize total = m_accum.buffer.desc.size + m_bits.buffer.desc.size;
    for (const rg::PersistentBuffer& b : m_lists)
        total += b.buffer.desc.size;
    for (const VoxelVolumes* v : {&m_volumes, &m_static})
        total += imageBytes(v->albedo.image.desc) + imageBytes(v->normal.image.desc) +
                 imageBytes(v->emission.image.desc) + imageBytes(v->faces.image.desc);
    return total;
}

VoxelizationPlan VoxelGrid::beginVoxelization(VoxelDrawSet set) {
    State& st = m_planned;
    VoxelizationPlan plan;
    plan.clearAccum = !st.accumZero;
    st.accumZero = true; // the resolve (or merge) zeroes every record the voxelization touches
    if (set == VoxelDrawSet::Dynamic) {
        // The grid becomes the static copy plus the merged dynamic voxels: no list covers it.
        plan.next = 2;
        st.cover[0] = -1;
        return plan;
    }
    int target = set == VoxelDrawSet::Static ? 1 : 0;
    plan.previous = st.cover[target];
    // The new list must not be the one whose voxels the stale clear reads.
    plan.next = 1 - (plan.previous >= 0 ? plan.previous : st.current);
    if (st.cover[1 - target] == plan.next)
        st.cover[1 - target] = -1; // that list is overwritten
    st.cover[target] = plan.next;
    st.current = plan.next;
    return plan;
}

void VoxelGrid::recordClear(VkCommandBuffer cmd, VkBuffer list, bool accum) const {
    // Transfer fills stream at memset speed (the first voxelization's N^3 records).
    if (accum) {
        vkCmdFillBuffer(cmd, m_accum.buffer.buffer, 0, VK_WHOLE_SIZE, 0);
        vkCmdFillBuffer(cmd, m_bits.buffer.buffer, 0, VK_WHOLE_SIZE, 0);
    }
    // Header (0, 1, 1, 0): no groups and no voxels yet; dispatch y = z = 1. Disjoint fills.
    vkCmdFillBuffer(cmd, list, 0, sizeof(uint32_t), 0);
    vkCmdFillBuffer(cmd, list, sizeof(uint32_t), 2 * sizeof(uint32_t), 1);
    vkCmdFillBuffer(cmd, list, 3 * sizeof(uint32_t), sizeof(uint32_t), 0);
}

void VoxelGrid::recordClearVolumes(VkCommandBuffer cmd, const VoxelVolumes& target,
                                   const VkImageLayout layouts[4]) const {
    VkClearColorValue zero{};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    const Image* images[] = {&target.albedo.image, &target.normal.image, &target.emission.image, &target.faces.image};
    for (int i = 0; i < 4; ++i)
        vkCmdClearColorImage(cmd, images[i]->image, layouts[i], &zero, 1, &range);
}

void VoxelGrid::recordCopyStatic(VkCommandBuffer cmd, const VkImageLayout src[4], const VkImageLayout dst[4]) const {
    const Image* from[] = {&m_static.albedo.image, &m_static.normal.image, &m_static.emission.image,
                           &m_static.faces.image};
    const Image* to[] = {&m_volumes.albedo.image, &m_volumes.normal.image, &m_volumes.emission.image,
                         &m_volumes.faces.image};
    uint32_t n = resolution();
    VkImageCopy region{};
    region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.extent = {n, n, n};
    for (int i = 0; i < 4; ++i)
        vkCmdCopyImage(cmd, from[i]->image, src[i], to[i]->image, dst[i], 1, &region);
}

void VoxelGrid::recordClearStale(VkCommandBuffer cmd, const VoxelVolumes& target, VkBuffer previous) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_stale.pipeline);
    gpu::VoxelGridPush push{m_params};
    pushConstants(cmd, m_stale, &push, sizeof(push));
    DescriptorItem items[] = {storageBuffer(VOXEL_STALE_BINDING_TOUCHED_BITS, m_bits.buffer.buffer),
                              storageImage(VOXEL_STALE_BINDING_ALBEDO, target.albedo.image),
                              storageImage(VOXEL_STALE_BINDING_NORMAL, target.normal.image),
                              storageImage(VOXEL_STALE_BINDING_EMISSION, target.emission.image),
                              storageImage(VOXEL_STALE_BINDING_FACES, target.faces.image),
                              storageBuffer(VOXEL_STALE_BINDING_PREVIOUS, previous)};
    pushDescriptors(m_ctx, cmd, m_stale, items);
    vkCmdDispatchIndirect(cmd, previous, 0);
}

std::vector<DescriptorItem> VoxelGrid::withRecords(std::span<const DescriptorItem> items) const {
    std::vector<DescriptorItem> all(items.begin(), items.end());
    const uint32_t n = resolution(), layers = gpu::voxelAccSlabLayers(n);
    const VkDeviceSize slab = accumBytes(n, layers);
    for (uint32_t k = 0; k < GI_VOXEL_ACC_SLABS; ++k) // voxel_acc.glsl
        all.push_back(storageBuffer(VOXEL_ACC_BINDING_RECORDS + k, m_accum.buffer.buffer, layers == n ? 0 : k * slab, slab));
    return all;
}

void VoxelGrid::recordVoxelize(VkCommandBuffer cmd, const VoxelSceneBuffers& scene, VoxelDrawSet set) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_voxelize.pipeline);
    DescriptorItem items[] = {storageBuffer(VOXELIZE_BINDING_VERTICES, scene.vertices),
                              storageBuffer(VOXELIZE_BINDING_INDICES, scene.indices),
                              storageBuffer(VOXELIZE_BINDING_INSTANCES, scene.instances),
                              storageBuffer(VOXELIZE_BINDING_MATERIALS, scene.materials),
                              storageBuffer(VOXELIZE_BINDING_TOUCHED_BITS, m_bits.buffer.buffer)};
    pushDescriptors(m_ctx, cmd, m_voxelize, withRecords(items));
    // Row slices per triangle (voxelize.comp), for draws that fit in one work group (one CPU
    // thread otherwise; the Cornell walls): about 8 rows each for a grid-wide triangle. Draws
    // of more triangles already spread over work groups, and their triangles are mostly small:
    // slicing them only repeats each triangle's setup (atrium voxelize 16 -> 24 ms).
    const uint32_t slices = std::max(1u, resolution() / 8u);
    for (const VoxelDraw& d : scene.draws) {
        if (d.triangleCount == 0 || (set == VoxelDrawSet::Static && d.dynamic) ||
            (set == VoxelDrawSet::Dynamic && !d.dynamic))
            continue;
        bool shared = d.triangleCount <= m_voxelize.localSize[0];
        gpu::VoxelizePush push{m_params,
                               glm::uvec4(d.instance, d.firstIndex, d.triangleCount,
                                          std::bit_cast<uint32_t>(d.vertexOffset)),
                               glm::uvec4(shared ? 1u : 0u, 0u, 0u, 0u)};
        pushConstants(cmd, m_voxelize, &push, sizeof(push));
        if (shared)
            vkCmdDispatch(cmd, d.triangleCount, slices, 1);
        else
            vkCmdDispatch(cmd, groupCount(d.triangleCount, m_voxelize.localSize[0]), 1, 1);
    }
}

void VoxelGrid::recordTouchedList(VkCommandBuffer cmd, VkBuffer list) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_touchedList.pipeline);
    gpu::VoxelGridPush push{m_params};
    pushConstants(cmd, m_touchedList, &push, sizeof(push));
    DescriptorItem items[] = {storageBuffer(VOXEL_TOUCHED_BINDING_BITS, m_bits.buffer.buffer),
                              storageBuffer(VOXEL_TOUCHED_BINDING_LIST, list)};
    pushDescriptors(m_ctx, cmd, m_touchedList, items);
    uint32_t n = resolution();
    vkCmdDispatch(cmd, groupCount(n * n * n / 32, m_touchedList.localSize[0]), 1, 1);
}

void VoxelGrid::recordResolve(VkCommandBuffer cmd, const VoxelVolumes& target, VkBuffer list) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_resolve.pipeline);
    gpu::VoxelGridPush push{m_params};
    pushConstants(cmd, m_resolve, &push, sizeof(push));
    DescriptorItem items[] = {storageImage(VOXEL_RESOLVE_BINDING_ALBEDO, target.albedo.image),
                              storageImage(VOXEL_RESOLVE_BINDING_NORMAL, target.normal.image),
                              storageImage(VOXEL_RESOLVE_BINDING_EMISSION, target.emission.image),
                              storageImage(VOXEL_RESOLVE_BINDING_FACES, target.faces.image),
                              storageBuffer(VOXEL_RESOLVE_BINDING_TOUCHED, list)};
    pushDescriptors(m_ctx, cmd, m_resolve, withRecords(items));
    vkCmdDispatchIndirect(cmd, list, 0);
}

void VoxelGrid::recordResolveMerge(VkCommandBuffer cmd) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m_resolveMerge.pipeline);
    gpu::VoxelGridPush push{m_params};
    pushConstants(cmd, m_resolveMerge, &push, sizeof(push));
    VkBuffer list = touched(VoxelDrawSet::Dynamic).buffer;
    DescriptorItem items[] = {storageImage(VOXEL_RESOLVE_BINDING_ALBEDO, m_volumes.albedo.image),
                              storageImage(VOXEL_RESOLVE_BINDING_NORMAL, m_volumes.normal.image),
                              storageImage(VOXEL_RESOLVE_BINDING_EMISSION, m_volumes.emission.image),
                              storageImage(VOXEL_RESOLVE_BINDING_FACES, m_volumes.faces.image),
                              storageImage(VOXEL_RESOLVE_BINDING_STATIC_ALBEDO, m_static.albedo.image),
                              storageBuffer(VOXEL_RESOLVE_BINDING_TOUCHED, list)};
    pushDescriptors(m_ctx, cmd, m_resolveMerge, withRecords(items));
    vkCmdDispatchIndirect(cmd, list, 0);
}

} // namespace vkgi::gi
