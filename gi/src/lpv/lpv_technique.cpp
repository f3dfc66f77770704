// Technique::Lpv: per frame, inject the shared RSM (and, in a scene with emission, the RSM of the
// emitters' point proxies, which the LPV renders itself) into a grid fitted to the lit part of
// the scene (or into camera-centred cascades when that part is too large for one grid), build the
// geometry volume from the RSM and the camera's G-buffer, propagate (with reflection at the shared
// voxel grid's occupied voxels when bounces are on), and look the accumulated light up per pixel.
// With one grid (no camera-following cascades) the accumulated volume and the injection buffer
// are persistent: injection and propagation run only when a light or object changed, or the
// camera moved while occlusion is on (the geometry volume takes the camera's G-buffer surfels, so
// it is view dependent); otherwise only the lookup runs. The voxel grid of the bounce is
// persistent too and re-voxelized only for moved objects. Everything else is a transient of the
// frame graph.
#include "lpv/lpv_technique.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "vkgi/frame_data.hpp"
#include "emissive/emissive_surfels.hpp"
#include "engine/lights.h"
#include "engine/scene_types.h"
#include "lpv/lpv_grid.hpp"
#include "lpv/lpv_inject.hpp"
#include "lpv/lpv_passes.hpp"
#include "lpv/lpv_volume.hpp"
#include "voxel/scene_voxel_grid.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

// Voxel grid resolution for the bounce: twice the LPV's (so trilinear sampling at a cell centre
// averages the 2^3 voxels inside it), a power of two in the voxelizer's range. 128^3 keeps the
// three RGBA8 volumes inside the module's memory budget.
uint32_t voxelResolutionFor(uint32_t lpvCells) {
    uint32_t resolution = GI_VOXEL_MIN_RESOLUTION;
    while (resolution < 2 * lpvCells && resolution < 128u)
        resolution *= 2;
    return resolution;
}

// Lambertian point sources standing for the scene's emission (emitterPointSources), each with a
// cube RSM whose faces have half the shadow map's side: together the proxies have the texels of
// one point light's cube RSM.
constexpr uint32_t kEmitterSources = 4;

// What every grid of a frame injects from and looks up for.
struct FrameSources {
    VkFormat format = VK_FORMAT_UNDEFINED; // SH storage format
    lpv::RsmInput rsm;                     // the lights' RSM as the light passes wrote it (before any
                                           // reduction); position invalid when no light has layers
    bool emitters = false;                 // the emitter proxies' RSM is injected too
    lpv::GBufferInput gbuffer;
};

// The persistent volumes of the single-grid case as this frame's graph sees them.
struct KeptVolumes {
    lpv::ShHandles accumulation;
    rg::BufferHandle injectionBuffer;
    rg::ImageHandle channelSum; // invalid without damping
};

class LpvTechnique final : public TechniqueModule {
public:
    LpvTechnique(Context& ctx, const LpvSettings& settings, uint32_t shadowMapSize, lpv::Propagator propagator,
                 lpv::Injector injector)
        : m_ctx(ctx), m_settings(settings), m_emitterResolution(std::max(shadowMapSize / 2u, 16u)),
          m_propagator(propagator), m_injector(injector) {}
    ~LpvTechnique() override {
        if (m_cache.cells != glm::ivec3(0))
            vkDeviceWaitIdle(m_ctx.device()); // the last frame may still read the kept volume
        destroyCache();
        m_voxels.reset();
        m_propagator.destroy(m_ctx);
        m_injector.destroy(m_ctx);
    }

    // Without a lit region (no light) there is nothing to inject: the light passes leave the RSM out.
    // A scene lit by emission alone needs only the emitter proxies' RSM, which the LPV renders.
    bool needsRsm() const override { return m_grid.has_value() && m_sceneHasLights; }

    // Cascades read the RSM inside their coarsest level only: a sun's RSM is fitted to that box
    // (its own layer spans the whole scene, hundreds of metres in a large world, where merged
    // texels blur the light over walls thinner than a cell).
    Aabb rsmWindow(const FrameData& frame) const override {
        if (!m_grid)
            return {};
        const std::vector<gpu::LpvGrid> grids = gridsFor(frame);
        if (grids.size() <= 1)
            return {};
        const gpu::LpvGrid& coarsest = grids.back();
        Aabb box;
        box.min = glm::vec3(coarsest.origin);
        box.max = box.min + coarsest.origin.w * glm::vec3(coarsest.size);
        return box;
    }

