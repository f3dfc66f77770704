// GiSystem: owns the GPU scene, the shared pass pipelines, the shadow/RSM atlases and the
// technique module, and turns a camera into a frame graph (pipeline.cpp) it executes.
#include <algorithm>
#include <cmath>
#include <optional>

#include "direct/direct_passes.hpp"
#include "direct/host_gbuffer.hpp"
#include "vkgi/frame_constants.hpp"
#include "vkgi/rg/transient_pool.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"
#include "vkgi/gi.hpp"
#include "pass_selection.hpp"
#include "technique.hpp"

namespace vkgi::gi {

namespace {

// Timestamp scopes per frame: far more passes than any technique adds (LPV: ~8 + steps).
constexpr uint32_t kMaxTimedPasses = 512;
// Largest frame side accepted (the path tracer's limit too).
constexpr uint32_t kMaxFrameSide = 16384;
// Frames of FrameConstants in flight: renderFrame waits, hosts may pipeline one frame.
constexpr uint32_t kFrameRing = 2;

Result<void> checkCamera(const Camera& c, uint32_t width, uint32_t height) {
    if (width == 0 || height == 0 || width > kMaxFrameSide || height > kMaxFrameSide)
        return makeError("frame size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1..16384");
    auto finite3 = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    bool finite = finite3(c.position) && finite3(c.forward) && finite3(c.up) && std::isfinite(c.znear) &&
                  std::isfinite(c.zfar);
    if (!finite || glm::length(c.forward) == 0.0f || !(c.yfov > 0.0f && c.yfov < 3.14159f) ||
        !(c.znear > 0.0f && c.zfar > c.znear))
        return makeError("camera: position/forward must be finite, yfov in (0, pi), 0 < znear < zfar");
    return {};
}

// The whole graph's GPU time (barriers included), or the sum of the passes without timestamps.
double frameTotalMs(const rg::RenderGraph& graph, const std::vector<rg::PassTiming>& passes) {
    double sum = 0.0;
    for (const rg::PassTiming& t : passes)
        sum += t.ms;
    return std::max(graph.frameMs(), sum);
}

} // namespace

struct GiSystem::Impl {
    std::unique_ptr<Context> ownedContext;
    Context* ctx = nullptr;
    GiSettings settings;
    DirectPipelines pipelines;
    std::unique_ptr<rg::TransientPool> pool;
    std::unique_ptr<TimestampPool> timestamps;
    std::unique_ptr<FrameConstantsRing> frameRing;
    std::unique_ptr<TechniqueModule> technique;
    Scene scene;
    std::optional<GpuScene> gpu;
    ShadowTargets shadows;
    Buffer readback[5]; // composite, direct, indirect, glossy, ao
    VkCommandPool commandPool = VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    uint32_t frameIndex = 0;
    // Pass selection (pass_selection.hpp): the scene's features and what changed since the shadow
    // passes and the technique last registered their passes.
    SceneFeatures features;
    SceneChanges shadowChanges;
    SceneChanges techniqueChanges;
    ShadowLayout lastShadowLayout; // layout the persistent atlas was last rendered with
    std::optional<Camera> lastTechniqueCamera;
    uint32_t lastTechniqueWidth = 0, lastTechniqueHeight = 0;
    // A frame failed: the technique's own record-time bookkeeping (what its volumes hold, which
    // voxels the last voxelization touched) may describe work that never ran, so the next frame
    // rebuilds the technique's state as for a new scene.
    bool rebuildTechnique = false;

