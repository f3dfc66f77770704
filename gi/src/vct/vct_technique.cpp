// Voxel cone tracing as a GiSystem technique: owns the voxel grid and the VCT volumes, re-fits
// them when a scene is uploaded, and adds the voxel + VCT passes to each frame's graph. The
// grid is also published on the blackboard (VoxelGridData) for other techniques.
#include "vct/vct_technique.hpp"

#include <algorithm>
#include <memory>

#include "vct/vct_passes.hpp"
#include "voxel/scene_voxel_grid.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

class VctTechnique final : public TechniqueModule {
public:
    explicit VctTechnique(Context& ctx, const VctSettings& settings) : m_ctx(ctx), m_settings(settings) {}
    ~VctTechnique() override {
        if (m_grid)
            vkDeviceWaitIdle(m_ctx.device()); // persistent volumes may still be read by the last frame
    }

    Result<void> sceneChanged(Context& ctx, const Scene& scene, const GpuScene& gpu, bool uploaded) override {
        m_draws = voxelDraws(gpu);
        m_lightCount = gpu.lightCount;
        if (!uploaded)
            return {}; // what moved arrives as PassSelection::changes with the next frame
        Aabb box = m_settings.gridBox ? *m_settings.gridBox : scene.bounds();
        if (!box.valid()) { // empty scene: a unit box keeps every pass well-defined (all voxels empty)
            box.extend(glm::vec3(-0.5f));
            box.extend(glm::vec3(0.5f));
        }
        auto fitted = fitVoxelGrid(box, m_settings.gridResolution, 1.0f);
        if (!fitted)
            return fitted.error();
        float scale = chooseRadianceScale(sceneMaxRadiance(scene, fitted->originSize.w));
        auto params = fitVoxelGrid(box, m_settings.gridResolution, scale);
        if (!params)
            return params.error();
        if (m_grid)
            vkDeviceWaitIdle(ctx.device());
        m_volumes.reset();
        m_grid.reset();
        auto grid = VoxelGrid::create(ctx, *params);
        if (!grid)
            return grid.error();
        m_grid = std::move(*grid);
        auto volumes = VctVolumes::create(ctx, *m_grid);
        if (!volumes)
            return volumes.error();
        m_volumes = std::move(*volumes);
        m_update = VoxelUpdate::Full;
        m_lit = false;
        return {};
    }

    IndirectOutputs addPasses(rg::RenderGraph& graph, const TechniqueInputs& in) override {
        const FrameData& frame = in.frame;
        const SceneHandles& scene = in.scene;
        const GBufferData& gbuffer = in.gbuffer;
        if (!m_grid)
            return {};
        PassSelection& selection = in.selection;
        const SceneChanges& changes = selection.changes;
        // A moved static object invalidates the static bake; a moved dynamic one only itself.
        VoxelUpdate update = std::max(m_update, voxelUpdateFor(changes));
        if (update == VoxelUpdate::None)
            selection.leaveOut("gi.voxel.*", LeftOutReason::NotDirty, "no object moved since the grid was voxelized");
        else if (update == VoxelUpdate::Dynamic)
            selection.leaveOut("gi.voxel.*.static", LeftOutReason::NotDirty, "no static object moved");
        // Voxel light, mips and bounce depend on the grid and the lights only, not on the camera.
        bool relight = !m_lit || update != VoxelUpdate::None || changes.anyLight();
        if (!relight) {
            std::string why = "no light or object changed since the voxels were lit";
            selection.leaveOut("gi.vct.light", LeftOutReason::NotDirty, why);
            selection.leaveOut("gi.vct.mip[*]", LeftOutReason::NotDirty, why);
            if (m_settings.bounces >= 2)
                selection.leaveOut("gi.vct.bounce*", LeftOutReason::NotDirty, why);
        }
        if (m_settings.bounces < 2)
            selection.leaveOut("gi.vct.bounce*", LeftOutReason::NotNeeded, "vct.bounces = 1");
        if (relight && !selection.features.emissive)
            selection.leaveOut("gi.vct.light:emission", LeftOutReason::NotNeeded, "no emissive material");
        // The trace weights the glossy cone by metallic: without a metallic material it adds 0
        // (unless the glossy image itself is asked for).
        VctSettings settings = m_settings;
        if (settings.glossy && !selection.features.metallic && !selection.request.glossy) {
            settings.glossy = false;
            selection.leaveOut("gi.vct.trace:glossy-cone", LeftOutReason::NotNeeded, "no metallic material");
        }
        VoxelSceneHandles handles{scene.vertices, scene.indices, scene.instances, scene.materials, m_draws};
        VoxelGridData grid = addVoxelGridPasses(graph, *m_grid, handles, update);
        m_update = VoxelUpdate::None;
        m_lit = true;
        in.blackboard.add(grid);
        VctGBufferHandles g{gbuffer.position, gbuffer.normal, gbuffer.albedo,       gbuffer.emission,
                            frame.width,      frame.height,   frame.camera.position};
        VctPassOptions options{relight, selection.features.emissive};
        options.glossyImage = selection.request.glossy;
        if (!options.glossyImage)
            selection.leaveOut("gi.vct.trace:glossy-image", LeftOutReason::NotNeeded,
                               "the glossy image is not requested");
        if (const ShadowData* sd = &in.shadow) {
            options.shadowAtlas = sd->atlas;
            options.shadowViews = sd->views;
            options.lightShadows = sd->lightShadows;
            options.shadowSampler = sd->compareSampler;
        }
        VctOutputs out = addVctPasses(graph, *m_volumes, grid, scene.lights, m_lightCount, settings, &g, options);
        in.blackboard.add(out);
        // Soft shadows: the cone-traced direct image replaces the deferred pass's (whose shadow-map
        // visibility it replaces, vct_soft_shadow.comp); the composite and the direct output read it.
        return {out.indirect, settings.ambientOcclusion ? out.indirect : rg::ImageHandle{},
                settings.glossy ? out.glossy : rg::ImageHandle{}, out.direct};
    }

    uint64_t persistentBytes() const override {
        return (m_grid ? m_grid->bytes() : 0) + (m_volumes ? m_volumes->bytes() : 0);
    }

private:
    Context& m_ctx;
    VctSettings m_settings;
    std::unique_ptr<VoxelGrid> m_grid;
    std::unique_ptr<VctVolumes> m_volumes;
    std::vector<VoxelDraw> m_draws;
    uint32_t m_lightCount = 0;
    VoxelUpdate m_update = VoxelUpdate::Full; // Full until a new grid's first frame
    bool m_lit = false;                       // the volumes hold the voxel light of the current grid
};

} // namespace

Result<std::unique_ptr<TechniqueModule>> createVctTechnique(Context& ctx, const VctSettings& settings) {
    auto valid = validateVctSettings(settings);
    if (!valid)
        return valid.error();
    return std::unique_ptr<TechniqueModule>(new VctTechnique(ctx, settings));
}

} // namespace vkgi::gi
