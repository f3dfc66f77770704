// execute(): binds physical resources (imports, pool entries), records passes with their
// batched barriers inside debug labels and timestamp scopes, then stores final states.
#include <algorithm>

#include "vkgi/context.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::rg {

using detail::Origin;
using detail::ResourceNode;

namespace {

// The union of what earlier users of a pool entry did to `range`: the first use in this graph
// must wait on it, since the same memory may still be in use by the previous graph, or by an
// earlier transient of this graph that shared the entry (`earlier`, its final states; where it
// did not touch a subresource the entry's stored state still applies).
void addPreviousUse(const std::vector<AccessState>& state, const std::vector<AccessState>* earlier, uint32_t mips,
                    const SubresourceRange& range, VkPipelineStageFlags2& stages, VkAccessFlags2& access) {
    for (uint32_t l = range.baseLayer; l < range.baseLayer + range.layerCount; ++l)
        for (uint32_t m = range.baseMip; m < range.baseMip + range.mipCount; ++m) {
            size_t i = size_t(l) * mips + m;
            const AccessState* s = earlier && i < earlier->size() && !((*earlier)[i] == AccessState{}) ? &(*earlier)[i]
                                   : i < state.size()                                                 ? &state[i]
                                                                                                      : nullptr;
            if (!s)
                continue;
            stages |= s->writeStages | s->readStages;
            access |= s->writeAccess;
        }
}

} // namespace

void RenderGraph::execute(VkCommandBuffer cmd, Context& ctx, TransientPool& pool, TimestampPool* timestamps,
                          TimestampScopes scopes) {
    VKGI_ASSERT(m_isCompiled, "RenderGraph::execute: the graph was not compiled successfully");
    acquireTransients(ctx, pool);
    m_timestamps = timestamps;
    m_timedPasses.clear();
    // Scope 0 spans the whole graph, barriers included. A pass's scope opens before its
    // barriers and closes when the next pass's opens. On lavapipe a timestamp is only written
    // when llvmpipe next flushes its command stream (a pipeline barrier or a bottom-of-pipe
    // timestamp does; a dispatch, which runs synchronously, does not), so a scope must be
    // followed by a barrier before the pass's own work: otherwise its begin was stamped after
    // that work and the work was billed to the previous pass's scope. The pass's own barriers
    // serve; a pass without any gets an empty one (pass-timed frames only).
    uint32_t frameScope = 0;
    if (timestamps) {
        timestamps->reset(cmd);
        frameScope = timestamps->begin(cmd);
    }
    constexpr uint32_t kNoScope = ~0u;
    uint32_t open = kNoScope; // scope of the previous pass, closed when the next one opens
    auto closeOpen = [&] {
        if (open != kNoScope)
            timestamps->end(cmd, open);
        open = kNoScope;
    };
    for (const CompiledPass& compiled : m_compiled.passes) {
        const detail::PassNode& node = m_passes[compiled.pass];
        ctx.beginLabel(cmd, node.name.c_str());
        closeOpen();
        // Passes beyond the pool's capacity run untimed rather than failing the frame.
        bool timed =
            timestamps && scopes == TimestampScopes::PerPass && m_timedPasses.size() + 1 < timestamps->capacity();
        if (timed) {
            open = timestamps->begin(cmd);
            m_timedPasses.push_back(compiled.pass);
        }
        if (!recordBarriers(cmd, compiled.barriers) && timed)
            recordFlush(cmd);
        if (node.execute) {
            PassContext passCtx(*this, compiled.pass, cmd, ctx);
            node.execute(passCtx);
        }
        ctx.endLabel(cmd);
    }
    closeOpen();
    recordBarriers(cmd, m_compiled.finalBarriers);
    if (timestamps)
        timestamps->end(cmd, frameScope);
    buildMemoryReport();
    storeFinalStates();
}

