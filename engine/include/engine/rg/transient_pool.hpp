#pragma once
// Transient images and buffers reused across frames (kajiya's descriptor-keyed cache): a
// graph asks for a description, gets a free entry with an equal description or a new one.
// Entries keep their last access state, so the next user's first barrier waits on it.
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/resources.hpp"
#include "engine/rg/render_graph.hpp"

namespace vkgi::rg {

class TransientPool {
public:
    explicit TransientPool(Context& ctx);
    ~TransientPool();
    TransientPool(const TransientPool&) = delete;
    TransientPool& operator=(const TransientPool&) = delete;

    // Starts one graph execution: every entry becomes free again, and entries unused for more
    // than kMaxIdleExecutions executions are destroyed.
    void beginGraph();
    // A free entry with exactly this description (created if none); busy until beginGraph().
    PersistentImage& acquireImage(const ImageDesc& desc, const char* name);
    PersistentBuffer& acquireBuffer(const BufferDesc& desc, const char* name);
    // Destroys everything (the device must be idle).
    void clear();

    size_t imageCount() const { return m_images.size(); }
    size_t bufferCount() const { return m_buffers.size(); }
    VkDeviceSize bytes() const; // device memory held by all entries

    // Idle entries may still be read by frames in flight; 8 executions covers two frames in
    // flight with up to four graphs per frame.
    static constexpr uint64_t kMaxIdleExecutions = 8;

private:
    template <typename T> struct Entry {
        T resource;
        uint64_t lastUsed = 0;
        bool busy = false;
    };
    Context& m_ctx;
    std::vector<std::unique_ptr<Entry<PersistentImage>>> m_images;
    std::vector<std::unique_ptr<Entry<PersistentBuffer>>> m_buffers;
    uint64_t m_execution = 0;
};

} // namespace vkgi::rg
