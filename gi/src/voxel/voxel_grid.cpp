#include "voxel/voxel_grid.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "vkgi/context.hpp"

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
    } shaders[] = {{&g->m_pipelines.voxelize, "gi/voxel/voxelize.comp"},
                   {&g->m_pipelines.resolve, "gi/voxel/voxel_resolve.comp"},
                   {&g->m_pipelines.resolveMerge, "gi/voxel/voxel_resolve_merge.comp"},
                   {&g->m_pipelines.clearStale, "gi/voxel/voxel_resolve_stale.comp"},
                   {&g->m_pipelines.touchedList, "gi/voxel/voxel_touched_list.comp"},
                   {&g->m_pipelines.mark, "gi/voxel/voxel_mark.comp"}};
    // Records in slabs (voxel_acc.glsl's kVoxelAccSlabs) only where one range cannot hold them;
    // the fill's clipping (dims.w, fixed for the grid's life) only in the grids that record it:
    // compiled out, it costs the others nothing.
    const std::vector<SpecConstant> spec{{0, gpu::voxelAccSlabLayers(n) < n ? 1u : 0u},
                                         {1, params.dims.w != 0u ? 1u : 0u}};
    for (const Named& s : shaders) {
        auto p = createComputePipeline(ctx, {s.shader, spec});
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
    list.usage =
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    g->m_lists[0].buffer = createBuffer(ctx, list, "voxel.touched.a");
    g->m_lists[1].buffer = createBuffer(ctx, list, "voxel.touched.b");
    g->m_lists[2].buffer = createBuffer(ctx, list, "voxel.touched.dynamic");
    return g;
}

VoxelGrid::~VoxelGrid() {
    for (Pipeline* p : {&m_pipelines.voxelize, &m_pipelines.resolve, &m_pipelines.resolveMerge, &m_pipelines.clearStale,
                        &m_pipelines.touchedList, &m_pipelines.mark})
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

VkDeviceSize VoxelGrid::accumulationRangeBytes() const {
    return accumBytes(resolution(), gpu::voxelAccSlabLayers(resolution()));
}

VkDeviceSize VoxelGrid::accumulationRangeOffset(uint32_t k) const {
    return gpu::voxelAccSlabLayers(resolution()) == resolution() ? 0 : k * accumulationRangeBytes();
}

} // namespace vkgi::gi
