#include "vkgi/resources.hpp"

#include <algorithm>
#include <cstring>

#include "vkgi/context.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi {

namespace {
// Block size: large enough that the default module's memory budget (DESIGN.md) needs only a few
// blocks, small enough not to over-reserve on lavapipe's single device heap.
constexpr VkDeviceSize kBlockSize = 64ull << 20;
VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }
// The steps of createBuffer/createImage that may throw after the handle exists.
void bindBufferMemory(Context& ctx, Buffer& b);
void bindImageMemoryAndViews(Context& ctx, Image& img, const char* name);
} // namespace

Allocator::Allocator(Context& ctx) : m_ctx(ctx) {
    vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice(), &m_props);
}

Allocator::~Allocator() {
    for (Block& b : m_blocks)
        if (b.memory)
            vkFreeMemory(m_ctx.device(), b.memory, nullptr);
}

uint32_t Allocator::findType(uint32_t bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const {
    int fallback = -1;
    for (uint32_t i = 0; i < m_props.memoryTypeCount; ++i) {
        if (!(bits & (1u << i)))
            continue;
        VkMemoryPropertyFlags f = m_props.memoryTypes[i].propertyFlags;
        if ((f & required) != required)
            continue;
        if ((f & preferred) == preferred)
            return i;
        if (fallback < 0)
            fallback = int(i);
    }
    VKGI_ASSERT(fallback >= 0, "no Vulkan memory type satisfies the request");
    return uint32_t(fallback);
}

Allocation Allocator::allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                               VkMemoryPropertyFlags preferred) {
    std::lock_guard lock(m_mutex);
    uint32_t type = findType(req.memoryTypeBits, required, preferred);
    VkDeviceSize align = std::max<VkDeviceSize>(req.alignment, m_ctx.properties().limits.bufferImageGranularity);
    for (uint32_t bi = 0; bi < m_blocks.size(); ++bi) {
        Block& b = m_blocks[bi];
        if (!b.memory || b.type != type)
            continue;
        for (size_t i = 0; i < b.freeList.size(); ++i) {
            Range r = b.freeList[i];
            VkDeviceSize start = alignUp(r.offset, align);
            if (start + req.size > r.offset + r.size)
                continue;
            // Split the free range into [r.offset, start) and [start+size, end).
            std::vector<Range> parts;
            if (start > r.offset)
                parts.push_back({r.offset, start - r.offset});
            if (start + req.size < r.offset + r.size)
                parts.push_back({start + req.size, r.offset + r.size - start - req.size});
            b.freeList.erase(b.freeList.begin() + long(i));
            b.freeList.insert(b.freeList.begin() + long(i), parts.begin(), parts.end());
            m_liveBytes += req.size;
            return {b.memory, start, req.size, type, bi, b.mapped ? static_cast<char*>(b.mapped) + start : nullptr};
        }
    }
    Block nb;
    nb.size = std::max(kBlockSize, alignUp(req.size, align));
    nb.type = type;
    VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = nb.size;
    info.memoryTypeIndex = type;
    VKGI_CHECK(vkAllocateMemory(m_ctx.device(), &info, nullptr, &nb.memory));
    if (m_props.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
        if (VkResult r = vkMapMemory(m_ctx.device(), nb.memory, 0, VK_WHOLE_SIZE, 0, &nb.mapped); r != VK_SUCCESS) {
            vkFreeMemory(m_ctx.device(), nb.memory, nullptr);
            throwVulkanError(__FILE__, __LINE__, "vkMapMemory", r);
        }
    }
    if (req.size < nb.size)
        nb.freeList.push_back({req.size, nb.size - req.size});
    m_reservedBytes += nb.size;
    m_liveBytes += req.size;
    m_blocks.push_back(std::move(nb));
    Block& b = m_blocks.back();
    return {b.memory, 0, req.size, type, uint32_t(m_blocks.size() - 1), b.mapped};
}