    ~Impl();
    // `host`: the host's G-buffer replaces the G-buffer pass, and no direct light is computed.
    Result<GiOutputs> addPasses(rg::RenderGraph& graph, rg::Blackboard& bb, const Camera& camera, uint32_t width,
                                uint32_t height, const FrameRequest& request, const HostGBuffer* host = nullptr);
    // The steps of addPasses, in the order it adds them.
    void addShadowPasses(rg::RenderGraph& graph, rg::Blackboard& bb, PassSelection& selection);
    void addTechniquePasses(rg::RenderGraph& graph, rg::Blackboard& bb, const FrameRequest& request, bool host,
                            GiOutputs& out);
    void addCompositeAndOutputs(rg::RenderGraph& graph, rg::Blackboard& bb, const FrameRequest& request,
                                GiOutputs& out);
    FrameData frameData(const Camera& camera, uint32_t width, uint32_t height);
    // The public entry points' bodies (GiSystem runs each inside guarded()).
    Result<void> setScene(const Scene& newScene);
    Result<void> updateScene(const Scene& newScene);
    Result<FrameResult> renderFrame(const Camera& camera, uint32_t width, uint32_t height, const FrameRequest& request);
    Result<GiOutputs> addHostPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard, const Camera& camera,
                                    const HostGBuffer& gbuffer);
    Result<FrameResult> renderIndirect(const Camera& camera, const HostFrame& host);
    PersistentMemory persistentMemory() const;
    const Buffer& readbackBuffer(uint32_t slot, uint32_t width, uint32_t height);
    void submitAndWait(rg::RenderGraph& graph, rg::TimestampScopes scopes = rg::TimestampScopes::PerPass);
    void invalidate() {
        shadowChanges = SceneChanges{};
        techniqueChanges = SceneChanges{};
    }
    // After a failed Vulkan call: waits until nothing of the frame can still run, drops its
    // half-recorded command buffer, and makes the next frame recompute every persistent result
    // (the failed frame may have marked work clean that never ran). Results are ignored: the
    // call that failed already reported the error, and a lost device fails these too.
    // `submits`: false for addPasses, which records and submits nothing of its own (and must not
    // wait on the host's queue).
    void recover(bool submits) noexcept {
        if (submits) {
            (void)vkDeviceWaitIdle(ctx->device());
            if (cmd)
                (void)vkResetCommandBuffer(cmd, 0);
        }
        invalidate();
        lastTechniqueCamera.reset();
        rebuildTechnique = true;
    }
    // Runs an entry point's body; a failed Vulkan call inside (VulkanError) becomes its error.
    template <typename Body> auto guarded(Body&& body, bool submits = true) -> decltype(body()) {
        try {
            return body();
        } catch (const VulkanError& e) {
            recover(submits);
            return makeError(e.what());
        }
    }
};

GiSystem::Impl::~Impl() {
    if (!ctx)
        return;
    // Never throws: after a device loss this fails too, and everything is destroyed regardless.
    (void)vkDeviceWaitIdle(ctx->device());
    technique.reset();
    for (Buffer& b : readback)
        if (b)
            destroyBuffer(*ctx, b);
    destroyShadowTargets(*ctx, shadows);
    if (gpu)
        destroyScene(*ctx, *gpu);
    frameRing.reset();
    timestamps.reset();
    pool.reset();
    destroyDirectPipelines(*ctx, pipelines);
    if (fence)
        vkDestroyFence(ctx->device(), fence, nullptr);
    if (commandPool)
        vkDestroyCommandPool(ctx->device(), commandPool, nullptr);
}

FrameData GiSystem::Impl::frameData(const Camera& camera, uint32_t width, uint32_t height) {
    FrameData f;
    f.camera = camera;
    f.width = width;
    f.height = height;
    f.view = camera.view();
    f.proj = camera.projection(float(width) / float(height));
    f.viewProj = f.proj * f.view;
    f.invViewProj = glm::inverse(f.viewProj);
    f.scene = &scene;
    f.gpuScene = &*gpu;
    f.settings = &settings;
    gpu::FrameConstants c{};
    c.view = f.view;
    c.proj = f.proj;
    c.viewProj = f.viewProj;
    c.invViewProj = f.invViewProj;
    c.cameraPosition = glm::vec4(camera.position, camera.yfov);
    c.resolution = glm::uvec4(width, height, frameIndex++, uint32_t(scene.lights.size()));
    c.sceneMin = glm::vec4(gpu->bounds.valid() ? gpu->bounds.min : glm::vec3(0.0f), 0.0f);
    c.sceneMax = glm::vec4(gpu->bounds.valid() ? gpu->bounds.max : glm::vec3(0.0f), 0.0f);
    f.frameSet = frameRing->next(c);
    return f;
}