    Result<void> sceneChanged(Context& ctx, const Scene& scene, const GpuScene& gpu, bool uploaded) override {
        m_emitters = emitterPointSources(scene, kEmitterSources);
        m_sceneHasLights = !scene.lights.empty();
        if (auto fitted = fitGrid(scene, gpu); !fitted)
            return fitted.error();
        if (m_settings.bounces) // the grid of the bounce
            return m_voxels.sceneChanged(ctx, gpu, uploaded, voxelResolutionFor(m_fittedCells),
                                         scene.cameraOrDefault().position);
        return {};
    }

    IndirectOutputs addPasses(rg::RenderGraph& graph, const TechniqueInputs& in) override {
        const bool lightRsm = in.rsm && !in.rsm->layers.empty();
        if (!m_grid || (!lightRsm && m_emitters.empty()))
            return {addUnlitPasses(graph, in), {}, {}, {}};
        const FrameData& frame = in.frame;
        // A camera-centred bounce grid that moves a step needs propagating again (needsPropagation).
        m_voxels.follow(frame.camera.position);
        FrameSources sources;
        sources.format = m_settings.halfFloat ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
        if (lightRsm) {
            const RsmData& rsm = *in.rsm;
            sources.rsm = {rsm.position, rsm.normal, rsm.flux, rsm.resolution, uint32_t(rsm.layers.size())};
            sources.rsm.views = in.shadow.views;
        }
        sources.emitters = !m_emitters.empty();
        sources.gbuffer = {in.gbuffer.position, in.gbuffer.normal, in.gbuffer.albedo, frame.width, frame.height};
        std::vector<gpu::LpvGrid> grids = gridsFor(frame);
        if (grids.size() == 1)
            return {addKeptGridPasses(graph, in, grids[0], sources), {}, {}, {}};
        return {addCascadePasses(graph, in, grids, sources), {}, {}, {}};
    }

    uint64_t persistentBytes() const override {
        uint64_t n = m_voxels.bytes();
        for (const rg::PersistentImage& image : m_cache.accumulation)
            n += image.image.alloc.size;
        if (m_cache.channelSum.image.image)
            n += m_cache.channelSum.image.alloc.size;
        return n + m_cache.injectionBuffer.buffer.alloc.size;
    }

private:
    // The grid fitted to the part of the scene the lights reach (none when nothing is lit).
    Result<void> fitGrid(const Scene& scene, const GpuScene& gpu) {
        m_grid.reset();
        m_fittedCells = m_settings.gridSize;
        // Emission has no range: with emitters the whole scene is lit.
        Aabb region = m_emitters.empty() ? lpv::litRegion(gpu.bounds, scene.lights) : gpu.bounds;
        if (!region.valid())
            return {};
        m_fittedCells = lpv::fittedCells(region, m_settings.gridSize, m_settings.fittedCell);
        auto grid = lpv::fitLpvGrid(region, m_fittedCells);
        if (!grid)
            return grid.error();
        m_grid = *grid;
        m_region = region;
        return {};
    }

    // One grid fitted to the lit region, or nested grids following the camera whose finest
    // cell is LpvSettings::cellSize metres (lpv::cascadeCount picks for cascades = 0).
    std::vector<gpu::LpvGrid> gridsFor(const FrameData& frame) const {
        const glm::vec3 eye = frame.camera.position;
        const bool inside = glm::all(glm::greaterThanEqual(eye, m_region.min)) &&
                            glm::all(glm::lessThanEqual(eye, m_region.max));
        const uint32_t count = lpv::cascadeCount(m_settings.cascades, m_settings.cellSize, m_grid->origin.w, inside);
        if (count <= 1)
            return {*m_grid};
        return lpv::fitCascades(frame.camera.position, glm::normalize(frame.camera.forward), m_settings.cellSize,
                                m_settings.gridSize, count);
    }

