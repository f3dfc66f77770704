#pragma once
// vkgi's render graph (namespace vkgi::rg). A pass is two callbacks: `setup(PassBuilder&)` runs
// at once and declares every access with an rg::Access; `execute(PassContext&)` records later.
// compile() works without a Vulkan device (validation, culling, ordering and barrier derivation
// are plain data), so unit tests cover it; execute() creates transients from a TransientPool,
// inserts the derived barriers, and wraps each pass in a debug label and a timestamp scope.
// execute() throws std::runtime_error naming the Vulkan call and the VkResult when creating a
// transient fails; compile() errors are Result errors.
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <iosfwd>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

#include "vkgi/pipeline.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/result.hpp"
#include "vkgi/rg/access.hpp"

namespace vkgi {
class Context;
class TimestampPool;
} // namespace vkgi

namespace vkgi::rg {

constexpr uint32_t kAll = ~0u;  // "all remaining" mips or layers in a SubresourceRange
constexpr uint32_t kNone = ~0u; // no pass / no resource
// Capture limit of execute callbacks (skaarj): big captures mean the pass should own its data
// through addPass<Data> instead of copying it into every std::function.
constexpr size_t kMaxExecuteCapture = 1024;

// Mips [baseMip, baseMip + mipCount) of layers [baseLayer, baseLayer + layerCount).
struct SubresourceRange {
    uint32_t baseMip = 0;
    uint32_t mipCount = kAll;
    uint32_t baseLayer = 0;
    uint32_t layerCount = kAll;
    static SubresourceRange mip(uint32_t level) { return {level, 1, 0, kAll}; }
    bool operator==(const SubresourceRange&) const = default;
};

// Versioned handles: every write returns a new version, and only the newest may be written.
struct ImageHandle {
    uint32_t index = kNone;
    uint32_t version = 0;
    bool valid() const { return index != kNone; }
    bool operator==(const ImageHandle&) const = default;
};
struct BufferHandle {
    uint32_t index = kNone;
    uint32_t version = 0;
    bool valid() const { return index != kNone; }
    bool operator==(const BufferHandle&) const = default;
};

// Synchronisation state of one subresource (or of a whole buffer) between accesses.
struct AccessState {
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkPipelineStageFlags2 writeStages = 0; // last write (or layout transition) later accesses must wait on
    VkAccessFlags2 writeAccess = 0;        // its memory accesses, to be made visible
    VkPipelineStageFlags2 readStages = 0;  // reads since then; a later write waits on them
    VkAccessFlags2 readAccess = 0;         // read accesses that already saw the last write
    bool written = false;                  // contents defined (reading undefined transients is an error)
    bool operator==(const AccessState&) const = default;
};

// State a resource is in when it enters the graph as an external import with a known access.
AccessState stateAfter(Access access);

// A resource that lives across frames (voxel grid, history). The graph reads its state on
// import and writes the final state back after execute, so next frame's barriers are right.
// `state` has one entry per (layer, mip), index layer * mipLevels + mip; empty = undefined.
struct PersistentImage {
    Image image;
    std::vector<AccessState> state;
};
struct PersistentBuffer {
    Buffer buffer;
    AccessState state;
};

// One derived barrier (image when `image`, otherwise buffer; range unused for buffers).
struct BarrierInfo {
    uint32_t resource = kNone;
    std::string resourceName;
    bool image = true;
    SubresourceRange range;
    VkPipelineStageFlags2 srcStages = 0;
    VkAccessFlags2 srcAccess = 0;
    VkPipelineStageFlags2 dstStages = 0;
    VkAccessFlags2 dstAccess = 0;
    VkImageLayout oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImageLayout newLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    // First use of a transient in this graph: execute() adds the pool entry's previous-frame
    // accesses to the source scope, since the memory may have been used by an earlier graph.
    bool firstUse = false;
};

struct CompiledPass {
    uint32_t pass = kNone;
    std::string name;
    std::vector<BarrierInfo> barriers; // issued as one vkCmdPipelineBarrier2 before the pass
};

struct CompiledGraph {
    std::vector<CompiledPass> passes;       // execution order (declaration order minus culled passes)
    std::vector<std::string> culled;        // culled pass names, declaration order
    std::vector<BarrierInfo> finalBarriers; // export transitions after the last pass
};

struct PassTiming {
    std::string name;
    double ms = 0.0;
};

struct PassMemory {
    std::string name;
    // Transients first used by this pass that take a pool entry no earlier transient of this
    // execution used (a transient reusing an entry freed earlier in the frame adds nothing).
    VkDeviceSize createdBytes = 0;
    VkDeviceSize touchedBytes = 0; // all transients this pass declares
    // Bytes the pass's declared accesses move, imports included: each declared subresource range
    // counted once if read and once if written (read-modify-write twice). Exact for streaming
    // passes (clears, copies, mips, propagation); an upper bound for gathers that sample sparsely.
    VkDeviceSize accessedBytes = 0;
};
struct MemoryReport {
    std::vector<PassMemory> passes;
    // Pool entries bound this execution: transients of equal description whose pass spans do not
    // overlap share one entry, so this is the sum over distinct entries.
    VkDeviceSize transientBytes = 0;
    uint32_t transientCount = 0; // distinct pool entries
    uint32_t sharedCount = 0;    // transients that reused an entry an earlier transient freed
};

class RenderGraph;
class TransientPool;
class PassContext;
class ComputePass;

namespace detail {
struct Use {
    uint32_t resource = kNone;
    uint32_t version = 0; // version read, or version produced by a write
    Access access = Access::None;
    SubresourceRange range;
};
struct PassNode {
    std::string name;
    std::vector<Use> uses;
    std::vector<std::pair<uint32_t, uint32_t>> reads;  // distinct (resource, version) read, incl. implicit
    std::vector<std::pair<uint32_t, uint32_t>> writes; // distinct (resource, version) produced
    std::function<void(PassContext&)> execute;
    std::shared_ptr<void> data;
    bool sideEffect = false;
    bool culled = false;
};
enum class Origin : uint8_t { Transient, Persistent, External };
struct ResourceNode {
    std::string name;
    bool image = true;
    Origin origin = Origin::Transient;
    ImageDesc imageDesc;
    BufferDesc bufferDesc;
    PersistentImage* persistentImage = nullptr;
    PersistentBuffer* persistentBuffer = nullptr;
    Image externalImage;
    Buffer externalBuffer;
    AccessState externalState;
    std::vector<uint32_t> producers{kNone}; // producing pass per version; version 0 has none
    std::vector<uint32_t> keptVersions;     // marked outputs / exports
    bool exported = false;
    Access exportAccess = Access::None;
    uint32_t mips() const { return image ? imageDesc.mipLevels : 1; }
    uint32_t layers() const { return image ? imageDesc.arrayLayers : 1; }
};
} // namespace detail

// Declares what a pass touches. Every method records errors on the graph instead of failing,
// so compile() reports the first problem with the pass and resource names.
class PassBuilder {
public:
    // A transient (version 0, no contents yet); usage flags are added from the declared accesses.
    ImageHandle create(std::string name, const ImageDesc& desc);
    BufferHandle create(std::string name, const BufferDesc& desc);
    // Reads `h` (mips/layers of `range`); read-only accesses only.
    void read(ImageHandle h, Access access, SubresourceRange range = {});
    void read(BufferHandle h, Access access);
    // Writes `h` and returns its next version; `h` must be the newest version (one writer each).
    [[nodiscard]] ImageHandle write(ImageHandle h, Access access, SubresourceRange range = {});
    [[nodiscard]] BufferHandle write(BufferHandle h, Access access);
    // Keeps the pass even if nothing reads its outputs (readbacks, debug dumps).
    void sideEffect();

private:
    friend class RenderGraph;
    friend class ComputePass;
    PassBuilder(RenderGraph& graph, uint32_t pass) : m_graph(graph), m_pass(pass) {}
    RenderGraph& m_graph;
    uint32_t m_pass;
};

// What execute callbacks see: the command buffer, physical resources of declared handles, and
// descriptor helpers whose image layouts follow from the accesses this pass declared. Lookups
// use the resource, not the version, so an execute lambda may capture a handle by value before
// setup() renamed it (the usual `[=]` capture of a handle that setup overwrites).
class PassContext {
public:
    VkCommandBuffer cmd() const { return m_cmd; }
    Context& context() const { return m_ctx; }
    const Image& image(ImageHandle h) const;
    const Buffer& buffer(BufferHandle h) const;
    VkImageView view(ImageHandle h) const { return image(h).view; }
    VkImageView mipView(ImageHandle h, uint32_t mip) const;
    // A 2D view of mip 0 of array layer `layer` of a 2D (or cube) image: a render target for one
    // layer. The image owns the view; the pass must have declared a use covering that layer.
    VkImageView layerView(ImageHandle h, uint32_t layer) const;
    // Layout this pass declared for mip `mip` (layer 0) of `h`.
    VkImageLayout layout(ImageHandle h, uint32_t mip = 0) const;