// Only transients of live passes are created; everything else binds to what was imported.
// Transients are bound in first-use order with their pass span, so two of equal description
// whose spans do not overlap share one pool entry (an exported transient lives to the end).
void RenderGraph::acquireTransients(Context& ctx, TransientPool& pool) {
    (void)ctx;
    pool.beginGraph();
    size_t n = m_resources.size();
    m_boundImages.assign(n, nullptr);
    m_boundBuffers.assign(n, nullptr);
    m_physImages.assign(n, nullptr);
    m_physBuffers.assign(n, nullptr);
    m_previousOccupant.assign(n, kNone);
    m_transientOrder.clear();
    for (uint32_t r = 0; r < n; ++r) {
        ResourceNode& res = m_resources[r];
        if (res.origin == Origin::Persistent) {
            m_physImages[r] = res.persistentImage ? &res.persistentImage->image : nullptr;
            m_physBuffers[r] = res.persistentBuffer ? &res.persistentBuffer->buffer : nullptr;
        } else if (res.origin == Origin::External) {
            m_physImages[r] = res.image ? &res.externalImage : nullptr;
            m_physBuffers[r] = res.image ? nullptr : &res.externalBuffer;
        } else if (m_firstUser[r] != kNone) {
            m_transientOrder.push_back(r);
        }
    }
    std::stable_sort(m_transientOrder.begin(), m_transientOrder.end(),
                     [&](uint32_t a, uint32_t b) { return m_firstUser[a] < m_firstUser[b]; });
    std::vector<std::pair<const void*, uint32_t>> occupant; // pool entry -> its latest transient
    for (uint32_t r : m_transientOrder) {
        ResourceNode& res = m_resources[r];
        uint32_t last = res.exported ? TransientPool::kAlways : m_lastUser[r];
        const void* entry = nullptr;
        if (res.image) {
            m_boundImages[r] = &pool.acquireImage(res.imageDesc, res.name.c_str(), m_firstUser[r], last);
            m_physImages[r] = &m_boundImages[r]->image;
            entry = m_boundImages[r];
        } else {
            m_boundBuffers[r] = &pool.acquireBuffer(res.bufferDesc, res.name.c_str(), m_firstUser[r], last);
            m_physBuffers[r] = &m_boundBuffers[r]->buffer;
            entry = m_boundBuffers[r];
        }
        auto it = std::find_if(occupant.begin(), occupant.end(), [&](const auto& o) { return o.first == entry; });
        if (it == occupant.end()) {
            occupant.push_back({entry, r});
        } else {
            m_previousOccupant[r] = it->second;
            it->second = r;
        }
    }
}

void RenderGraph::recordFlush(VkCommandBuffer cmd) {
    VkMemoryBarrier2 mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    mb.srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    mb.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.memoryBarrierCount = 1;
    dep.pMemoryBarriers = &mb;
    vkCmdPipelineBarrier2(cmd, &dep);
}

bool RenderGraph::recordBarriers(VkCommandBuffer cmd, const std::vector<BarrierInfo>& barriers) const {
    std::vector<VkImageMemoryBarrier2> images;
    std::vector<VkBufferMemoryBarrier2> buffers;
    for (const BarrierInfo& b : barriers) {
        VkPipelineStageFlags2 srcStages = b.srcStages;
        VkAccessFlags2 srcAccess = b.srcAccess;
        const ResourceNode& res = m_resources[b.resource];
        const uint32_t earlier = b.firstUse ? m_previousOccupant[b.resource] : kNone;
        const std::vector<AccessState>* earlierStates = earlier != kNone ? &m_finalStates[earlier] : nullptr;
        if (b.firstUse && b.image && m_boundImages[b.resource])
            addPreviousUse(m_boundImages[b.resource]->state, earlierStates, res.mips(), b.range, srcStages, srcAccess);
        if (b.firstUse && !b.image && m_boundBuffers[b.resource])
            addPreviousUse({m_boundBuffers[b.resource]->state}, earlierStates, 1, {0, 1, 0, 1}, srcStages, srcAccess);
        if (srcStages == 0 && b.oldLayout == b.newLayout)
            continue; // a first use with nothing before it
        if (b.image) {
            const Image* image = m_physImages[b.resource];
            VkImageMemoryBarrier2 ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
            ib.srcStageMask = srcStages;
            ib.srcAccessMask = srcAccess;
            ib.dstStageMask = b.dstStages;
            ib.dstAccessMask = b.dstAccess;
            ib.oldLayout = b.oldLayout;
            ib.newLayout = b.newLayout;
            ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            ib.image = image->image;
            ib.subresourceRange = {aspectOf(image->desc.format), b.range.baseMip, b.range.mipCount, b.range.baseLayer,
                                   b.range.layerCount};
            images.push_back(ib);
        } else {
            VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
            bb.srcStageMask = srcStages;
            bb.srcAccessMask = srcAccess;
            bb.dstStageMask = b.dstStages;
            bb.dstAccessMask = b.dstAccess;
            bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            bb.buffer = m_physBuffers[b.resource]->buffer;
            bb.size = VK_WHOLE_SIZE;
            buffers.push_back(bb);
        }
    }
    if (images.empty() && buffers.empty())
        return false;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.imageMemoryBarrierCount = uint32_t(images.size());
    dep.pImageMemoryBarriers = images.data();
    dep.bufferMemoryBarrierCount = uint32_t(buffers.size());
    dep.pBufferMemoryBarriers = buffers.data();
    vkCmdPipelineBarrier2(cmd, &dep);
    return true;
}

