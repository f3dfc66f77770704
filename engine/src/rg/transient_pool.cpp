// Descriptor-keyed transient pool (kajiya's TransientResourceCache, v1 without aliasing).
#include "engine/rg/transient_pool.hpp"

#include <algorithm>

#include "engine/context.hpp"

namespace vkgi::rg {

TransientPool::TransientPool(Context& ctx) : m_ctx(ctx) {}

TransientPool::~TransientPool() {
    clear();
}

void TransientPool::beginGraph() {
    ++m_execution;
    auto stale = [&](const auto& e) { return m_execution - e->lastUsed > kMaxIdleExecutions; };
    for (auto& e : m_images)
        if (stale(e))
            destroyImage(m_ctx, e->resource.image);
    for (auto& e : m_buffers)
        if (stale(e))
            destroyBuffer(m_ctx, e->resource.buffer);
    std::erase_if(m_images, stale);
    std::erase_if(m_buffers, stale);
    for (auto& e : m_images)
        e->busy = false;
    for (auto& e : m_buffers)
        e->busy = false;
}

PersistentImage& TransientPool::acquireImage(const ImageDesc& desc, const char* name) {
    for (auto& e : m_images)
        if (!e->busy && e->resource.image.desc == desc) {
            e->busy = true;
            e->lastUsed = m_execution;
            m_ctx.setName(VK_OBJECT_TYPE_IMAGE, uint64_t(e->resource.image.image), name);
            return e->resource;
        }
    auto entry = std::make_unique<Entry<PersistentImage>>();
    entry->resource.image = createImage(m_ctx, desc, name);
    entry->busy = true;
    entry->lastUsed = m_execution;
    m_images.push_back(std::move(entry));
    return m_images.back()->resource;
}

PersistentBuffer& TransientPool::acquireBuffer(const BufferDesc& desc, const char* name) {
    for (auto& e : m_buffers)
        if (!e->busy && e->resource.buffer.desc == desc) {
            e->busy = true;
            e->lastUsed = m_execution;
            m_ctx.setName(VK_OBJECT_TYPE_BUFFER, uint64_t(e->resource.buffer.buffer), name);
            return e->resource;
        }
    auto entry = std::make_unique<Entry<PersistentBuffer>>();
    entry->resource.buffer = createBuffer(m_ctx, desc, name);
    entry->busy = true;
    entry->lastUsed = m_execution;
    m_buffers.push_back(std::move(entry));
    return m_buffers.back()->resource;
}

void TransientPool::clear() {
    for (auto& e : m_images)
        destroyImage(m_ctx, e->resource.image);
    for (auto& e : m_buffers)
        destroyBuffer(m_ctx, e->resource.buffer);
    m_images.clear();
    m_buffers.clear();
}

VkDeviceSize TransientPool::bytes() const {
    VkDeviceSize total = 0;
    for (const auto& e : m_images)
        total += e->resource.image.alloc.size;
    for (const auto& e : m_buffers)
        total += e->resource.buffer.alloc.size;
    return total;
}

} // namespace vkgi::rg