Result<GiOutputs> GiSystem::Impl::addPasses(rg::RenderGraph& graph, rg::Blackboard& bb, const Camera& camera,
                                            uint32_t width, uint32_t height, const FrameRequest& request,
                                            const HostGBuffer* host) {
    if (!gpu)
        return makeError("GiSystem: no scene (call setScene before rendering)");
    if (auto ok = checkCamera(camera, width, height); !ok)
        return ok.error();
    if (rebuildTechnique && technique) {
        VKGI_CHECK(vkDeviceWaitIdle(ctx->device())); // a host's frames may still read the old volumes
        if (auto ok = technique->sceneChanged(*ctx, scene, *gpu, true); !ok)
            return ok.error();
    }
    rebuildTechnique = false;
    FrameData frameValue = frameData(camera, width, height);
    graph.setFrameSet(frameValue.frameSet); // set 0 for technique shaders that read FrameConstants
    const FrameData& frame = bb.add(std::move(frameValue));
    const SceneHandles& sceneHandles = bb.add(importScene(graph, *gpu));
    const GBufferData& gbuffer = bb.add(host ? importHostGBuffer(graph, pipelines, frame, *host)
                                             : addGBufferPass(graph, pipelines, frame, sceneHandles));

    PassSelection& selection = bb.add(PassSelection{features, {}, {}, request});
    leaveOutMissingLightKinds(features, selection);
    addShadowPasses(graph, bb, selection);
    if (host)
        selection.leaveOut("gi.direct", LeftOutReason::NotNeeded, "host G-buffer: the host shades direct light");
    bb.add(host ? DirectData{} : addDeferredPass(graph, pipelines, frame, sceneHandles, gbuffer, bb.get<ShadowData>()));

    GiOutputs out;
    addTechniquePasses(graph, bb, request, host != nullptr, out);
    addCompositeAndOutputs(graph, bb, request, out);
    return out;
}

// Shadow atlas (and RSM when the technique or the settings want it): one pass per light whose
// layers do not already hold this frame's content.
void GiSystem::Impl::addShadowPasses(rg::RenderGraph& graph, rg::Blackboard& bb, PassSelection& selection) {
    bool rsm = settings.forceRsm || (technique && technique->needsRsm());
    ShadowLayout layout = planShadows(scene, gpu->bounds, settings.shadowMapSize, settings.maxShadowLayers);
    // New atlas or RSM arrays have no contents yet: every light renders.
    uint32_t oldLayers = shadows.layers, oldResolution = shadows.resolution;
    bool oldRsm = shadows.rsm;
    ensureShadowTargets(*ctx, shadows, uint32_t(layout.views.size()), settings.shadowMapSize, rsm);
    if (shadows.layers != oldLayers || shadows.resolution != oldResolution || shadows.rsm != oldRsm)
        shadowChanges.all = true;
    std::vector<bool> keep = cleanShadowLights(layout, lastShadowLayout, shadowChanges);
    for (uint32_t i = 0; i < keep.size(); ++i)
        if (keep[i])
            selection.leaveOut(lightPassName(i, scene.lights[i].type), LeftOutReason::NotDirty,
                               "light " + std::to_string(i) + " and every object unchanged");
    addLightPasses(graph, bb, pipelines, bb.get<FrameData>(), bb.get<SceneHandles>(), layout, shadows, rsm, keep);
    lastShadowLayout = std::move(layout);
    shadowChanges.reset();
}

// The technique's indirect light (IndirectData), or the reason no technique pass runs.
void GiSystem::Impl::addTechniquePasses(rg::RenderGraph& graph, rg::Blackboard& bb, const FrameRequest& request,
                                        bool host, GiOutputs& out) {
    PassSelection& selection = bb.get<PassSelection>();
    if (!technique) {
        selection.leaveOut("gi.indirect.*", LeftOutReason::NotNeeded,
                           "technique none: no voxel grid, LPV or VPL is allocated or run");
        return;
    }
    if (!request.composite && !request.indirect && !request.glossy && !request.ao) {
        // Persistent technique volumes would keep their passes alive in the graph: do not add them.
        selection.leaveOut(
            std::string("gi.") + toString(settings.technique) + ".*", LeftOutReason::NotNeeded,
            "no requested output reads indirect light (composite, indirect, glossy and ao not requested)");
        return;
    }
    const FrameData& frame = bb.get<FrameData>();
    // A host's G-buffer may change without a camera move: view-dependent work re-runs each frame.
    techniqueChanges.camera = host || !lastTechniqueCamera ||
                              !sameView(*lastTechniqueCamera, lastTechniqueWidth, lastTechniqueHeight, frame.camera,
                                        frame.width, frame.height);
    selection.changes = techniqueChanges;
    const TechniqueInputs inputs{frame,
                                 bb.get<SceneHandles>(),
                                 bb.get<GBufferData>(),
                                 bb.get<ShadowData>(),
                                 bb.tryGet<RsmData>(),
                                 bb.get<DirectData>().direct,
                                 selection,
                                 bb};
    const IndirectOutputs produced = technique->addPasses(graph, inputs);
    techniqueChanges.reset();
    lastTechniqueCamera = frame.camera;
    lastTechniqueWidth = frame.width;
    lastTechniqueHeight = frame.height;
    bb.add(IndirectData{produced.indirect, produced.ao, produced.glossy});
    out.indirect = produced.indirect;
    out.glossy = produced.glossy;
    out.ao = produced.ao;
    if (produced.direct.valid())
        bb.get<DirectData>().direct = produced.direct;
}