void Allocator::free(const Allocation& a) {
    if (!a.memory)
        return;
    std::lock_guard lock(m_mutex);
    Block& b = m_blocks[a.block];
    auto it = std::lower_bound(b.freeList.begin(), b.freeList.end(), a.offset,
                               [](const Range& r, VkDeviceSize off) { return r.offset < off; });
    it = b.freeList.insert(it, {a.offset, a.size});
    // Coalesce with the neighbours so the block does not fragment over frames.
    if (it + 1 != b.freeList.end() && it->offset + it->size == (it + 1)->offset) {
        it->size += (it + 1)->size;
        b.freeList.erase(it + 1);
    }
    if (it != b.freeList.begin() && (it - 1)->offset + (it - 1)->size == it->offset) {
        (it - 1)->size += it->size;
        b.freeList.erase(it);
    }
    m_liveBytes -= a.size;
    if (b.freeList.size() == 1 && b.freeList[0].size == b.size) {
        vkFreeMemory(m_ctx.device(), b.memory, nullptr);
        m_reservedBytes -= b.size;
        b = Block{};
    }
}

bool isDepthFormat(VkFormat f) {
    return f == VK_FORMAT_D16_UNORM || f == VK_FORMAT_D32_SFLOAT || f == VK_FORMAT_D24_UNORM_S8_UINT ||
           f == VK_FORMAT_D32_SFLOAT_S8_UINT || f == VK_FORMAT_X8_D24_UNORM_PACK32;
}

VkImageAspectFlags aspectOf(VkFormat f) { return isDepthFormat(f) ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT; }

uint32_t tryFormatBytes(VkFormat f) {
    switch (f) {
    case VK_FORMAT_R8_UNORM:
    case VK_FORMAT_R8_UINT:
        return 1;
    case VK_FORMAT_R16_SFLOAT:
    case VK_FORMAT_R16_UINT:
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_R8G8_UNORM:
        return 2;
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R32_SINT:
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_A2B10G10R10_UNORM_PACK32:
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32:
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R16G16_UNORM:
        return 4;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R16G16B16A16_UINT:
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R32G32_UINT:
        return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT:
        return 16;
    default:
        return 0;
    }
}

uint32_t formatBytes(VkFormat f) {
    uint32_t bytes = tryFormatBytes(f);
    if (bytes == 0)
        fatal(__FILE__, __LINE__, "formatBytes: format not in vkgi's table");
    return bytes;
}

uint32_t mipCount(uint32_t w, uint32_t h, uint32_t d) {
    uint32_t m = std::max({w, h, d}), n = 1;
    while (m > 1) {
        m >>= 1;
        ++n;
    }
    return n;
}

void fullMemoryBarrier(VkCommandBuffer cmd) {
    VkMemoryBarrier2 b{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    b.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    b.srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT;
    b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    b.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &dep);
}

VkDeviceSize imageBytes(const ImageDesc& d) {
    VkDeviceSize total = 0;
    for (uint32_t m = 0; m < d.mipLevels; ++m)
        total += VkDeviceSize(std::max(1u, d.width >> m)) * std::max(1u, d.height >> m) * std::max(1u, d.depth >> m);
    return total * d.arrayLayers * formatBytes(d.format);
}

Buffer createBuffer(Context& ctx, const BufferDesc& desc, const char* name) {
    VKGI_ASSERT(desc.size > 0, "createBuffer: size must be > 0");
    Buffer b;
    b.desc = desc;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = desc.size;
    info.usage = desc.usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VKGI_CHECK(vkCreateBuffer(ctx.device(), &info, nullptr, &b.buffer));
    try {
        bindBufferMemory(ctx, b);
    } catch (...) {
        destroyBuffer(ctx, b); // a failed allocation leaks no buffer
        throw;
    }
    ctx.setName(VK_OBJECT_TYPE_BUFFER, uint64_t(b.buffer), name);
    return b;
}