    // One grid: the propagated volume is kept and reused while nothing it depends on changed.
    rg::ImageHandle addKeptGridPasses(rg::RenderGraph& graph, const TechniqueInputs& in, const gpu::LpvGrid& grid,
                                      const FrameSources& sources) {
        const bool fresh = ensureCache(glm::ivec3(grid.size), sources.format);
        KeptVolumes kept = importCache(graph);
        if (fresh || needsPropagation(grid, in.selection.changes)) {
            lpv::VoxelInput voxels = addVoxelPasses(graph, in);
            const std::vector<lpv::RsmInput> rsms = injectedRsms(graph, in, sources, grid.origin.w);
            const uint32_t steps = lpv::fittedIterations(m_settings.iterations, m_settings.gridSize, m_fittedCells);
            lpv::InjectionResult propagated = addGridPasses(graph, grid, sources, rsms, voxels, steps, "gi.lpv",
                                                            kept.accumulation, kept.injectionBuffer);
            kept.accumulation = propagated.accumulation;
            kept.injectionBuffer = propagated.buffer;
            if (kept.channelSum.valid())
                kept.channelSum =
                    lpv::addAccumulationSumPass(graph, m_injector, grid, kept.accumulation, kept.channelSum);
            m_cache.grid = grid;
            m_cache.valid = true;
        } else {
            leaveOutUnchanged(in.selection, kept.channelSum.valid());
        }
        return lpv::addLookupPass(graph, m_injector, grid, kept.accumulation, kept.injectionBuffer, sources.gbuffer,
                                  m_settings.damping, {}, {}, "gi.lpv", kept.channelSum);
    }

    // True when the kept volume does not hold this frame's light in `grid`.
    bool needsPropagation(const gpu::LpvGrid& grid, const SceneChanges& changes) const {
        const bool sameGrid = std::memcmp(&grid, &m_cache.grid, sizeof(grid)) == 0;
        const bool viewChanged = m_settings.occlusion && changes.camera;
        return !m_cache.valid || !sameGrid || changes.any() || viewChanged || m_voxels.updatePending();
    }

    // The passes that only refresh the kept volume, left out while it holds this frame's light.
    void leaveOutUnchanged(PassSelection& selection, bool channelSum) const {
        const std::string why = m_settings.occlusion ? "no light or object changed and the camera did not move"
                                                     : "no light or object changed";
        selection.leaveOut("gi.lpv.inject*", LeftOutReason::NotDirty, why);
        if (!m_emitters.empty())
            selection.leaveOut("gi.lpv.emitter.*", LeftOutReason::NotDirty, why);
        if (m_settings.occlusion)
            selection.leaveOut("gi.lpv.gv.*", LeftOutReason::NotDirty, why);
        selection.leaveOut("gi.lpv.propagate*", LeftOutReason::NotDirty, why);
        if (channelSum)
            selection.leaveOut("gi.lpv.lookup.sum", LeftOutReason::NotDirty, why);
        if (m_voxels.exists())
            selection.leaveOut("gi.voxel.*", LeftOutReason::NotDirty, why);
    }

    // Camera-following cascades, all transient: every level is injected, propagated and looked
    // up every frame, the coarser levels adding to what the finer ones wrote.
    rg::ImageHandle addCascadePasses(rg::RenderGraph& graph, const TechniqueInputs& in,
                                     const std::vector<gpu::LpvGrid>& grids, const FrameSources& sources) {
        // The kept single-grid volume does not see this frame's changes: when the automatic
        // setting returns to it (the camera left the lit region), it must be propagated again.
        m_cache.valid = false;
        lpv::VoxelInput voxels = addVoxelPasses(graph, in);
        const std::vector<lpv::RsmInput> rsms = injectedRsms(graph, in, sources, grids.front().origin.w);
        rg::ImageHandle indirect;
        for (size_t k = 0; k < grids.size(); ++k) {
            const gpu::LpvGrid& grid = grids[k];
            const std::string prefix = k == 0 ? "gi.lpv" : "gi.lpv.c" + std::to_string(k);
            lpv::ShHandles accumulation =
                lpv::createShVolume(graph, (prefix + ".accumulation").c_str(), glm::ivec3(grid.size), sources.format);
            lpv::InjectionResult propagated =
                addGridPasses(graph, grid, sources, rsms, voxels, m_settings.iterations, prefix, accumulation, {});
            lpv::CascadeBlend blend;
            blend.fadeBorder = true;
            blend.accumulate = k > 0;
            for (size_t j = k >= 2 ? k - 2 : 0; j < k; ++j)
                blend.finer.push_back(grids[j]);
            indirect = lpv::addLookupPass(graph, m_injector, grid, propagated.accumulation, propagated.buffer,
                                          sources.gbuffer, m_settings.damping, indirect, blend, prefix);
        }
        return indirect;
    }

