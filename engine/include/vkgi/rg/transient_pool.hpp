#pragma once
// Transient images and buffers reused across frames and within one (kajiya's descriptor-keyed
// cache, with lifetimes): a graph asks for a description and the span of passes [first, last]
// that use it, and gets an entry with an equal description that is free for that span (unused
// in this execution, or busy only until a pass before `first`), or a new one. Entries keep
// their last access state, so the next user's first barrier waits on it; within one execution
// the graph knows the previous occupant's final state itself.
#include <cstdint>
#include <memory>
#include <vector>

#include "vkgi/resources.hpp"
#include "vkgi/rg/render_graph.hpp"

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
    // An entry with exactly this description that is free from pass `first` on (created if
    // none), busy through pass `last` (kAlways: until beginGraph()). Pass numbers increase in
    // execution order within one graph execution.
    static constexpr uint32_t kAlways = ~0u;
    PersistentImage& acquireImage(const ImageDesc& desc, const char* name, uint32_t first = 0, uint32_t last = kAlways);
    PersistentBuffer& acquireBuffer(const BufferDesc& desc, const char* name, uint32_t first = 0,
                                    uint32_t last = kAlways);
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
        uint32_t busyUntil = 0; // last pass of this execution using it (when busy)
        bool freeFrom(uint32_t first) const { return !busy || (busyUntil != kAlways && busyUntil < first); }
    };
    template <typename T, typename D, typename Create>
    T& acquire(std::vector<std::unique_ptr<Entry<T>>>& entries, const D& desc, const char* name, uint32_t first,
               uint32_t last, Create create);
    Context& m_ctx;
    std::vector<std::unique_ptr<Entry<PersistentImage>>> m_images;
    std::vector<std::unique_ptr<Entry<PersistentBuffer>>> m_buffers;
    uint64_t m_execution = 0;
};

} // namespace vkgi::rg
