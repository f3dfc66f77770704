// Voxel cone tracing as a GiSystem technique: owns the voxel grid and the VCT volumes, re-fits
// them when a scene is uploaded, and adds the voxel + VCT passes to each frame's graph. The
// grid is also published on the blackboard (VoxelGridData) for other techniques.
#include "voxel/vct_technique.hpp"

#include <memory>

#include "voxel/voxel_graph.hpp"

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
        m_draws.clear();
        for (const GpuDraw& d : gpu.draws)
            m_draws.push_back({d.instance, d.firstIndex, d.indexCount / 3, d.vertexOffset, d.dynamic});
        m_lightCount = gpu.lightCount;
        if (!uploaded) {
            m_update = m_update == VoxelUpdate::Full ? VoxelUpdate::Full : VoxelUpdate::Dynamic;
            return {};
        }
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
        return {};
    }

    void addPasses(rg::RenderGraph& graph, rg::Blackboard& bb) override {
        const FrameData& frame = bb.get<FrameData>();
        const SceneHandles& scene = bb.get<SceneHandles>();
        const GBufferData& gbuffer = bb.get<GBufferData>();
        if (!m_grid) {
            bb.add(IndirectData{});
            return;
        }
        VoxelSceneHandles handles{scene.vertices, scene.indices, scene.instances, scene.materials, m_draws};
        VoxelGridData grid = addVoxelGridPasses(graph, *m_grid, handles, m_update);
        m_update = VoxelUpdate::None;
        bb.add(grid);
        VctGBufferHandles g{gbuffer.position, gbuffer.normal, gbuffer.albedo, frame.width, frame.height,
                            frame.camera.position};
        VctOutputs out = addVctPasses(graph, *m_volumes, grid, scene.lights, m_lightCount, m_settings, &g);
        bb.add(IndirectData{out.indirect, {}});
        bb.add(out);
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
    VoxelUpdate m_update = VoxelUpdate::Full;
};

} // namespace

Result<std::unique_ptr<TechniqueModule>> createVctTechnique(Context& ctx, const VctSettings& settings) {
    auto valid = validateVctSettings(settings);
    if (!valid)
        return valid.error();
    return std::unique_ptr<TechniqueModule>(new VctTechnique(ctx, settings));
}

} // namespace vkgi::gi