namespace {

void bindBufferMemory(Context& ctx, Buffer& b) {
    const BufferDesc& desc = b.desc;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device(), b.buffer, &req);
    VkMemoryPropertyFlags required = 0, preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    if (desc.memory == MemoryUsage::CpuToGpu) {
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    } else if (desc.memory == MemoryUsage::GpuToCpu) {
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
    }
    b.alloc = ctx.allocator().allocate(req, required, preferred);
    VKGI_CHECK(vkBindBufferMemory(ctx.device(), b.buffer, b.alloc.memory, b.alloc.offset));
}

VkImageView makeView(Context& ctx, const Image& img, uint32_t baseMip, uint32_t mips) {
    VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    info.image = img.image;
    const ImageDesc& d = img.desc;
    if (d.type == VK_IMAGE_TYPE_3D)
        info.viewType = VK_IMAGE_VIEW_TYPE_3D;
    else if (d.cube)
        info.viewType = d.arrayLayers > 6 ? VK_IMAGE_VIEW_TYPE_CUBE_ARRAY : VK_IMAGE_VIEW_TYPE_CUBE;
    else
        info.viewType = d.arrayLayers > 1 || d.arrayView ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    // Storage writes to a cube go through a 2D-array view of the same mip.
    if (d.cube && mips == 1 && baseMip != ~0u && (d.usage & VK_IMAGE_USAGE_STORAGE_BIT))
        info.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    info.format = d.format;
    info.subresourceRange = {aspectOf(d.format), baseMip, mips, 0, d.arrayLayers};
    VkImageView view;
    VKGI_CHECK(vkCreateImageView(ctx.device(), &info, nullptr, &view));
    return view;
}

// A 2D view of mip 0 of one layer (a render target, or one layer sampled as a plain 2D image).
VkImageView makeLayerView(Context& ctx, const Image& img, uint32_t layer) {
    VkImageViewCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    info.image = img.image;
    info.viewType = VK_IMAGE_VIEW_TYPE_2D;
    info.format = img.desc.format;
    info.subresourceRange = {aspectOf(img.desc.format), 0, 1, layer, 1};
    VkImageView view;
    VKGI_CHECK(vkCreateImageView(ctx.device(), &info, nullptr, &view));
    return view;
}
} // namespace

Image createImage(Context& ctx, const ImageDesc& desc, const char* name) {
    VKGI_ASSERT(desc.width > 0 && desc.height > 0 && desc.depth > 0 && desc.mipLevels > 0 && desc.arrayLayers > 0,
              "createImage: zero extent, mip count or layer count");
    Image img;
    img.desc = desc;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = desc.type;
    info.format = desc.format;
    info.extent = {desc.width, desc.height, desc.depth};
    info.mipLevels = desc.mipLevels;
    info.arrayLayers = desc.arrayLayers;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = desc.usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    info.flags = desc.cube ? VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT : 0;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VKGI_CHECK(vkCreateImage(ctx.device(), &info, nullptr, &img.image));
    try {
        bindImageMemoryAndViews(ctx, img, name);
    } catch (...) {
        destroyImage(ctx, img); // a failed allocation or view leaks no image
        throw;
    }
    return img;
}

namespace {

void bindImageMemoryAndViews(Context& ctx, Image& img, const char* name) {
    const ImageDesc& desc = img.desc;
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device(), img.image, &req);
    img.alloc = ctx.allocator().allocate(req, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VKGI_CHECK(vkBindImageMemory(ctx.device(), img.image, img.alloc.memory, img.alloc.offset));
    ctx.setName(VK_OBJECT_TYPE_IMAGE, uint64_t(img.image), name);
    img.view = makeView(ctx, img, 0, desc.mipLevels);
    for (uint32_t m = 0; m < desc.mipLevels; ++m)
        img.mipViews.push_back(makeView(ctx, img, m, 1));
    if (desc.type == VK_IMAGE_TYPE_2D)
        for (uint32_t l = 0; l < desc.arrayLayers; ++l)
            img.layerViews.push_back(makeLayerView(ctx, img, l));
}

} // namespace