// Composite = direct + indirect (the direct image alone without indirect light); then only the
// requested images stay in `out` and become graph outputs.
void GiSystem::Impl::addCompositeAndOutputs(rg::RenderGraph& graph, rg::Blackboard& bb, const FrameRequest& request,
                                            GiOutputs& out) {
    out.direct = bb.get<DirectData>().direct;
    out.composite = out.indirect.valid() && out.direct.valid()
                        ? addCompositePass(graph, pipelines, bb.get<FrameData>(), out.direct, out.indirect).final
                        : out.direct;
    bb.add(CompositeData{out.composite});
    if (!request.composite)
        out.composite = {};
    if (!request.direct)
        out.direct = {};
    if (!request.indirect)
        out.indirect = {};
    if (!request.glossy)
        out.glossy = {};
    if (!request.ao)
        out.ao = {};
    for (rg::ImageHandle h : {out.composite, out.direct, out.indirect, out.glossy, out.ao})
        if (h.valid())
            graph.markOutput(h);
}

const Buffer& GiSystem::Impl::readbackBuffer(uint32_t slot, uint32_t width, uint32_t height) {
    VkDeviceSize size = VkDeviceSize(width) * height * sizeof(glm::vec4);
    Buffer& b = readback[slot];
    if (!b || b.desc.size != size) {
        if (b)
            destroyBuffer(*ctx, b);
        b = createBuffer(*ctx, {size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::GpuToCpu}, "gi.readback");
    }
    return b;
}

void GiSystem::Impl::submitAndWait(rg::RenderGraph& graph, rg::TimestampScopes scopes) {
    VKGI_CHECK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VKGI_CHECK(vkBeginCommandBuffer(cmd, &begin));
    graph.execute(cmd, *ctx, *pool, ctx->timestampsSupported() ? timestamps.get() : nullptr, scopes);
    try {
        VKGI_CHECK(vkEndCommandBuffer(cmd));
        VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        cmdInfo.commandBuffer = cmd;
        VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        submit.commandBufferInfoCount = 1;
        submit.pCommandBufferInfos = &cmdInfo;
        VKGI_CHECK(vkResetFences(ctx->device(), 1, &fence));
        VKGI_CHECK(vkQueueSubmit2(ctx->queue(), 1, &submit, fence));
    } catch (const VulkanError&) {
        graph.discardFinalStates(); // recorded, never run: resources keep their previous states
        throw;
    }
    VKGI_CHECK(vkWaitForFences(ctx->device(), 1, &fence, VK_TRUE, UINT64_MAX));
}

GiSystem::GiSystem(std::unique_ptr<Impl> impl) : m(std::move(impl)) {}
GiSystem::~GiSystem() = default;

Result<std::unique_ptr<GiSystem>> GiSystem::create(Context& ctx, const GiSettings& settings) {
    if (auto ok = validateSettings(settings); !ok)
        return ok.error();
    auto impl = std::make_unique<Impl>();
    impl->ctx = &ctx;
    impl->settings = settings;
    try {
        auto pipelines = createDirectPipelines(ctx);
        if (!pipelines)
            return pipelines.error();
        impl->pipelines = *pipelines;
        auto technique = createTechnique(ctx, settings);
        if (!technique)
            return technique.error();
        impl->technique = std::move(*technique);
        impl->pool = std::make_unique<rg::TransientPool>(ctx);
        impl->timestamps = std::make_unique<TimestampPool>(ctx, kMaxTimedPasses);
        impl->frameRing = std::make_unique<FrameConstantsRing>(ctx, kFrameRing);
        VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        poolInfo.queueFamilyIndex = ctx.queueFamily();
        VKGI_CHECK(vkCreateCommandPool(ctx.device(), &poolInfo, nullptr, &impl->commandPool));
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = impl->commandPool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        VKGI_CHECK(vkAllocateCommandBuffers(ctx.device(), &alloc, &impl->cmd));
        VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VKGI_CHECK(vkCreateFence(ctx.device(), &fenceInfo, nullptr, &impl->fence));
    } catch (const VulkanError& e) {
        return makeError(e.what()); // ~Impl destroys what was created so far
    }
    return std::unique_ptr<GiSystem>(new GiSystem(std::move(impl)));
}