    // Injection, geometry volume and `steps` propagation steps of one grid into `accumulation`
    // (written whole) with `injectionBuffer` (invalid: a transient). Returns the accumulated light
    // and the injection buffer the lookup reads.
    lpv::InjectionResult addGridPasses(rg::RenderGraph& graph, const gpu::LpvGrid& grid, const FrameSources& sources,
                                       const std::vector<lpv::RsmInput>& rsms, const lpv::VoxelInput& voxels,
                                       uint32_t steps, const std::string& prefix,
                                       const lpv::ShHandles& accumulation, rg::BufferHandle injectionBuffer) {
        const glm::ivec3 cells(grid.size);
        lpv::ShHandles firstWavefront = lpv::createShVolume(graph, (prefix + ".wave.a").c_str(), cells, sources.format);
        lpv::InjectionResult injected = lpv::addInjectionPasses(graph, m_injector, grid, sources.format, rsms,
                                                                firstWavefront, accumulation, injectionBuffer, prefix);
        // The geometry volume's RSM surfels come from one RSM, the lights' when there is one, and of
        // the emitter proxies' from the first proxy's cube alone: every proxy sees the same walls,
        // which would be counted once per proxy in the same sum.
        rg::ImageHandle geometryVolume;
        if (m_settings.occlusion) {
            lpv::RsmInput blockers = rsms.front();
            if (!sources.rsm.position.valid())
                blockers.layers = std::min(blockers.layers, 6u);
            geometryVolume = lpv::addGeometryVolumePasses(graph, m_injector, grid, blockers, sources.gbuffer, prefix);
        }
        lpv::PropagationVolumes volumes{injected.wavefront,
                                        lpv::createShVolume(graph, (prefix + ".wave.b").c_str(), cells, sources.format),
                                        injected.accumulation};
        volumes = lpv::addPropagationPasses(graph, m_propagator, cells, sources.format, volumes, geometryVolume,
                                            steps, voxels, grid.origin, prefix);
        return {volumes.wavefront, volumes.accumulation, injected.buffer};
    }

    // The voxel grid of the bounce (when on), re-voxelized for what moved and a pending bake.
    lpv::VoxelInput addVoxelPasses(rg::RenderGraph& graph, const TechniqueInputs& in) {
        if (!m_voxels.exists())
            return {};
        VoxelGridData grid = m_voxels.addPasses(graph, in.scene, in.selection.changes, in.frame.camera.position);
        return {grid.albedo, grid.normal, grid.params.originSize, grid.params.dims.x};
    }

    // The RSM injection and the geometry volume read (gi.lpv.inject.reduce when rsmReduce > 1).
    // A block merges into one surfel only within half of `finestCell`, the finest grid's cell:
    // there it lands where its texels would.
    // Every grid leaves out the surfels within `finestCell` of their point or spot light
    // (gpu::lpvInjectsNearLight): the light that reaches the camera's surroundings comes through
    // the finest grid, and a coarser cascade's cell would drop whole rooms around a lamp.
    lpv::RsmInput reducedRsm(rg::RenderGraph& graph, const lpv::RsmInput& rsm, float finestCell,
                             const std::string& prefix = "gi.lpv") const {
        lpv::RsmInput out = m_settings.rsmReduce <= 1 ? rsm
                                                      : lpv::addRsmReducePass(graph, m_injector, rsm, m_settings.rsmReduce,
                                                                              0.5f * finestCell, prefix);
        out.nearLightRadius = finestCell;
        out.label = rsm.label;
        return out;
    }

    // The RSMs every grid of this frame injects: the lights' (when any light has layers), then the
    // emitter proxies' (when the scene has emission), both reduced as reducedRsm says.
    std::vector<lpv::RsmInput> injectedRsms(rg::RenderGraph& graph, const TechniqueInputs& in,
                                            const FrameSources& sources, float finestCell) const {
        std::vector<lpv::RsmInput> rsms;
        if (sources.rsm.position.valid())
            rsms.push_back(reducedRsm(graph, sources.rsm, finestCell));
        if (sources.emitters)
            rsms.push_back(reducedRsm(graph, addEmitterRsm(graph, in), finestCell, "gi.lpv.emitter"));
        return rsms;
    }