namespace {

constexpr VkAccessFlags2 kReadBits =
    VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT | VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT |
    VK_ACCESS_2_UNIFORM_READ_BIT | VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT |
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_MEMORY_READ_BIT |
    VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT;

// Bytes of the mips and layers `range` selects in an image described by `d`.
VkDeviceSize rangeBytes(const ImageDesc& d, const SubresourceRange& range) {
    uint32_t layers = d.arrayLayers;
    uint32_t layerCount = range.layerCount == kAll ? layers - std::min(range.baseLayer, layers) : range.layerCount;
    uint32_t mipEnd = range.mipCount == kAll ? d.mipLevels : std::min(d.mipLevels, range.baseMip + range.mipCount);
    VkDeviceSize texels = 0;
    for (uint32_t m = range.baseMip; m < mipEnd; ++m)
        texels += VkDeviceSize(std::max(1u, d.width >> m)) * std::max(1u, d.height >> m) * std::max(1u, d.depth >> m);
    return texels * layerCount * tryFormatBytes(d.format); // 0 for a host format vkgi does not know
}

} // namespace

void RenderGraph::buildMemoryReport() {
    m_memory = {};
    auto bytesOf = [&](uint32_t r) -> VkDeviceSize {
        if (m_boundImages[r])
            return m_boundImages[r]->image.alloc.size;
        return m_boundBuffers[r] ? m_boundBuffers[r]->buffer.alloc.size : 0;
    };
    // A pool entry shared by several transients counts once, at its first occupant.
    auto firstOccupant = [&](uint32_t r) { return m_previousOccupant[r] == kNone; };
    for (uint32_t r = 0; r < m_resources.size(); ++r)
        if ((m_boundImages[r] || m_boundBuffers[r]) && firstOccupant(r)) {
            m_memory.transientBytes += bytesOf(r);
            m_memory.transientCount++;
        } else if (m_boundImages[r] || m_boundBuffers[r]) {
            m_memory.sharedCount++;
        }
    for (const CompiledPass& compiled : m_compiled.passes) {
        PassMemory pm{compiled.name, 0, 0, 0};
        std::vector<uint32_t> seen;
        for (const detail::Use& u : m_passes[compiled.pass].uses) {
            const ResourceNode& res = m_resources[u.resource];
            const AccessInfo& info = accessInfo(u.access);
            VkDeviceSize bytes = res.image ? rangeBytes(res.imageDesc, u.range) : res.bufferDesc.size;
            pm.accessedBytes += bytes * ((info.access & kReadBits ? 1u : 0u) + (info.write ? 1u : 0u));
            if (std::find(seen.begin(), seen.end(), u.resource) != seen.end())
                continue;
            seen.push_back(u.resource);
            pm.touchedBytes += bytesOf(u.resource);
            if (m_firstUser[u.resource] == compiled.pass && (m_boundImages[u.resource] || m_boundBuffers[u.resource]) &&
                firstOccupant(u.resource))
                pm.createdBytes += bytesOf(u.resource);
        }
        m_memory.passes.push_back(pm);
    }
}

std::vector<PassTiming> RenderGraph::timings() const {
    std::vector<PassTiming> out;
    if (!m_timestamps)
        return out;
    std::vector<double> ms = m_timestamps->resolveMs();
    for (size_t i = 0; i < m_timedPasses.size() && i + 1 < ms.size(); ++i)
        out.push_back({m_passes[m_timedPasses[i]].name, ms[i + 1]});
    return out;
}

double RenderGraph::frameMs() const {
    if (!m_timestamps)
        return 0.0;
    std::vector<double> ms = m_timestamps->resolveMs();
    return ms.empty() ? 0.0 : ms[0];
}

} // namespace vkgi::rg
