#pragma once
// Buffers, images, views and samplers as plain structs with small free functions
// (create/destroy/upload/readback), backed by vkgi's own block allocator. A failed Vulkan call
// (creation, allocation, submit) throws std::runtime_error naming the call and the VkResult, and
// leaks nothing; destroy functions never throw.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace vkgi {

class Context;

struct Allocation {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
    VkDeviceSize size = 0;
    uint32_t memoryType = 0;
    uint32_t block = 0;
    void* mapped = nullptr; // host pointer when the memory type is host-visible
};

// Sub-allocates from fixed-size device-memory blocks (kBlockSize) per memory type (first fit, coalescing free
// list). lavapipe has a single device-local + host-visible type, so this stays tiny; large
// requests get a dedicated block. Tracks live bytes for the memory report.
class Allocator {
public:
    explicit Allocator(Context& ctx);
    ~Allocator();
    Allocation allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                        VkMemoryPropertyFlags preferred);
    void free(const Allocation& a);
    VkDeviceSize liveBytes() const { return m_liveBytes; }
    VkDeviceSize reservedBytes() const { return m_reservedBytes; }

private:
    struct Range {
        VkDeviceSize offset, size;
    };
    struct Block {
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize size = 0;
        uint32_t type = 0;
        void* mapped = nullptr;
        std::vector<Range> freeList; // sorted by offset
    };
    uint32_t findType(uint32_t bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const;
    Context& m_ctx;
    VkPhysicalDeviceMemoryProperties m_props{};
    std::vector<Block> m_blocks;
    VkDeviceSize m_liveBytes = 0;
    VkDeviceSize m_reservedBytes = 0;
    std::mutex m_mutex;
};

enum class MemoryUsage {
    GpuOnly,   // device-local; filled by uploads through a staging buffer when not host-visible
    CpuToGpu,  // host-visible, written by the CPU
    GpuToCpu,  // host-visible (cached if possible), read back by the CPU
};

struct BufferDesc {
    VkDeviceSize size = 0;
    VkBufferUsageFlags usage = 0;
    MemoryUsage memory = MemoryUsage::GpuOnly;
    bool operator==(const BufferDesc&) const = default;
};

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    Allocation alloc;
    BufferDesc desc;
    void* mapped() const { return alloc.mapped; }
    explicit operator bool() const { return buffer != VK_NULL_HANDLE; }
};

struct ImageDesc {
    VkImageType type = VK_IMAGE_TYPE_2D;
    VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    uint32_t width = 1, height = 1, depth = 1;
    uint32_t mipLevels = 1;
    uint32_t arrayLayers = 1;
    bool cube = false; // 2D with 6*n layers, viewed as a cube (array)
    VkImageUsageFlags usage = 0;
    // 2D: the default view is a 2D array even with one layer (for sampler2DArray bindings).
    bool arrayView = false;
    bool operator==(const ImageDesc&) const = default;
};

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;         // all mips and layers
    std::vector<VkImageView> mipViews;         // one per mip level (all layers), for storage writes
    std::vector<VkImageView> layerViews;       // 2D images: one 2D view of mip 0 per layer, for render targets
    Allocation alloc;
    ImageDesc desc;
    explicit operator bool() const { return image != VK_NULL_HANDLE; }
};

bool isDepthFormat(VkFormat format);
VkImageAspectFlags aspectOf(VkFormat format);
uint32_t formatBytes(VkFormat format); // bytes per texel of uncompressed colour/depth formats
uint32_t tryFormatBytes(VkFormat format); // the same, 0 for a format outside vkgi's table (host images)
uint32_t mipCount(uint32_t width, uint32_t height, uint32_t depth);

Buffer createBuffer(Context& ctx, const BufferDesc& desc, const char* name);
Image createImage(Context& ctx, const ImageDesc& desc, const char* name);
void destroyBuffer(Context& ctx, Buffer& buffer);
void destroyImage(Context& ctx, Image& image);
VkDeviceSize imageBytes(const ImageDesc& desc);

struct SamplerDesc {
    VkFilter filter = VK_FILTER_LINEAR;
    VkSamplerMipmapMode mipmap = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    VkSamplerAddressMode address = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkBorderColor border = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;
    bool compare = false; // depth compare (shadow maps), VK_COMPARE_OP_LESS_OR_EQUAL
};
VkSampler createSampler(Context& ctx, const SamplerDesc& desc);

// Every earlier write made visible to every later access: engine-internal immediate transfers
// and GPU tests that record outside the render graph. Frame work gets barriers from the graph.
void fullMemoryBarrier(VkCommandBuffer cmd);

// Immediate (submit + wait) transfers for set-up and tests. Images must be in `layout`, which
// they are left in afterwards. Inside a frame, use render-graph passes instead.
void uploadBuffer(Context& ctx, const Buffer& dst, const void* data, VkDeviceSize size, VkDeviceSize offset = 0);
std::vector<uint8_t> readbackBuffer(Context& ctx, const Buffer& src);
void uploadImage(Context& ctx, const Image& dst, const void* data, VkDeviceSize size, VkImageLayout finalLayout);
// Tightly packed texels of one mip level (all layers / depth slices).
std::vector<uint8_t> readbackImage(Context& ctx, const Image& src, VkImageLayout currentLayout, uint32_t mip = 0);

// GPU timestamps around named scopes; resolved to milliseconds after the submit completed.
class TimestampPool {
public:
    TimestampPool(Context& ctx, uint32_t maxScopes);
    ~TimestampPool();
    TimestampPool(const TimestampPool&) = delete;
    TimestampPool& operator=(const TimestampPool&) = delete;
    void reset(VkCommandBuffer cmd);                    // before the first scope of a frame
    uint32_t begin(VkCommandBuffer cmd);                // returns the scope index
    void end(VkCommandBuffer cmd, uint32_t scope);
    std::vector<double> resolveMs();                    // after the submit finished; one entry per scope
    uint32_t capacity() const { return m_max; }

private:
    Context& m_ctx;
    VkQueryPool m_pool = VK_NULL_HANDLE;
    uint32_t m_max = 0;
    uint32_t m_used = 0;
};

} // namespace vkgi