    // The cube RSM of every emitter proxy (docs/lpv.md, "Emissive surfaces"): the proxies as
    // GI_LIGHT_EMITTER lights and their cube-face views are uploaded by gi.lpv.emitter.setup and
    // rendered by gi.lpv.emitter.rsm with the light passes' RSM pipeline. The views also give the
    // injection the proxies' positions (the near-light rule).
    lpv::RsmInput addEmitterRsm(rg::RenderGraph& graph, const TechniqueInputs& in) const {
        std::vector<gpu::GpuLight> lights;
        std::vector<gpu::GpuShadowView> views;
        for (const EmitterPointSource& e : m_emitters) {
            gpu::GpuLight light{};
            light.positionType = glm::vec4(e.position, float(GI_LIGHT_EMITTER));
            light.directionRange = glm::vec4(e.normal, 0.0f);
            light.colorIntensity = glm::vec4(e.flux / 3.14159265358979f, 1.0f); // I(n) = flux / pi
            lights.push_back(light);
            for (const gpu::GpuShadowView& v : cubeShadowViews(e.position, in.frame.gpuScene->bounds, m_emitterResolution))
                views.push_back(v);
        }
        struct Setup {
            std::vector<gpu::GpuLight> lights;
            std::vector<gpu::GpuShadowView> views;
            rg::BufferHandle lightBuffer, viewBuffer;
        };
        const Setup& setup = graph.addPass<Setup>(
            "gi.lpv.emitter.setup",
            [&](rg::PassBuilder& b, Setup& d) {
                d.lights = lights;
                d.views = views;
                d.lightBuffer = b.write(b.create("gi.lpv.emitter.lights",
                                                 BufferDesc{lights.size() * sizeof(gpu::GpuLight)}),
                                        rg::Access::TransferWrite);
                d.viewBuffer = b.write(b.create("gi.lpv.emitter.views",
                                                BufferDesc{views.size() * sizeof(gpu::GpuShadowView)}),
                                       rg::Access::TransferWrite);
            },
            [](const Setup& d, rg::PassContext& pc) {
                vkCmdUpdateBuffer(pc.cmd(), pc.buffer(d.lightBuffer).buffer, 0,
                                  d.lights.size() * sizeof(gpu::GpuLight), d.lights.data());
                vkCmdUpdateBuffer(pc.cmd(), pc.buffer(d.viewBuffer).buffer, 0,
                                  d.views.size() * sizeof(gpu::GpuShadowView), d.views.data());
            });
        const RsmImages images = addPointSourceRsmPass(graph, in.pipelines, in.frame, in.scene, setup.lightBuffer,
                                                       views, m_emitterResolution, "gi.lpv.emitter.rsm");
        lpv::RsmInput rsm{images.position, images.normal, images.flux, m_emitterResolution, uint32_t(views.size())};
        rsm.views = setup.viewBuffer;
        rsm.label = ".emitter";
        return rsm;
    }

    // No lit region or no light in the shadow atlas: nothing to inject, a black indirect image.
    rg::ImageHandle addUnlitPasses(rg::RenderGraph& graph, const TechniqueInputs& in) {
        m_cache.valid = false; // the changes of this frame are not looked at
        in.selection.leaveOut("gi.lpv.*", LeftOutReason::NotNeeded,
                              !m_grid ? "no light or emission reaches the scene (the LPV injects only RSMs)"
                                      : "no light has shadow-atlas layers and the scene has no emission");
        return addBlack(graph, in.frame);
    }

    // A black indirect image (the lookup with an empty grid would read nothing).
    rg::ImageHandle addBlack(rg::RenderGraph& graph, const FrameData& frame) {
        ImageDesc desc;
        desc.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        desc.width = frame.width;
        desc.height = frame.height;
        desc.usage = VK_IMAGE_USAGE_STORAGE_BIT;
        rg::ImageHandle out = graph.createImage("gi.lpv.indirect", desc);
        graph.addPass(
            "gi.lpv.black", [&](rg::PassBuilder& b) { out = b.write(out, rg::Access::TransferWrite); },
            [=](rg::PassContext& ctx) {
                VkClearColorValue black{};
                VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
                vkCmdClearColorImage(ctx.cmd(), ctx.image(out).image, ctx.layout(out), &black, 1, &range);
            });
        return out;
    }

