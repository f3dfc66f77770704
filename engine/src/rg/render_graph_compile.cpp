// compile(): culling (skaarj's reference-count flood fill), usage accumulation and barrier
// derivation from the Access table. Pure data, no Vulkan calls, so unit tests run it.
#include <algorithm>

#include "vkgi/rg/render_graph.hpp"

namespace vkgi::rg {

using detail::Origin;
using detail::PassNode;
using detail::ResourceNode;

namespace {

// What one pass wants of one subresource, merged over all its declared accesses.
struct Wanted {
    VkPipelineStageFlags2 stages = 0;
    VkAccessFlags2 access = 0;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    Access first = Access::None;
    bool write = false;
    bool discard = true; // only if every access to it discards
    bool used = false;
};

constexpr VkAccessFlags2 kWriteBits = VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                                      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
                                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT |
                                      VK_ACCESS_2_HOST_WRITE_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;

std::string quoted(const std::string& name) {
    return "'" + name + "'";
}

SubresourceRange clampRange(const SubresourceRange& r, uint32_t mips, uint32_t layers) {
    return {r.baseMip, r.mipCount == kAll ? mips - r.baseMip : r.mipCount, r.baseLayer,
            r.layerCount == kAll ? layers - r.baseLayer : r.layerCount};
}

bool sameSync(const BarrierInfo& a, const BarrierInfo& b) {
    return a.resource == b.resource && a.srcStages == b.srcStages && a.srcAccess == b.srcAccess &&
           a.dstStages == b.dstStages && a.dstAccess == b.dstAccess && a.oldLayout == b.oldLayout &&
           a.newLayout == b.newLayout && a.firstUse == b.firstUse;
}

// Appends a single-subresource barrier, extending an earlier one of the same resource when the
// sync parameters match and the ranges are adjacent (mips within a layer, then whole layers).
void appendMerged(std::vector<BarrierInfo>& list, BarrierInfo b) {
    for (auto it = list.rbegin(); it != list.rend() && it->resource == b.resource; ++it) {
        if (!sameSync(*it, b))
            continue;
        SubresourceRange& r = it->range;
        if (r.layerCount == 1 && r.baseLayer == b.range.baseLayer && r.baseMip + r.mipCount == b.range.baseMip) {
            r.mipCount += b.range.mipCount;
            return;
        }
        if (r.baseMip == b.range.baseMip && r.mipCount == b.range.mipCount &&
            r.baseLayer + r.layerCount == b.range.baseLayer) {
            r.layerCount += b.range.layerCount;
            return;
        }
    }
    list.push_back(std::move(b));
}

// Moves `s` to the access `w`; fills `b` and returns true when a barrier is needed: writes and
// layout changes wait on every earlier access, reads wait on the last write unless an earlier
// barrier already made it visible to the same stages (read-after-read needs nothing).
bool transition(AccessState& s, const Wanted& w, bool image, bool firstUse, BarrierInfo& b) {
    VkImageLayout newLayout = image ? w.layout : VK_IMAGE_LAYOUT_UNDEFINED;
    bool layoutChange = image && (s.layout != newLayout || (w.discard && s.layout != VK_IMAGE_LAYOUT_UNDEFINED));
    b.oldLayout = w.discard ? VK_IMAGE_LAYOUT_UNDEFINED : s.layout;
    b.newLayout = newLayout;
    b.dstStages = w.stages;
    b.dstAccess = w.access;
    bool needed = false;
    if (w.write || layoutChange) {
        // After reads, an execution dependency is enough (they already saw the last write).
        b.srcStages = s.readStages ? s.readStages : s.writeStages;
        b.srcAccess = s.readStages ? 0 : s.writeAccess;
        needed = layoutChange || b.srcStages != 0 || firstUse;
        // A layout transition is itself a write that later stages must wait on.
        s.writeStages = w.stages;
        s.writeAccess = w.write ? (w.access & kWriteBits) : 0;
        s.readStages = w.write ? 0 : w.stages;
        s.readAccess = w.write ? 0 : w.access;
    } else {
        bool covered = (s.readStages & w.stages) == w.stages && (s.readAccess & w.access) == w.access;
        b.srcStages = s.writeStages;
        b.srcAccess = s.writeAccess;
        needed = (s.writeStages != 0 && !covered) || firstUse;
        s.readStages |= w.stages;
        s.readAccess |= w.access;
    }
    s.layout = newLayout;
    s.written = s.written || w.write;
    return needed;
}

} // namespace

Result<void> RenderGraph::compile() {
    m_compiled = {};
    m_isCompiled = false;
    if (!m_errors.empty()) {
        std::string more = m_errors.size() > 1 ? " (+" + std::to_string(m_errors.size() - 1) + " more)" : "";
        return makeError("render graph: " + m_errors.front() + more);
    }
    cull();
    accumulateUsage();
    if (Result<void> r = checkImportedUsage(); !r)
        return r;
    if (Result<void> r = deriveBarriers(); !r)
        return r;
    m_isCompiled = true;
    return {};
}

// skaarj's algorithm on resource versions: a version's count is its readers (+1 when it is an
// output or export); a pass's count is the versions it produces (+1 for side effects). Versions
// at zero release their producer; a producer at zero is culled and releases what it read.
void RenderGraph::cull() {
    std::vector<std::vector<uint32_t>> refs(m_resources.size());
    for (size_t r = 0; r < m_resources.size(); ++r) {
        refs[r].assign(m_resources[r].producers.size(), 0);
        for (uint32_t v : m_resources[r].keptVersions)
            if (v < refs[r].size())
                refs[r][v]++;
    }
    std::vector<uint32_t> passRefs(m_passes.size());
    for (size_t p = 0; p < m_passes.size(); ++p) {
        m_passes[p].culled = false;
        passRefs[p] = uint32_t(m_passes[p].writes.size()) + (m_passes[p].sideEffect ? 1 : 0);
        for (auto [r, v] : m_passes[p].reads)
            refs[r][v]++;
    }
    std::vector<std::pair<uint32_t, uint32_t>> unused;
    auto cullPass = [&](uint32_t p) {
        m_passes[p].culled = true;
        for (auto [r, v] : m_passes[p].reads)
            if (--refs[r][v] == 0 && m_resources[r].producers[v] != kNone)
                unused.emplace_back(r, v);
    };
    for (uint32_t p = 0; p < m_passes.size(); ++p)
        if (passRefs[p] == 0)
            cullPass(p);
    for (uint32_t r = 0; r < m_resources.size(); ++r)
        for (uint32_t v = 1; v < refs[r].size(); ++v)
            if (refs[r][v] == 0)
                unused.emplace_back(r, v);
    while (!unused.empty()) {
        auto [r, v] = unused.back();
        unused.pop_back();
        uint32_t producer = m_resources[r].producers[v];
        if (!m_passes[producer].culled && --passRefs[producer] == 0)
            cullPass(producer);
    }
    for (const PassNode& p : m_passes)
        if (p.culled)
            m_compiled.culled.push_back(p.name);
}

// Transients get exactly the usage their live accesses need (kajiya); imports keep theirs.
void RenderGraph::accumulateUsage() {
    for (const PassNode& p : m_passes) {
        if (p.culled)
            continue;
        for (const detail::Use& u : p.uses) {
            ResourceNode& res = m_resources[u.resource];
            if (res.origin != Origin::Transient)
                continue;
            const AccessInfo& info = accessInfo(u.access);
            if (res.image)
                res.imageDesc.usage |= info.imageUsage;
            else
                res.bufferDesc.usage |= info.bufferUsage;
        }
    }
}

// Imported resources cannot gain usage bits, so a missing one is an error. Transfer bits are
// skipped: vkgi::createImage adds them to every image without recording them in the desc.
Result<void> RenderGraph::checkImportedUsage() const {
    constexpr VkFlags kTransfer = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    static_assert(kTransfer == (VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT));
    for (const PassNode& p : m_passes) {
        if (p.culled)
            continue;
        for (const detail::Use& u : p.uses) {
            const ResourceNode& res = m_resources[u.resource];
            VkFlags have = res.image ? res.imageDesc.usage : res.bufferDesc.usage;
            const AccessInfo& info = accessInfo(u.access);
            VkFlags need = (res.image ? info.imageUsage : info.bufferUsage) & ~kTransfer;
            if (res.origin != Origin::Transient && have != 0 && (have & need) != need)
                return makeError("render graph: pass " + quoted(p.name) + " uses imported " + quoted(res.name) +
                                 " as " + info.name + ", but it was not created with that usage");
        }
    }
    return {};
}

Result<void> RenderGraph::deriveBarriers() {
    std::vector<std::vector<AccessState>> states(m_resources.size());
    for (size_t r = 0; r < m_resources.size(); ++r) {
        const ResourceNode& res = m_resources[r];
        size_t count = size_t(res.mips()) * res.layers();
        states[r].assign(count, res.origin == Origin::External ? res.externalState : AccessState{});
        if (res.persistentImage && res.persistentImage->state.size() == count)
            states[r] = res.persistentImage->state;
        if (res.persistentBuffer)
            states[r][0] = res.persistentBuffer->state;
    }
    m_firstUser.assign(m_resources.size(), kNone);
    m_lastUser.assign(m_resources.size(), kNone);
    for (uint32_t p = 0; p < m_passes.size(); ++p) {
        if (m_passes[p].culled)
            continue;
        CompiledPass compiled{p, m_passes[p].name, {}};
        if (Result<void> r = derivePassBarriers(p, states, compiled.barriers); !r)
            return r;
        m_compiled.passes.push_back(std::move(compiled));
    }
    deriveFinalBarriers(states);
    m_finalStates = std::move(states);
    return {};
}

Result<void> RenderGraph::derivePassBarriers(uint32_t pass, std::vector<std::vector<AccessState>>& states,
                                             std::vector<BarrierInfo>& out) {
    const PassNode& node = m_passes[pass];
    std::vector<std::pair<uint32_t, std::vector<Wanted>>> wanted; // per resource, per subresource
    for (const detail::Use& u : node.uses) {
        const ResourceNode& res = m_resources[u.resource];
        auto it = std::find_if(wanted.begin(), wanted.end(), [&](auto& w) { return w.first == u.resource; });
        if (it == wanted.end())
            it = wanted.insert(wanted.end(), {u.resource, std::vector<Wanted>(states[u.resource].size())});
        const AccessInfo& info = accessInfo(u.access);
        SubresourceRange range = clampRange(u.range, res.mips(), res.layers());
        for (uint32_t l = range.baseLayer; l < range.baseLayer + range.layerCount; ++l)
            for (uint32_t m = range.baseMip; m < range.baseMip + range.mipCount; ++m) {
                Wanted& w = it->second[l * res.mips() + m];
                if (w.used && res.image && w.layout != info.layout)
                    return makeError("render graph: pass " + quoted(node.name) + " uses mip " + std::to_string(m) +
                                     " layer " + std::to_string(l) + " of " + quoted(res.name) + " as both " +
                                     toString(w.first) + " and " + info.name + ", which need different layouts");
                w.first = w.used ? w.first : u.access;
                w.stages |= info.stages;
                w.access |= info.access;
                w.layout = info.layout;
                w.write = w.write || info.write;
                w.discard = w.discard && info.discard;
                w.used = true;
            }
    }
    for (auto& [r, subs] : wanted) {
        const ResourceNode& res = m_resources[r];
        if (m_firstUser[r] == kNone)
            m_firstUser[r] = pass;
        m_lastUser[r] = pass;
        for (uint32_t i = 0; i < subs.size(); ++i) {
            if (!subs[i].used)
                continue;
            AccessState& s = states[r][i];
            uint32_t mip = i % res.mips(), layer = i / res.mips();
            if (!subs[i].write && !s.written && res.origin == Origin::Transient)
                return makeError("render graph: pass " + quoted(node.name) + " reads mip " + std::to_string(mip) +
                                 " layer " + std::to_string(layer) + " of " + quoted(res.name) +
                                 ", which no pass wrote before it");
            bool firstUse = res.origin == Origin::Transient && s == AccessState{};
            BarrierInfo b{r, res.name, res.image, {mip, 1, layer, 1}};
            b.firstUse = firstUse;
            if (transition(s, subs[i], res.image, firstUse, b))
                appendMerged(out, std::move(b));
        }
    }
    return {};
}

// Exports move resources into their final access after the last pass (present, host read,
// a host renderer's sampled read).
void RenderGraph::deriveFinalBarriers(std::vector<std::vector<AccessState>>& states) {
    for (uint32_t r = 0; r < m_resources.size(); ++r) {
        const ResourceNode& res = m_resources[r];
        if (!res.exported || res.exportAccess == Access::None)
            continue;
        if (res.origin == Origin::Transient && m_firstUser[r] == kNone)
            continue; // never created
        const AccessInfo& info = accessInfo(res.exportAccess);
        Wanted w{info.stages, info.access, info.layout, res.exportAccess, false, false, true};
        for (uint32_t i = 0; i < states[r].size(); ++i) {
            BarrierInfo b{r, res.name, res.image, {i % res.mips(), 1, i / res.mips(), 1}};
            if (transition(states[r][i], w, res.image, false, b))
                appendMerged(m_compiled.finalBarriers, std::move(b));
        }
    }
}

void RenderGraph::storeFinalStates() {
    if (!m_isCompiled)
        return;
    // Transients sharing a pool entry store in the order they used it: the last occupant's
    // states win where it touched the entry, the earlier ones' elsewhere.
    std::vector<uint32_t> order;
    for (uint32_t r = 0; r < m_resources.size(); ++r)
        if (r >= m_boundImages.size() || (!m_boundImages[r] && !m_boundBuffers[r]))
            order.push_back(r);
    order.insert(order.end(), m_transientOrder.begin(), m_transientOrder.end());
    m_replacedImageStates.clear();
    m_replacedBufferStates.clear();
    for (uint32_t r : order) {
        ResourceNode& res = m_resources[r];
        PersistentImage* image = r < m_boundImages.size() && m_boundImages[r] ? m_boundImages[r] : res.persistentImage;
        PersistentBuffer* buffer =
            r < m_boundBuffers.size() && m_boundBuffers[r] ? m_boundBuffers[r] : res.persistentBuffer;
        const std::vector<AccessState>& fin = m_finalStates[r];
        if (image) {
            m_replacedImageStates.emplace_back(image, image->state);
            image->state.resize(fin.size());
            for (size_t i = 0; i < fin.size(); ++i)
                if (!(fin[i] == AccessState{})) // untouched transient subresources keep older state
                    image->state[i] = fin[i];
        }
        if (buffer && !(fin[0] == AccessState{})) {
            m_replacedBufferStates.emplace_back(buffer, buffer->state);
            buffer->state = fin[0];
        }
    }
}

void RenderGraph::discardFinalStates() {
    // Reverse order: a pool entry several transients shared gets its state from before the first.
    for (auto it = m_replacedImageStates.rbegin(); it != m_replacedImageStates.rend(); ++it)
        it->first->state = std::move(it->second);
    for (auto it = m_replacedBufferStates.rbegin(); it != m_replacedBufferStates.rend(); ++it)
        it->first->state = it->second;
    m_replacedImageStates.clear();
    m_replacedBufferStates.clear();
}

} // namespace vkgi::rg