Result<std::unique_ptr<GiSystem>> GiSystem::createHeadless(const GiSettings& settings) {
    auto ctx = defaultDeviceBuilder().build();
    if (!ctx)
        return ctx.error();
    std::unique_ptr<Context> owned = std::move(*ctx);
    auto system = create(*owned, settings);
    if (!system)
        return system.error();
    // The context must outlive everything the system created on it: Impl destroys it last.
    (*system)->m->ownedContext = std::move(owned);
    return system;
}

Context& GiSystem::context() { return *m->ctx; }
const GiSettings& GiSystem::settings() const { return m->settings; }

void GiSystem::invalidate() { m->invalidate(); }

// Every entry point runs inside Impl::guarded: a failed Vulkan call is returned as the error.
Result<void> GiSystem::setScene(const Scene& scene) {
    return m->guarded([&] { return m->setScene(scene); });
}

Result<void> GiSystem::updateScene(const Scene& scene) {
    return m->guarded([&] { return m->updateScene(scene); });
}

Result<GiOutputs> GiSystem::addPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard, const Camera& camera,
                                      uint32_t width, uint32_t height, const FrameRequest& request) {
    return m->guarded([&] { return m->addPasses(graph, blackboard, camera, width, height, request); }, false);
}

Result<FrameResult> GiSystem::renderFrame(const Camera& camera, uint32_t width, uint32_t height,
                                          const FrameRequest& request) {
    return m->guarded([&] { return m->renderFrame(camera, width, height, request); });
}

Result<GiOutputs> GiSystem::addPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard, const Camera& camera,
                                      const HostGBuffer& gbuffer) {
    return m->guarded([&] { return m->addHostPasses(graph, blackboard, camera, gbuffer); }, false);
}

Result<FrameResult> GiSystem::renderIndirect(const Camera& camera, const HostFrame& host) {
    return m->guarded([&] { return m->renderIndirect(camera, host); });
}

Result<void> GiSystem::Impl::setScene(const Scene& newScene) {
    auto uploaded = uploadScene(*ctx, newScene);
    if (!uploaded)
        return uploaded.error();
    if (gpu) {
        VKGI_CHECK(vkDeviceWaitIdle(ctx->device()));
        destroyScene(*ctx, *gpu);
    }
    gpu = std::move(*uploaded);
    scene = newScene;
    features = analyzeScene(newScene);
    invalidate();
    if (technique)
        return technique->sceneChanged(*ctx, scene, *gpu, true);
    return {};
}

Result<void> GiSystem::Impl::updateScene(const Scene& newScene) {
    if (!gpu)
        return makeError("GiSystem::updateScene: no scene (call setScene first)");
    if (auto ok = updateSceneTransforms(*ctx, *gpu, newScene); !ok)
        return ok;
    SceneChanges changes = diffScenes(scene, newScene);
    shadowChanges.merge(changes);
    techniqueChanges.merge(changes);
    scene.instances = newScene.instances;
    scene.lights = newScene.lights;
    if (technique)
        return technique->sceneChanged(*ctx, scene, *gpu, false);
    return {};
}

Result<FrameResult> GiSystem::Impl::renderFrame(const Camera& camera, uint32_t width, uint32_t height,
                                                const FrameRequest& request) {
    rg::RenderGraph graph;
    rg::Blackboard bb;
    auto outputs = addPasses(graph, bb, camera, width, height, request);
    if (!outputs)
        return outputs.error();
    rg::ImageHandle images[5] = {outputs->composite, outputs->direct, outputs->indirect, outputs->glossy, outputs->ao};
    const char* names[5] = {"gi.readback.composite", "gi.readback.direct", "gi.readback.indirect",
                            "gi.readback.glossy", "gi.readback.ao"};
    for (uint32_t i = 0; i < 5; ++i)
        if (images[i].valid())
            addReadbackPass(graph, names[i], images[i], readbackBuffer(i, width, height));
    if (auto ok = graph.compile(); !ok) {
        invalidate(); // nothing ran: what this frame skipped as clean may be stale
        return makeError("frame graph: " + ok.error().message);
    }
    submitAndWait(graph, request.passTimings ? rg::TimestampScopes::PerPass : rg::TimestampScopes::FrameOnly);

    FrameResult r;
    HdrImage* targets[5] = {&r.composite, &r.direct, &r.indirect, &r.glossy, &r.ao};
    for (uint32_t i = 0; i < 5; ++i)
        if (images[i].valid())
            *targets[i] = readbackToImage(readback[i], width, height, i == 4 ? ReadbackChannels::AlphaToRgb
                                                                                 : ReadbackChannels::Rgb);
    r.passes = graph.timings();
    r.totalMs = frameTotalMs(graph, r.passes);
    r.culledPasses = graph.culledPassNames();
    r.leftOut = bb.get<PassSelection>().leftOut;
    for (const std::string& name : r.culledPasses)
        r.leftOut.push_back({name, LeftOutReason::Culled, "no requested output reads what it writes"});
    r.transientResources = graph.usedResourceNames(false);
    r.persistentResources = graph.usedResourceNames(true);
    r.transientBytes = graph.memoryReport().transientBytes;
    r.passMemory = graph.memoryReport().passes;
    r.persistentByOwner = persistentMemory();
    r.persistentBytes = r.persistentByOwner.total();
    return r;
}