    // The kept volume for `cells` x `format`; true when (re)allocated (contents undefined).
    bool ensureCache(glm::ivec3 cells, VkFormat format) {
        if (m_cache.cells == cells && m_cache.format == format)
            return false;
        if (m_cache.cells != glm::ivec3(0))
            vkDeviceWaitIdle(m_ctx.device());
        destroyCache();
        for (int c = 0; c < 3; ++c)
            m_cache.accumulation[c].image =
                createImage(m_ctx, lpv::shImageDesc(cells, format), accumulationName(c).c_str());
        if (m_settings.damping > 0.0f)
            m_cache.channelSum.image = createImage(m_ctx, lpv::shImageDesc(cells, format), "gi.lpv.accumulation.sum");
        BufferDesc desc{lpv::injectionBufferBytes(cells),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT};
        m_cache.injectionBuffer.buffer = createBuffer(m_ctx, desc, "gi.lpv.injection");
        m_cache.cells = cells;
        m_cache.format = format;
        m_cache.valid = false;
        return true;
    }

    // The kept volumes imported into this frame's graph.
    KeptVolumes importCache(rg::RenderGraph& graph) {
        KeptVolumes kept;
        for (int c = 0; c < 3; ++c)
            kept.accumulation.channel[c] = graph.importImage(accumulationName(c), m_cache.accumulation[c]);
        kept.injectionBuffer = graph.importBuffer("gi.lpv.injection", m_cache.injectionBuffer);
        if (m_cache.channelSum.image.image)
            kept.channelSum = graph.importImage("gi.lpv.accumulation.sum", m_cache.channelSum);
        return kept;
    }

    static std::string accumulationName(int channel) { return "gi.lpv.accumulation." + std::string(1, "rgb"[channel]); }

    void destroyCache() {
        for (rg::PersistentImage& image : m_cache.accumulation)
            if (image.image.image)
                destroyImage(m_ctx, image.image);
        if (m_cache.channelSum.image.image)
            destroyImage(m_ctx, m_cache.channelSum.image);
        if (m_cache.injectionBuffer.buffer.buffer)
            destroyBuffer(m_ctx, m_cache.injectionBuffer.buffer);
        m_cache = {};
    }

    Context& m_ctx;
    LpvSettings m_settings;
    uint32_t m_emitterResolution = 0; // texels per side of an emitter proxy's cube face
    lpv::Propagator m_propagator;
    lpv::Injector m_injector;
    std::optional<gpu::LpvGrid> m_grid; // fitted to the lit region (also what cascadeCount weighs)
    uint32_t m_fittedCells = 0;         // m_grid's cells per axis (lpv::fittedCells)
    Aabb m_region;                      // the lit region
    std::vector<EmitterPointSource> m_emitters; // the emission's proxies (empty without emission)
    bool m_sceneHasLights = false;
    SceneVoxelGrid m_voxels; // the bounce's grid (multi-bounce on)
    // The accumulated SH volume and injection buffer (its header holds the flux unit M) of the
    // single-grid case, kept across frames.
    struct Cache {
        std::array<rg::PersistentImage, 3> accumulation;
        rg::PersistentImage channelSum; // R + G + B of `accumulation` (the damping's input; only with damping)
        rg::PersistentBuffer injectionBuffer;
        glm::ivec3 cells{0};
        VkFormat format = VK_FORMAT_UNDEFINED;
        gpu::LpvGrid grid{};
        bool valid = false; // holds the propagated light of `grid`
    } m_cache;
};

} // namespace

Result<std::unique_ptr<TechniqueModule>> createLpvTechnique(Context& ctx, const GiSettings& settings) {
    if (auto ok = validate(settings.lpv); !ok)
        return ok.error();
    auto propagator = lpv::Propagator::create(ctx);
    if (!propagator)
        return propagator.error();
    auto injector = lpv::Injector::create(ctx);
    if (!injector) {
        propagator->destroy(ctx);
        return injector.error();
    }
    return std::unique_ptr<TechniqueModule>(new LpvTechnique(ctx, settings.lpv, settings.shadowMapSize, *propagator, *injector));
}

} // namespace vkgi::gi