void destroyBuffer(Context& ctx, Buffer& b) {
    if (b.buffer)
        vkDestroyBuffer(ctx.device(), b.buffer, nullptr);
    ctx.allocator().free(b.alloc);
    b = Buffer{};
}

void destroyImage(Context& ctx, Image& img) {
    for (VkImageView v : img.mipViews)
        vkDestroyImageView(ctx.device(), v, nullptr);
    for (VkImageView v : img.layerViews)
        vkDestroyImageView(ctx.device(), v, nullptr);
    if (img.view)
        vkDestroyImageView(ctx.device(), img.view, nullptr);
    if (img.image)
        vkDestroyImage(ctx.device(), img.image, nullptr);
    ctx.allocator().free(img.alloc);
    img = Image{};
}

VkSampler createSampler(Context& ctx, const SamplerDesc& d) {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = d.filter;
    info.mipmapMode = d.mipmap;
    info.addressModeU = info.addressModeV = info.addressModeW = d.address;
    info.borderColor = d.border;
    info.maxLod = VK_LOD_CLAMP_NONE;
    info.compareEnable = d.compare ? VK_TRUE : VK_FALSE;
    info.compareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    VkSampler s;
    VKGI_CHECK(vkCreateSampler(ctx.device(), &info, nullptr, &s));
    return s;
}

namespace {
void imageLayoutBarrier(VkCommandBuffer cmd, const Image& img, VkImageLayout from, VkImageLayout to) {
    // engine-internal immediate transfers only; frame work gets its barriers from the render graph.
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    b.srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT;
    b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    b.dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = img.image;
    b.subresourceRange = {aspectOf(img.desc.format), 0, img.desc.mipLevels, 0, img.desc.arrayLayers};
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = 1;
    dep.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &dep);
}

// A host-visible transfer buffer for one copy, destroyed on every way out (a failed submit
// throws VulkanError through the copy).
class Staging {
public:
    Staging(Context& ctx, VkDeviceSize size, MemoryUsage usage)
        : m_ctx(ctx),
          m_buffer(createBuffer(ctx, {size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, usage},
                                "vkgi.staging")) {}
    ~Staging() { destroyBuffer(m_ctx, m_buffer); }
    Staging(const Staging&) = delete;
    Staging& operator=(const Staging&) = delete;
    VkBuffer buffer() const { return m_buffer.buffer; }
    void* mapped() const { return m_buffer.mapped(); }

private:
    Context& m_ctx;
    Buffer m_buffer;
};
} // namespace

void uploadBuffer(Context& ctx, const Buffer& dst, const void* data, VkDeviceSize size, VkDeviceSize offset) {
    VKGI_ASSERT(offset + size <= dst.desc.size, "uploadBuffer: write past the end of the buffer");
    if (size == 0)
        return;
    Staging s(ctx, size, MemoryUsage::CpuToGpu);
    std::memcpy(s.mapped(), data, size);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        fullMemoryBarrier(cmd); // order after any earlier use of dst in previous submissions
        VkBufferCopy region{0, offset, size};
        vkCmdCopyBuffer(cmd, s.buffer(), dst.buffer, 1, &region);
        fullMemoryBarrier(cmd);
    });
}

std::vector<uint8_t> readbackBuffer(Context& ctx, const Buffer& src) {
    Staging s(ctx, src.desc.size, MemoryUsage::GpuToCpu);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        fullMemoryBarrier(cmd);
        VkBufferCopy region{0, 0, src.desc.size};
        vkCmdCopyBuffer(cmd, src.buffer, s.buffer(), 1, &region);
        fullMemoryBarrier(cmd);
    });
    const auto* p = static_cast<const uint8_t*>(s.mapped());
    return std::vector<uint8_t>(p, p + src.desc.size);
}