    // Storage image binding of one mip (or the whole image with kAll).
    DescriptorItem storage(uint32_t binding, ImageHandle h, uint32_t mip = kAll) const;
    // Combined image sampler of one mip (or the whole image with kAll).
    DescriptorItem sampled(uint32_t binding, ImageHandle h, VkSampler sampler, uint32_t mip = kAll) const;
    // Storage or uniform buffer binding (the whole buffer).
    DescriptorItem buffer(uint32_t binding, BufferHandle h) const;

    // Binds `pipeline`, pushes set 1 and the push constants, and dispatches `groups`.
    template <typename T>
    void dispatch(const Pipeline& pipeline, glm::uvec3 groups, const T& pushConstants,
                  std::initializer_list<DescriptorItem> items) const {
        static_assert(std::is_trivially_copyable_v<T>, "push constants are copied bytewise");
        static_assert(sizeof(T) <= 128, "lavapipe allows 128 bytes of push constants");
        dispatchRaw(pipeline, groups, &pushConstants, uint32_t(sizeof(T)), items);
    }
    void dispatch(const Pipeline& pipeline, glm::uvec3 groups, std::initializer_list<DescriptorItem> items) const {
        dispatchRaw(pipeline, groups, nullptr, 0, items);
    }
    // The same with push constants as bytes and any number of descriptors.
    void dispatch(const Pipeline& pipeline, glm::uvec3 groups, const void* push, uint32_t pushSize,
                  std::span<const DescriptorItem> items) const;
    // As dispatch(), with the work-group counts read from `args` at `offset` (a
    // VkDispatchIndirectCommand); the pass must have declared Access::IndirectRead of `args`.
    void dispatchIndirect(const Pipeline& pipeline, BufferHandle args, VkDeviceSize offset, const void* push,
                          uint32_t pushSize, std::span<const DescriptorItem> items) const;
    // Binds the graph's frame set (RenderGraph::setFrameSet) as set 0 of `pipeline`.
    void bindFrameSet(const Pipeline& pipeline) const;
    // Work groups covering `threads` invocations with the pipeline's local size.
    static glm::uvec3 groupsFor(const Pipeline& pipeline, glm::uvec3 threads);

private:
    friend class RenderGraph;
    PassContext(const RenderGraph& graph, uint32_t pass, VkCommandBuffer cmd, Context& ctx)
        : m_graph(graph), m_pass(pass), m_cmd(cmd), m_ctx(ctx) {}
    void dispatchRaw(const Pipeline& pipeline, glm::uvec3 groups, const void* push, uint32_t pushSize,
                     std::initializer_list<DescriptorItem> items) const;
    void bindForDispatch(const Pipeline& pipeline, const void* push, uint32_t pushSize,
                         std::span<const DescriptorItem> items) const;
    const detail::Use* findUse(uint32_t resource, uint32_t mip, uint32_t layer = kAll) const;
    const RenderGraph& m_graph;
    uint32_t m_pass;
    VkCommandBuffer m_cmd;
    Context& m_ctx;
};

// What execute() times. A pass scope is not free: on lavapipe writing a timestamp makes llvmpipe
// synchronise its threads, so every pass scope adds to the frame it measures, and a frame time
// without the profile's cost needs FrameOnly.
enum class TimestampScopes {
    PerPass,   // the frame and every executed pass (timings() lists them)
    FrameOnly, // the frame only (frameMs(); timings() is empty)
};

class RenderGraph {
public:
    RenderGraph() = default;
    ~RenderGraph();
    RenderGraph(const RenderGraph&) = delete;
    RenderGraph& operator=(const RenderGraph&) = delete;

