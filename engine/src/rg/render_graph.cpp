// Declaration side of the render graph: passes, resources, versions, imports and exports.
// Misuse is recorded as an error naming the pass and resource and reported by compile().
#include "vkgi/rg/render_graph.hpp"

#include <algorithm>

namespace vkgi::rg {

using detail::Origin;
using detail::ResourceNode;

namespace {

void addUnique(std::vector<std::pair<uint32_t, uint32_t>>& list, uint32_t resource, uint32_t version) {
    auto item = std::make_pair(resource, version);
    if (std::find(list.begin(), list.end(), item) == list.end())
        list.push_back(item);
}

std::string quoted(const std::string& name) {
    return "'" + name + "'";
}

} // namespace

AccessState stateAfter(Access access) {
    const AccessInfo& info = accessInfo(access);
    AccessState s;
    s.layout = info.layout;
    if (access == Access::None)
        return s;
    s.written = true;
    if (access == Access::Present) {
        // The acquire semaphore may wait at any stage: order the first transition after all of them.
        s.readStages = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        return s;
    }
    if (info.write) {
        s.writeStages = info.stages;
        s.writeAccess = info.access;
    } else {
        s.readStages = info.stages;
        s.readAccess = info.access;
    }
    return s;
}

RenderGraph::~RenderGraph() = default;

uint32_t RenderGraph::beginPass(std::string name) {
    m_isCompiled = false;
    m_passes.push_back({});
    m_passes.back().name = std::move(name) + m_passNameSuffix;
    return uint32_t(m_passes.size() - 1);
}

uint32_t RenderGraph::addResource(ResourceNode node) {
    m_isCompiled = false;
    m_resources.push_back(std::move(node));
    return uint32_t(m_resources.size() - 1);
}

void RenderGraph::addError(std::string message) {
    m_errors.push_back(std::move(message));
}

std::string RenderGraph::passLabel(uint32_t pass) const {
    return pass == kNone ? std::string("<graph>") : "pass " + quoted(m_passes[pass].name);
}

ImageHandle RenderGraph::createImage(std::string name, const ImageDesc& desc) {
    ResourceNode node;
    node.name = std::move(name);
    node.imageDesc = desc;
    if (desc.mipLevels == 0 || desc.arrayLayers == 0)
        addError("render graph: image " + quoted(node.name) + " has zero mip levels or layers");
    return {addResource(std::move(node)), 0};
}

BufferHandle RenderGraph::createBuffer(std::string name, const BufferDesc& desc) {
    ResourceNode node;
    node.name = std::move(name);
    node.image = false;
    node.bufferDesc = desc;
    return {addResource(std::move(node)), 0};
}

ImageHandle RenderGraph::importImage(std::string name, PersistentImage& image) {
    ImageHandle h = createImage(std::move(name), image.image.desc);
    m_resources[h.index].origin = Origin::Persistent;
    m_resources[h.index].persistentImage = &image;
    return h;
}

BufferHandle RenderGraph::importBuffer(std::string name, PersistentBuffer& buffer) {
    BufferHandle h = createBuffer(std::move(name), buffer.buffer.desc);
    m_resources[h.index].origin = Origin::Persistent;
    m_resources[h.index].persistentBuffer = &buffer;
    return h;
}

ImageHandle RenderGraph::importImage(std::string name, const Image& image, Access current) {
    ImageHandle h = createImage(std::move(name), image.desc);
    ResourceNode& node = m_resources[h.index];
    node.origin = Origin::External;
    node.externalImage = image;
    node.externalState = stateAfter(current);
    if (!accessInfo(current).image)
        addError("render graph: image " + quoted(node.name) + " imported in buffer-only state " + toString(current));
    return h;
}

BufferHandle RenderGraph::importBuffer(std::string name, const Buffer& buffer, Access current) {
    BufferHandle h = createBuffer(std::move(name), buffer.desc);
    ResourceNode& node = m_resources[h.index];
    node.origin = Origin::External;
    node.externalBuffer = buffer;
    node.externalState = stateAfter(current);
    node.externalState.layout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (!accessInfo(current).buffer)
        addError("render graph: buffer " + quoted(node.name) + " imported in image-only state " + toString(current));
    return h;
}

void RenderGraph::keepVersion(uint32_t index, uint32_t version, bool image) {
    if (index >= m_resources.size() || m_resources[index].image != image) {
        addError("render graph: markOutput/export of an invalid handle");
        return;
    }
    m_isCompiled = false;
    m_resources[index].keptVersions.push_back(version);
}

void RenderGraph::exportImage(ImageHandle h, Access finalAccess) {
    keepVersion(h.index, h.version, true);
    if (h.index < m_resources.size()) {
        m_resources[h.index].exported = true;
        m_resources[h.index].exportAccess = finalAccess;
        if (!accessInfo(finalAccess).image || accessInfo(finalAccess).write)
            addError("render graph: export of image " + quoted(m_resources[h.index].name) + " to " +
                     toString(finalAccess) + ", which is not a read access valid on images");
    }
}

void RenderGraph::exportBuffer(BufferHandle h, Access finalAccess) {
    keepVersion(h.index, h.version, false);
    if (h.index < m_resources.size()) {
        m_resources[h.index].exported = true;
        m_resources[h.index].exportAccess = finalAccess;
        if (!accessInfo(finalAccess).buffer || accessInfo(finalAccess).write)
            addError("render graph: export of buffer " + quoted(m_resources[h.index].name) + " to " +
                     toString(finalAccess) + ", which is not a read access valid on buffers");
    }
}

void RenderGraph::markOutput(ImageHandle h) {
    keepVersion(h.index, h.version, true);
}
void RenderGraph::markOutput(BufferHandle h) {
    keepVersion(h.index, h.version, false);
}

// Checks kind, access/kind compatibility and range bounds; records an error and returns false.
bool RenderGraph::checkHandle(uint32_t pass, uint32_t index, bool image, Access access, const SubresourceRange& range,
                              const char* what) {
    const char* kind = image ? "image" : "buffer";
    if (index >= m_resources.size() || m_resources[index].image != image) {
        addError(passLabel(pass) + ": " + what + " of an invalid " + kind + " handle");
        return false;
    }
    const ResourceNode& res = m_resources[index];
    const AccessInfo& info = accessInfo(access);
    if (image ? !info.image : !info.buffer) {
        addError(passLabel(pass) + ": access " + info.name + " is not valid on " + kind + " " + quoted(res.name));
        return false;
    }
    if (image && (range.baseMip >= res.mips() || range.baseLayer >= res.layers() ||
                  (range.mipCount != kAll && range.baseMip + range.mipCount > res.mips()) ||
                  (range.layerCount != kAll && range.baseLayer + range.layerCount > res.layers()))) {
        addError(passLabel(pass) + ": subresource range outside image " + quoted(res.name));
        return false;
    }
    bool depth = image && isDepthFormat(res.imageDesc.format);
    if (image && (access == Access::ColorAttachmentWrite || access == Access::ColorAttachmentReadWrite) && depth)
        addError(passLabel(pass) + ": colour attachment access on depth image " + quoted(res.name));
    if (image && (access == Access::DepthAttachmentWrite || access == Access::DepthAttachmentRead) && !depth)
        addError(passLabel(pass) + ": depth attachment access on colour image " + quoted(res.name));
    return true;
}

void RenderGraph::declareRead(uint32_t pass, uint32_t index, uint32_t version, Access access,
                              const SubresourceRange& range) {
    ResourceNode& res = m_resources[index];
    uint32_t latest = uint32_t(res.producers.size() - 1);
    std::string who = passLabel(pass) + " reads " + quoted(res.name) + " v" + std::to_string(version);
    if (version > latest) {
        addError(who + ", a version that is only written later (dependency cycle or foreign handle)");
        return;
    }
    // A pass may read the version it is about to replace (read mip k-1, write mip k).
    bool ownPrevious = version + 1 == latest && res.producers[latest] == pass;
    if (version < latest && !ownPrevious) {
        addError(who + ", but " + passLabel(res.producers[version + 1]) + " already wrote v" +
                 std::to_string(version + 1) + " before it (stale handle)");
        return;
    }
    if (version == 0 && res.origin == Origin::Transient) {
        addError(passLabel(pass) + " reads " + quoted(res.name) + ", which no pass wrote before it");
        return;
    }
    m_passes[pass].uses.push_back({index, version, access, range});
    addUnique(m_passes[pass].reads, index, version);
}

uint32_t RenderGraph::declareWrite(uint32_t pass, uint32_t index, uint32_t version, Access access,
                                   const SubresourceRange& range) {
    ResourceNode& res = m_resources[index];
    uint32_t latest = uint32_t(res.producers.size() - 1);
    if (version + 1 == latest && res.producers[latest] == pass) {
        // Second write of the same resource in one pass (e.g. two mips): same new version.
    } else if (version < latest) {
        addError(passLabel(pass) + " writes " + quoted(res.name) + " v" + std::to_string(version) + ", but " +
                 passLabel(res.producers[version + 1]) + " already wrote that version (two writers of one version)");
        return version;
    } else if (version > latest) {
        addError(passLabel(pass) + " writes " + quoted(res.name) + " v" + std::to_string(version) +
                 ", a version that does not exist yet");
        return version;
    } else {
        res.producers.push_back(pass);
        latest++;
    }
    detail::PassNode& node = m_passes[pass];
    node.uses.push_back({index, latest, access, range});
    addUnique(node.writes, index, latest);
    const AccessInfo& info = accessInfo(access);
    // Unless the write discards, untouched subresources keep the previous version's contents,
    // so that version's producer must stay alive.
    if (!info.discard && res.producers[latest - 1] != kNone)
        addUnique(node.reads, index, latest - 1);
    if (res.origin != Origin::Transient)
        node.sideEffect = true; // writing state that outlives the graph is observable
    return latest;
}

ImageHandle PassBuilder::create(std::string name, const ImageDesc& desc) {
    return m_graph.createImage(std::move(name), desc);
}

BufferHandle PassBuilder::create(std::string name, const BufferDesc& desc) {
    return m_graph.createBuffer(std::move(name), desc);
}

void PassBuilder::read(ImageHandle h, Access access, SubresourceRange range) {
    if (accessInfo(access).write)
        return m_graph.addError(m_graph.passLabel(m_pass) + ": read() with write access " + toString(access));
    if (m_graph.checkHandle(m_pass, h.index, true, access, range, "read"))
        m_graph.declareRead(m_pass, h.index, h.version, access, range);
}

void PassBuilder::read(BufferHandle h, Access access) {
    if (accessInfo(access).write)
        return m_graph.addError(m_graph.passLabel(m_pass) + ": read() with write access " + toString(access));
    if (m_graph.checkHandle(m_pass, h.index, false, access, {}, "read"))
        m_graph.declareRead(m_pass, h.index, h.version, access, {});
}

ImageHandle PassBuilder::write(ImageHandle h, Access access, SubresourceRange range) {
    if (!accessInfo(access).write) {
        m_graph.addError(m_graph.passLabel(m_pass) + ": write() with read access " + toString(access));
        return h;
    }
    if (!m_graph.checkHandle(m_pass, h.index, true, access, range, "write"))
        return h;
    return {h.index, m_graph.declareWrite(m_pass, h.index, h.version, access, range)};
}

BufferHandle PassBuilder::write(BufferHandle h, Access access) {
    if (!accessInfo(access).write) {
        m_graph.addError(m_graph.passLabel(m_pass) + ": write() with read access " + toString(access));
        return h;
    }
    if (!m_graph.checkHandle(m_pass, h.index, false, access, {}, "write"))
        return h;
    return {h.index, m_graph.declareWrite(m_pass, h.index, h.version, access, {})};
}

void PassBuilder::sideEffect() {
    m_graph.m_passes[m_pass].sideEffect = true;
}

std::vector<std::string> RenderGraph::orderedPassNames() const {
    std::vector<std::string> names;
    for (const CompiledPass& p : m_compiled.passes)
        names.push_back(p.name);
    return names;
}

std::vector<std::string> RenderGraph::usedResourceNames(bool persistent) const {
    std::vector<std::string> names;
    std::vector<bool> seen(m_resources.size(), false);
    for (const CompiledPass& p : m_compiled.passes)
        for (const detail::Use& u : m_passes[p.pass].uses) {
            const detail::ResourceNode& res = m_resources[u.resource];
            bool wanted = persistent ? res.origin == detail::Origin::Persistent : res.origin == detail::Origin::Transient;
            if (wanted && !seen[u.resource]) {
                seen[u.resource] = true;
                names.push_back(res.name);
            }
        }
    return names;
}

const std::vector<BarrierInfo>* RenderGraph::barriersBefore(std::string_view pass) const {
    for (const CompiledPass& p : m_compiled.passes)
        if (p.name == pass)
            return &p.barriers;
    return nullptr;
}

} // namespace vkgi::rg
