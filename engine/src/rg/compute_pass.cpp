// ComputePass: the declaration of a compute dispatch's bindings is also its recording, so the
// graph's accesses, the barriers derived from them and the descriptors can never disagree.
#include "vkgi/rg/compute_pass.hpp"

#include <string>
#include <vector>

#include "vkgi/context.hpp"
#include "vk_check.hpp"

namespace vkgi::rg {

struct ComputePass::Data {
    const Pipeline* pipeline = nullptr;
    std::vector<Binding> bindings;
    std::array<uint8_t, 128> push{};
    uint32_t pushSize = 0;
    enum class Mode : uint8_t { Groups, Indirect } mode = Mode::Groups;
    glm::uvec3 groups{0};
    uint32_t args = kNone;
    VkDeviceSize argsOffset = 0;
};

ComputePass::ComputePass(RenderGraph& graph, std::string name, const Pipeline& pipeline)
    : m_graph(graph), m_pass(graph.beginPass(std::move(name))), m_builder(graph, m_pass),
      m_data(std::make_shared<Data>()) {
    m_data->pipeline = &pipeline;
    if (pipeline.bindPoint != VK_PIPELINE_BIND_POINT_COMPUTE)
        m_graph.addError(m_graph.passLabel(m_pass) + ": " + pipeline.name + " is not a compute pipeline");
}

ComputePass::~ComputePass() {
    if (!m_dispatched)
        m_graph.addError(m_graph.passLabel(m_pass) + ": declared but never dispatched");
}

const ReflectedBinding* ComputePass::check(uint32_t binding, bool image, const char* what) {
    const Pipeline& p = *m_data->pipeline;
    const ReflectedBinding* b = p.findBinding(1, binding);
    const std::string where = m_graph.passLabel(m_pass) + ": " + p.name + " binding " + std::to_string(binding);
    if (!b) {
        m_graph.addError(where + " is not in the shader's set 1");
        return nullptr;
    }
    for (const Binding& given : m_data->bindings)
        if (given.binding == binding) {
            m_graph.addError(where + " is bound twice");
            return nullptr;
        }
    const bool isImage = b->type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE ||
                         b->type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER ||
                         b->type == VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    if (isImage != image) {
        m_graph.addError(where + " ('" + b->name + "') is " + (isImage ? "an image" : "a buffer") + ", given " + what);
        return nullptr;
    }
    return b;
}

Access ComputePass::storageAccess(const ReflectedBinding& b, bool write, bool discard, uint32_t binding) {
    const std::string where = m_graph.passLabel(m_pass) + ": " + m_data->pipeline->name + " binding " +
                              std::to_string(binding) + " ('" + b.name + "')";
    if (b.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER || b.type == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER) {
        if (write)
            m_graph.addError(where + " is a uniform binding and cannot be written");
        return Access::ComputeUniformRead;
    }
    if (!write) {
        if (b.writable)
            m_graph.addError(where + " is read with read() but the shader may write it: declare it readonly "
                                     "in the shader, or bind it with write()");
        return Access::ComputeStorageRead;
    }
    if (!b.writable) {
        m_graph.addError(where + " is readonly in the shader but bound with write()");
        return Access::ComputeStorageRead;
    }
    if (discard)
        return Access::ComputeStorageWriteDiscard;
    return b.readable ? Access::ComputeStorageReadWrite : Access::ComputeStorageWrite;
}

ComputePass& ComputePass::image(uint32_t binding, ImageHandle& image, SubresourceRange range, bool write,
                                bool discard) {
    const ReflectedBinding* b = check(binding, true, "an image");
    if (!b)
        return *this;
    if (b->type != VK_DESCRIPTOR_TYPE_STORAGE_IMAGE) {
        m_graph.addError(m_graph.passLabel(m_pass) + ": " + m_data->pipeline->name + " binding " +
                         std::to_string(binding) + " ('" + b->name + "') is sampled: bind it with sample()");
        return *this;
    }
    const Access access = storageAccess(*b, write, discard, binding);
    if (write)
        image = m_builder.write(image, access, range);
    else
        m_builder.read(image, access, range);
    add({binding, Kind::StorageImage, image.index, range.mipCount == 1 ? range.baseMip : kAll});
    return *this;
}

ComputePass& ComputePass::read(uint32_t binding, ImageHandle image, SubresourceRange range) {
    return this->image(binding, image, range, false, false);
}

ComputePass& ComputePass::write(uint32_t binding, ImageHandle& image, SubresourceRange range) {
    return this->image(binding, image, range, true, false);
}

ComputePass& ComputePass::overwrite(uint32_t binding, ImageHandle& image, SubresourceRange range) {
    return this->image(binding, image, range, true, true);
}

ComputePass& ComputePass::sample(uint32_t binding, ImageHandle image, VkSampler sampler, SubresourceRange range) {
    const ReflectedBinding* b = check(binding, true, "an image");
    if (!b)
        return *this;
    if (b->type != VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER) {
        m_graph.addError(m_graph.passLabel(m_pass) + ": " + m_data->pipeline->name + " binding " +
                         std::to_string(binding) + " ('" + b->name + "') is not a combined image sampler");
        return *this;
    }
    m_builder.read(image, Access::ComputeSampledRead, range);
    Binding given{binding, Kind::SampledImage, image.index, range.mipCount == 1 ? range.baseMip : kAll};
    given.sampler = sampler;
    add(given);
    return *this;
}

ComputePass& ComputePass::buffer(uint32_t binding, BufferHandle& buffer, bool write, bool discard,
                                 VkBufferView texels) {
    const ReflectedBinding* b = check(binding, false, "a buffer");
    if (!b)
        return *this;
    const bool texelBinding =
        b->type == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER || b->type == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    if (texelBinding != (texels != VK_NULL_HANDLE)) {
        m_graph.addError(m_graph.passLabel(m_pass) + ": " + m_data->pipeline->name + " binding " +
                         std::to_string(binding) + " ('" + b->name + "') " +
                         (texelBinding ? "is a texel buffer: bind it with readTexels()/writeTexels()"
                                       : "is not a texel buffer"));
        return *this;
    }
    const Access access = storageAccess(*b, write, discard, binding);
    if (write)
        buffer = m_builder.write(buffer, access);
    else
        m_builder.read(buffer, access);
    Binding given{binding, texelBinding ? Kind::TexelBuffer : Kind::Buffer, buffer.index};
    given.texels = texels;
    add(given);
    return *this;
}

ComputePass& ComputePass::read(uint32_t binding, BufferHandle buffer) {
    return this->buffer(binding, buffer, false, false, VK_NULL_HANDLE);
}

ComputePass& ComputePass::write(uint32_t binding, BufferHandle& buffer) {
    return this->buffer(binding, buffer, true, false, VK_NULL_HANDLE);
}

ComputePass& ComputePass::overwrite(uint32_t binding, BufferHandle& buffer) {
    return this->buffer(binding, buffer, true, true, VK_NULL_HANDLE);
}

ComputePass& ComputePass::readTexels(uint32_t binding, BufferHandle buffer, VkBufferView view) {
    return this->buffer(binding, buffer, false, false, view);
}

ComputePass& ComputePass::writeTexels(uint32_t binding, BufferHandle& buffer, VkBufferView view) {
    return this->buffer(binding, buffer, true, false, view);
}

ComputePass& ComputePass::depend(BufferHandle buffer, Access access) {
    if (accessInfo(access).write)
        m_graph.addError(m_graph.passLabel(m_pass) + ": depend() takes read accesses only, got " + toString(access));
    else
        m_builder.read(buffer, access);
    return *this;
}

ComputePass& ComputePass::sideEffect() {
    m_builder.sideEffect();
    return *this;
}

void ComputePass::add(Binding b) {
    m_data->bindings.push_back(b);
}

void ComputePass::setPush(const void* data, uint32_t size) {
    std::memcpy(m_data->push.data(), data, size);
    m_data->pushSize = size;
}

void ComputePass::dispatch(glm::uvec3 threads) {
    dispatchGroups(PassContext::groupsFor(*m_data->pipeline, threads));
}

void ComputePass::dispatchGroups(glm::uvec3 groups) {
    m_data->mode = Data::Mode::Groups;
    m_data->groups = groups;
    finish();
}

void ComputePass::dispatchIndirect(BufferHandle args, VkDeviceSize offset) {
    m_builder.read(args, Access::IndirectRead);
    m_data->mode = Data::Mode::Indirect;
    m_data->args = args.index;
    m_data->argsOffset = offset;
    finish();
}

void ComputePass::finish() {
    if (m_dispatched) {
        m_graph.addError(m_graph.passLabel(m_pass) + ": dispatched twice");
        return;
    }
    m_dispatched = true;
    const Pipeline& p = *m_data->pipeline;
    if (m_data->pushSize != p.pushConstantSize)
        m_graph.addError(m_graph.passLabel(m_pass) + ": " + p.name + " expects " + std::to_string(p.pushConstantSize) +
                         " bytes of push constants, given " + std::to_string(m_data->pushSize));
    size_t declared = 0;
    for (const ReflectedBinding& b : p.bindings)
        declared += b.set == 1 ? 1 : 0;
    if (declared != m_data->bindings.size())
        for (const ReflectedBinding& b : p.bindings) {
            if (b.set != 1)
                continue;
            bool given = false;
            for (const Binding& g : m_data->bindings)
                given = given || g.binding == b.binding;
            if (!given)
                m_graph.addError(m_graph.passLabel(m_pass) + ": " + p.name + " binding " + std::to_string(b.binding) +
                                 " ('" + b.name + "') is not bound");
        }
    const Data* data = m_data.get();
    m_graph.setExecute(m_pass, [data](PassContext& ctx) {
        std::vector<DescriptorItem> items;
        items.reserve(data->bindings.size());
        for (const Binding& b : data->bindings) {
            DescriptorItem item;
            item.binding = b.binding;
            switch (b.kind) {
            case Kind::StorageImage:
            case Kind::SampledImage: {
                const ImageHandle h{b.resource, 0};
                const VkImageView view = b.viewMip == kAll ? ctx.view(h) : ctx.mipView(h, b.viewMip);
                item.image = {b.sampler, view, ctx.layout(h, b.viewMip == kAll ? 0 : b.viewMip)};
                break;
            }
            case Kind::Buffer:
                item.buffer = {ctx.buffer(BufferHandle{b.resource, 0}).buffer, 0, VK_WHOLE_SIZE};
                break;
            case Kind::TexelBuffer:
                item.texelBuffer = b.texels;
                break;
            }
            items.push_back(item);
        }
        const std::span<const DescriptorItem> span(items);
        if (data->mode == Data::Mode::Indirect)
            ctx.dispatchIndirect(*data->pipeline, BufferHandle{data->args, 0}, data->argsOffset, data->push.data(),
                                 data->pushSize, span);
        else
            ctx.dispatch(*data->pipeline, data->groups, data->push.data(), data->pushSize, span);
    });
    m_graph.m_passes[m_pass].data = m_data;
}

} // namespace vkgi::rg