    // Appended to the name of every pass added from now on (until set again): a module that adds
    // the same passes once per instance (VCT's clipmap levels) keeps their names apart.
    void setPassNameSuffix(std::string suffix) { m_passNameSuffix = std::move(suffix); }
    const std::string& passNameSuffix() const { return m_passNameSuffix; }

    // Adds a pass: `setup(PassBuilder&)` runs now; `execute(PassContext&)` is stored and runs in
    // execute() unless the pass is culled. Captures are copied; keep them small.
    template <typename Setup, typename Execute>
    requires std::is_invocable_v<Setup, PassBuilder&> && std::is_invocable_v<Execute, PassContext&>
    void addPass(std::string name, Setup&& setup, Execute&& execute) {
        static_assert(sizeof(std::decay_t<Execute>) <= kMaxExecuteCapture,
                      "execute capture too large; use addPass<Data>");
        uint32_t pass = beginPass(std::move(name));
        PassBuilder builder(*this, pass);
        setup(builder);
        setExecute(pass, std::forward<Execute>(execute));
    }

    // Typed pass (Frostbite style): `setup(PassBuilder&, Data&)` fills Data, which the graph owns;
    // `execute(const Data&, PassContext&)`. Returns Data so later passes can use its handles.
    template <typename Data, typename Setup, typename Execute>
    requires std::is_invocable_v<Setup, PassBuilder&, Data&> && std::is_invocable_v<Execute, const Data&, PassContext&>
    const Data& addPass(std::string name, Setup&& setup, Execute&& execute) {
        static_assert(sizeof(std::decay_t<Execute>) <= kMaxExecuteCapture, "execute capture too large");
        uint32_t pass = beginPass(std::move(name));
        auto data = std::make_shared<Data>();
        PassBuilder builder(*this, pass);
        setup(builder, *data);
        const Data* raw = data.get();
        setExecute(pass, [raw, fn = std::forward<Execute>(execute)](PassContext& ctx) { fn(*raw, ctx); });
        m_passes[pass].data = std::move(data);
        return *raw;
    }