namespace {

Result<void> checkHostFrame(const TechniqueModule* technique, const HostGBuffer& g) {
    if (!technique)
        return makeError("GiSystem host G-buffer path: technique none computes no indirect light");
    return checkHostGBuffer(g);
}

} // namespace

Result<GiOutputs> GiSystem::Impl::addHostPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard,
                                                 const Camera& camera, const HostGBuffer& gbuffer) {
    if (auto ok = checkHostFrame(technique.get(), gbuffer); !ok)
        return ok.error();
    return addPasses(graph, blackboard, camera, gbuffer.normal.width, gbuffer.normal.height,
                        FrameRequest{false, false, true}, &gbuffer);
}

Result<FrameResult> GiSystem::Impl::renderIndirect(const Camera& camera, const HostFrame& host) {
    if (auto ok = checkHostFrame(technique.get(), host.gbuffer); !ok)
        return ok.error();
    if (!host.indirect.image && !host.readback)
        return makeError("GiSystem::renderIndirect: HostFrame has no indirect image and no readback: nothing to do");
    if (host.indirect.image)
        if (auto ok = checkHostIndirect(host.indirect, host.gbuffer); !ok)
            return ok.error();
    if (auto ok = checkFinalAccess("HostFrame.indirectFinalAccess", host.indirectFinalAccess); !ok)
        return ok.error();
    if (auto ok = checkFinalAccess("HostFrame.gbufferFinalAccess", host.gbufferFinalAccess); !ok)
        return ok.error();
    uint32_t width = host.gbuffer.normal.width, height = host.gbuffer.normal.height;
    rg::RenderGraph graph;
    rg::Blackboard bb;
    auto outputs = addPasses(graph, bb, camera, width, height, FrameRequest{false, false, true}, &host.gbuffer);
    if (!outputs)
        return outputs.error();
    exportHostGBuffer(graph, bb.get<GBufferData>(), host.gbuffer, host.gbufferFinalAccess);
    if (host.indirect.image)
        addHostIndirectCopy(graph, outputs->indirect, host.indirect, host.indirectFinalAccess);
    if (host.readback)
        addReadbackPass(graph, "gi.readback.indirect", outputs->indirect, readbackBuffer(2, width, height));
    if (auto ok = graph.compile(); !ok)
        return makeError("frame graph: " + ok.error().message);
    submitAndWait(graph);

    FrameResult r;
    if (host.readback)
        r.indirect = readbackToImage(readback[2], width, height);
    r.passes = graph.timings();
    r.totalMs = frameTotalMs(graph, r.passes);
    r.culledPasses = graph.culledPassNames();
    r.transientBytes = graph.memoryReport().transientBytes;
    r.persistentByOwner = persistentMemory();
    r.persistentBytes = r.persistentByOwner.total();
    return r;
}

uint64_t GiSystem::persistentBytes() const {
    return persistentMemory().total();
}

PersistentMemory GiSystem::persistentMemory() const { return m->persistentMemory(); }

PersistentMemory GiSystem::Impl::persistentMemory() const {
    PersistentMemory p;
    p.shadows = shadows.bytes();
    if (gpu)
        p.scene = gpu->bytes();
    for (const Buffer& b : readback)
        p.readback += b ? b.desc.size : 0;
    if (technique)
        p.technique = technique->persistentBytes();
    return p;
}

} // namespace vkgi::gi
