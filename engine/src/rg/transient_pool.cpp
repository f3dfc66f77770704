// Descriptor-keyed transient pool (kajiya's TransientResourceCache) with lifetime-based reuse
// within one execution: resources of equal description whose pass spans do not overlap share
// one entry (aliasing of equal descriptions only; no placed sub-allocation).
#include "vkgi/rg/transient_pool.hpp"

#include <algorithm>

#include "vkgi/context.hpp"

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

template <typename T, typename D, typename Create>
T& TransientPool::acquire(std::vector<std::unique_ptr<Entry<T>>>& entries, const D& desc, const char* name,
                          uint32_t first, uint32_t last, Create create) {
    // Any free equal entry: the graph asks in order of first use, and first-fit colouring of
    // intervals taken by start is optimal, so the choice among free entries does not matter.
    Entry<T>* best = nullptr;
    for (auto& e : entries)
        if (e->freeFrom(first) && create.matches(e->resource, desc)) {
            best = e.get();
            break;
        }
    if (!best) {
        entries.push_back(std::make_unique<Entry<T>>());
        best = entries.back().get();
        try {
            create.make(best->resource, desc, name);
        } catch (...) {
            entries.pop_back(); // a failed creation leaves no empty entry a later graph could match
            throw;
        }
    } else {
        create.rename(best->resource, name);
    }
    best->busy = true;
    best->busyUntil = last;
    best->lastUsed = m_execution;
    return best->resource;
}

PersistentImage& TransientPool::acquireImage(const ImageDesc& desc, const char* name, uint32_t first, uint32_t last) {
    struct {
        Context& ctx;
        bool matches(const PersistentImage& r, const ImageDesc& d) const { return r.image.desc == d; }
        void make(PersistentImage& r, const ImageDesc& d, const char* n) const { r.image = createImage(ctx, d, n); }
        void rename(PersistentImage& r, const char* n) const {
            ctx.setName(VK_OBJECT_TYPE_IMAGE, uint64_t(r.image.image), n);
        }
    } ops{m_ctx};
    return acquire(m_images, desc, name, first, last, ops);
}

PersistentBuffer& TransientPool::acquireBuffer(const BufferDesc& desc, const char* name, uint32_t first,
                                               uint32_t last) {
    struct {
        Context& ctx;
        bool matches(const PersistentBuffer& r, const BufferDesc& d) const { return r.buffer.desc == d; }
        void make(PersistentBuffer& r, const BufferDesc& d, const char* n) const { r.buffer = createBuffer(ctx, d, n); }
        void rename(PersistentBuffer& r, const char* n) const {
            ctx.setName(VK_OBJECT_TYPE_BUFFER, uint64_t(r.buffer.buffer), n);
        }
    } ops{m_ctx};
    return acquire(m_buffers, desc, name, first, last, ops);
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