    // Transients created outside any pass (same as PassBuilder::create).
    ImageHandle createImage(std::string name, const ImageDesc& desc);
    BufferHandle createBuffer(std::string name, const BufferDesc& desc);
    // Persistent resources: state read now, final state stored back by execute().
    ImageHandle importImage(std::string name, PersistentImage& image);
    BufferHandle importBuffer(std::string name, PersistentBuffer& buffer);
    // External resources (host G-buffer, swapchain image) in the state `current` left them.
    ImageHandle importImage(std::string name, const Image& image, Access current);
    BufferHandle importBuffer(std::string name, const Buffer& buffer, Access current);
    // Transitions the resource into `finalAccess` after the last pass and keeps its writers.
    void exportImage(ImageHandle h, Access finalAccess);
    void exportBuffer(BufferHandle h, Access finalAccess);
    // Requested outputs: the passes producing this version (and what they need) are kept.
    void markOutput(ImageHandle h);
    void markOutput(BufferHandle h);

    // Validates, culls, orders and derives every barrier. Needs no Vulkan device.
    Result<void> compile();
    // Records the compiled graph into `cmd`. Transients come from `pool`; `timestamps` (may be
    // null) is reset and gets the frame's scope and, with TimestampScopes::PerPass, one scope per
    // executed pass. Stores final states of persistent resources and pool entries.
    void execute(VkCommandBuffer cmd, Context& ctx, TransientPool& pool, TimestampPool* timestamps = nullptr,
                 TimestampScopes scopes = TimestampScopes::PerPass);
    // Per-pass GPU time of the last execute(); call after its submit has finished.
    std::vector<PassTiming> timings() const;
    // GPU time of the whole last execute(), from before the first barrier to after the export
    // barriers: what the frame costs. On lavapipe it exceeds the sum of timings(), as some work
    // completes inside barriers, outside every pass's scope.
    double frameMs() const;
    // Set 0 (FrameConstants) for this frame: PassContext::dispatch binds it for every pipeline
    // whose shaders read the frame constants; graphics passes call PassContext::bindFrameSet.
    void setFrameSet(VkDescriptorSet set) { m_frameSet = set; }
    VkDescriptorSet frameSet() const { return m_frameSet; }
    // Transient bytes per pass of the last execute() (actual allocation sizes).
    const MemoryReport& memoryReport() const { return m_memory; }

