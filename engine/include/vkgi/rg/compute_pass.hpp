#pragma once
// One compute dispatch declared, bound and recorded in one expression (kajiya's
// SimpleRenderPass::new_compute(..).read(..).write(..).dispatch(..)):
//
//     rg::ComputePass(graph, "gi.vct.mip[2]", pipeline)
//         .push(push)
//         .read(VCT_MIP_BINDING_SOURCE, volume, rg::SubresourceRange::mip(1))
//         .write(VCT_MIP_BINDING_TARGET, volume, rg::SubresourceRange::mip(2))
//         .dispatch({size, size, size});
//
// Every binding names the shader's set-1 binding (a #define from the shared header) and a
// graph handle; its rg::Access follows from the pipeline's reflected descriptor:
//   sampled image (with a sampler)           -> ComputeSampledRead
//   readonly storage image / buffer / texels -> ComputeStorageRead
//   writeonly storage ...                    -> ComputeStorageWrite (overwrite(): WriteDiscard)
//   other storage ...                        -> ComputeStorageReadWrite
//   uniform buffer                           -> ComputeUniformRead
// read() of a binding the shader may write, write() of a readonly one, a binding the shader
// does not declare, one given twice or one left out, and a pass that is never dispatched are
// errors that RenderGraph::compile() reports with the pass and binding. A write() replaces the
// caller's handle with the new version, so later passes see what this one wrote.
//
// The descriptor of an image binding is the view of its range: one mip's view when the range
// is a single mip, the whole image's view otherwise.
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>

#include <glm/vec3.hpp>

#include "vkgi/pipeline.hpp"
#include "vkgi/rg/render_graph.hpp"

namespace vkgi::rg {

class ComputePass {
public:
    ComputePass(RenderGraph& graph, std::string name, const Pipeline& pipeline);
    ~ComputePass();
    ComputePass(const ComputePass&) = delete;
    ComputePass& operator=(const ComputePass&) = delete;

    // Storage image the shader only reads (readonly).
    ComputePass& read(uint32_t binding, ImageHandle image, SubresourceRange range = {});
    // Sampled image (combined image sampler) with `sampler`.
    ComputePass& sample(uint32_t binding, ImageHandle image, VkSampler sampler, SubresourceRange range = {});
    // Storage image the shader writes; `image` becomes the version this pass produces.
    ComputePass& write(uint32_t binding, ImageHandle& image, SubresourceRange range = {});
    // As write(), declaring that the pass overwrites the whole range (contents before are dropped).
    ComputePass& overwrite(uint32_t binding, ImageHandle& image, SubresourceRange range = {});

    // Storage or uniform buffer, whole.
    ComputePass& read(uint32_t binding, BufferHandle buffer);
    ComputePass& write(uint32_t binding, BufferHandle& buffer);
    ComputePass& overwrite(uint32_t binding, BufferHandle& buffer);
    // Texel-buffer binding through `view`, a view of `buffer` owned by whoever created it.
    ComputePass& readTexels(uint32_t binding, BufferHandle buffer, VkBufferView view);
    ComputePass& writeTexels(uint32_t binding, BufferHandle& buffer, VkBufferView view);

    // A read the dispatch needs without a binding of its own (e.g. contents another binding's
    // shader code depends on through memory the pass does not bind). Rarely needed.
    ComputePass& depend(BufferHandle buffer, Access access);

    // Push constants (size checked against the shader's block when the pass records).
    template <typename T> ComputePass& push(const T& constants) {
        static_assert(std::is_trivially_copyable_v<T>, "push constants are copied bytewise");
        static_assert(sizeof(T) <= 128, "lavapipe allows 128 bytes of push constants");
        setPush(&constants, uint32_t(sizeof(T)));
        return *this;
    }
    // Keeps the pass even if nothing reads what it writes (see PassBuilder::sideEffect).
    ComputePass& sideEffect();

    // Records the pass: `threads` invocations (work groups from the pipeline's local size),
    // explicit work-group counts, or counts read from `args` at `offset` (a
    // VkDispatchIndirectCommand; the pass reads `args` as Access::IndirectRead).
    void dispatch(glm::uvec3 threads);
    void dispatchGroups(glm::uvec3 groups);
    void dispatchIndirect(BufferHandle args, VkDeviceSize offset = 0);

private:
    enum class Kind : uint8_t { StorageImage, SampledImage, Buffer, TexelBuffer };
    struct Binding {
        uint32_t binding = 0;
        Kind kind = Kind::Buffer;
        uint32_t resource = kNone;
        uint32_t viewMip = kAll; // one mip's view, or kAll for the whole image's view
        VkSampler sampler = VK_NULL_HANDLE;
        VkBufferView texels = VK_NULL_HANDLE;
    };
    struct Data;

    const ReflectedBinding* check(uint32_t binding, bool image, const char* what);
    Access storageAccess(const ReflectedBinding& b, bool write, bool discard, uint32_t binding);
    void add(Binding b);
    ComputePass& image(uint32_t binding, ImageHandle& image, SubresourceRange range, bool write, bool discard);
    ComputePass& buffer(uint32_t binding, BufferHandle& buffer, bool write, bool discard, VkBufferView texels);
    void setPush(const void* data, uint32_t size);
    void finish();

    RenderGraph& m_graph;
    uint32_t m_pass;
    PassBuilder m_builder;
    std::shared_ptr<Data> m_data;
    bool m_dispatched = false;
};

} // namespace vkgi::rg