namespace {
VkBufferImageCopy mipRegion(const Image& img, uint32_t mip) {
    VkBufferImageCopy r{};
    r.imageSubresource = {aspectOf(img.desc.format), mip, 0, img.desc.arrayLayers};
    r.imageExtent = {std::max(1u, img.desc.width >> mip), std::max(1u, img.desc.height >> mip),
                     std::max(1u, img.desc.depth >> mip)};
    return r;
}
VkDeviceSize mipBytes(const Image& img, uint32_t mip) {
    VkBufferImageCopy r = mipRegion(img, mip);
    return VkDeviceSize(r.imageExtent.width) * r.imageExtent.height * r.imageExtent.depth * img.desc.arrayLayers *
           formatBytes(img.desc.format);
}
} // namespace

void uploadImage(Context& ctx, const Image& dst, const void* data, VkDeviceSize size, VkImageLayout finalLayout) {
    VKGI_ASSERT(size == mipBytes(dst, 0), "uploadImage: data size does not match mip 0 of the image");
    Staging s(ctx, size, MemoryUsage::CpuToGpu);
    std::memcpy(s.mapped(), data, size);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        imageLayoutBarrier(cmd, dst, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkBufferImageCopy r = mipRegion(dst, 0);
        vkCmdCopyBufferToImage(cmd, s.buffer(), dst.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &r);
        imageLayoutBarrier(cmd, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, finalLayout);
    });
}

std::vector<uint8_t> readbackImage(Context& ctx, const Image& src, VkImageLayout currentLayout, uint32_t mip) {
    VKGI_ASSERT(mip < src.desc.mipLevels, "readbackImage: mip level out of range");
    VkDeviceSize size = mipBytes(src, mip);
    Staging s(ctx, size, MemoryUsage::GpuToCpu);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
        imageLayoutBarrier(cmd, src, currentLayout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        VkBufferImageCopy r = mipRegion(src, mip);
        vkCmdCopyImageToBuffer(cmd, src.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, s.buffer(), 1, &r);
        imageLayoutBarrier(cmd, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, currentLayout);
        fullMemoryBarrier(cmd);
    });
    const auto* p = static_cast<const uint8_t*>(s.mapped());
    return std::vector<uint8_t>(p, p + size);
}

TimestampPool::TimestampPool(Context& ctx, uint32_t maxScopes) : m_ctx(ctx), m_max(maxScopes) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2 * maxScopes;
    VKGI_CHECK(vkCreateQueryPool(ctx.device(), &info, nullptr, &m_pool));
}

TimestampPool::~TimestampPool() { vkDestroyQueryPool(m_ctx.device(), m_pool, nullptr); }

void TimestampPool::reset(VkCommandBuffer cmd) {
    vkCmdResetQueryPool(cmd, m_pool, 0, 2 * m_max);
    m_used = 0;
}

uint32_t TimestampPool::begin(VkCommandBuffer cmd) {
    VKGI_ASSERT(m_used < m_max, "TimestampPool: more scopes than the pool was created for");
    uint32_t scope = m_used++;
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, m_pool, 2 * scope);
    return scope;
}

void TimestampPool::end(VkCommandBuffer cmd, uint32_t scope) {
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, m_pool, 2 * scope + 1);
}

std::vector<double> TimestampPool::resolveMs() {
    std::vector<double> ms(m_used, 0.0);
    if (m_used == 0)
        return ms;
    std::vector<uint64_t> ticks(2 * m_used);
    VKGI_CHECK(vkGetQueryPoolResults(m_ctx.device(), m_pool, 0, 2 * m_used, ticks.size() * sizeof(uint64_t),
                                   ticks.data(), sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    for (uint32_t i = 0; i < m_used; ++i)
        ms[i] = double(ticks[2 * i + 1] - ticks[2 * i]) * m_ctx.timestampPeriodNs() * 1e-6;
    return ms;
}

} // namespace vkgi