    const CompiledGraph& compiled() const { return m_compiled; }
    std::vector<std::string> orderedPassNames() const;
    std::vector<std::string> culledPassNames() const { return m_compiled.culled; }
    // Transients (or, with `persistent`, persistent imports) the live passes use, in first-use order.
    std::vector<std::string> usedResourceNames(bool persistent) const;
    // Barriers before the named pass; null if the pass does not exist or was culled.
    const std::vector<BarrierInfo>* barriersBefore(std::string_view pass) const;
    // Description with the usage flags accumulated from the declared accesses (after compile).
    const ImageDesc& imageDesc(ImageHandle h) const { return m_resources.at(h.index).imageDesc; }
    const BufferDesc& bufferDesc(BufferHandle h) const { return m_resources.at(h.index).bufferDesc; }
    const std::string& resourceName(uint32_t resource) const { return m_resources.at(resource).name; }
    // Copies the compiled final states into persistent imports (execute() does this; device-less
    // tests call it directly to simulate a frame).
    void storeFinalStates();
    // The commands execute() recorded never ran (their submit failed): puts back the states
    // storeFinalStates replaced, so the next graph's barriers start from what the GPU last did.
    void discardFinalStates();
    // Graphviz: passes are boxes (culled ones grey), resource versions ellipses.
    void writeDot(std::ostream& out) const;

private:
    friend class PassBuilder;
    friend class PassContext;
    friend class ComputePass;

    uint32_t beginPass(std::string name);
    template <typename F> void setExecute(uint32_t pass, F&& fn) {
        m_passes[pass].execute = std::function<void(PassContext&)>(std::forward<F>(fn));
    }
    uint32_t addResource(detail::ResourceNode node);
    void addError(std::string message);
    bool checkHandle(uint32_t pass, uint32_t index, bool image, Access access, const SubresourceRange& range,
                     const char* what);
    void declareRead(uint32_t pass, uint32_t index, uint32_t version, Access access, const SubresourceRange& range);
    uint32_t declareWrite(uint32_t pass, uint32_t index, uint32_t version, Access access,
                          const SubresourceRange& range);
    void keepVersion(uint32_t index, uint32_t version, bool image);
    std::string passLabel(uint32_t pass) const;

    // compile() steps (render_graph_compile.cpp)
    void cull();
    void accumulateUsage();
    Result<void> checkImportedUsage() const;
    Result<void> deriveBarriers();
    Result<void> derivePassBarriers(uint32_t pass, std::vector<std::vector<AccessState>>& states,
                                    std::vector<BarrierInfo>& out);
    void deriveFinalBarriers(std::vector<std::vector<AccessState>>& states);

    // execute() steps (render_graph_execute.cpp)
    void acquireTransients(Context& ctx, TransientPool& pool);
    // Returns whether anything was recorded.
    bool recordBarriers(VkCommandBuffer cmd, const std::vector<BarrierInfo>& barriers) const;
    // An empty execution barrier: makes lavapipe write the pending timestamps (execute()).
    static void recordFlush(VkCommandBuffer cmd);
    void buildMemoryReport();

    std::vector<detail::PassNode> m_passes;
    std::vector<detail::ResourceNode> m_resources;
    std::vector<std::string> m_errors;
    CompiledGraph m_compiled;
    bool m_isCompiled = false;
    std::vector<std::vector<AccessState>> m_finalStates; // per resource, after the final barriers
    // What storeFinalStates overwrote, for discardFinalStates.
    std::vector<std::pair<PersistentImage*, std::vector<AccessState>>> m_replacedImageStates;
    std::vector<std::pair<PersistentBuffer*, AccessState>> m_replacedBufferStates;
    std::vector<uint32_t> m_firstUser;                   // first live pass using each resource
    std::vector<uint32_t> m_lastUser;                    // last live pass using each resource
    // Execute: transients in first-use order, and for each the transient that used its pool
    // entry earlier in this execution (kNone: the entry was free or new).
    std::vector<uint32_t> m_transientOrder;
    std::vector<uint32_t> m_previousOccupant;
    // Physical resources bound in execute(): persistent imports and pool entries share the
    // PersistentImage/PersistentBuffer form, so final states go back the same way.
    std::vector<PersistentImage*> m_boundImages;
    std::vector<PersistentBuffer*> m_boundBuffers;
    std::vector<const Image*> m_physImages;
    std::vector<const Buffer*> m_physBuffers;
    TimestampPool* m_timestamps = nullptr;
    std::vector<uint32_t> m_timedPasses;
    MemoryReport m_memory;
    VkDescriptorSet m_frameSet = VK_NULL_HANDLE;
    std::string m_passNameSuffix;
};

} // namespace vkgi::rg
