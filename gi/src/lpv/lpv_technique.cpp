// Technique::Lpv: per frame, inject the shared RSM into a grid fitted to the lit part of the
// scene, build the geometry volume from the RSM and the camera's G-buffer, propagate (with
// reflection at the shared voxel grid's occupied voxels when bounces are on), and look the
// accumulated light up per pixel. Everything is a transient of the frame graph except the voxel
// grid, which is persistent and re-voxelized only when the scene changed.
#include "lpv/lpv_technique.hpp"

#include <optional>
#include <string>
#include <vector>

#include "gi/frame_data.hpp"
#include "lpv/lpv_grid.hpp"
#include "lpv/lpv_inject.hpp"
#include "lpv/lpv_passes.hpp"
#include "lpv/lpv_volume.hpp"
#include "voxel/voxel_graph.hpp"
#include "voxel/voxel_grid.hpp"

namespace vkgi::gi {

namespace {

// Voxel grid resolution for the bounce: twice the LPV's (so trilinear sampling at a cell centre
// averages the 2^3 voxels inside it), a power of two in the voxelizer's range.
uint32_t voxelResolutionFor(uint32_t lpvCells) {
    uint32_t r = GI_VOXEL_MIN_RESOLUTION;
    while (r < 2 * lpvCells && r < 128u) // 128^3 RGBA8 x 3 volumes = 24 MiB: the module budget's limit
        r *= 2;
    return r;
}

class LpvTechnique final : public TechniqueModule {
public:
    LpvTechnique(Context& ctx, const LpvSettings& settings, lpv::Propagator propagator, lpv::Injector injector)
        : m_ctx(ctx), m_settings(settings), m_propagator(propagator), m_injector(injector) {}
    ~LpvTechnique() override {
        m_voxels.reset();
        m_propagator.destroy(m_ctx);
        m_injector.destroy(m_ctx);
    }

    bool needsRsm() const override { return true; }

    Result<void> sceneChanged(Context& ctx, const Scene& scene, const GpuScene& gpu, bool uploaded) override {
        m_grid.reset();
        m_directional = false;
        for (const Light& l : scene.lights)
            m_directional = m_directional || l.type == LightType::Directional;
        Aabb region = lpv::litRegion(gpu.bounds, scene.lights);
        if (region.valid()) {
            auto grid = lpv::fitLpvGrid(region, m_settings.gridSize);
            if (!grid)
                return grid.error();
            m_grid = *grid;
        }
        m_draws.clear();
        for (const GpuDraw& d : gpu.draws)
            m_draws.push_back({d.instance, d.firstIndex, d.indexCount / 3, d.vertexOffset, d.dynamic});
        if (m_settings.bounces && gpu.bounds.valid() && (uploaded || !m_voxels)) {
            auto params = fitVoxelGrid(gpu.bounds, voxelResolutionFor(m_settings.gridSize), 1.0f);
            if (!params)
                return params.error();
            auto voxels = VoxelGrid::create(ctx, *params);
            if (!voxels)
                return voxels.error();
            m_voxels = std::move(*voxels);
            m_voxelUpdate = VoxelUpdate::Full;
        } else if (m_voxels && m_voxelUpdate == VoxelUpdate::None) {
            m_voxelUpdate = VoxelUpdate::Dynamic;
        }
        return {};
    }

    void addPasses(rg::RenderGraph& graph, rg::Blackboard& bb) override {
        const FrameData& frame = bb.get<FrameData>();
        const GBufferData& gbuffer = bb.get<GBufferData>();
        const RsmData* rsmData = bb.tryGet<RsmData>();
        lpv::GBufferInput gb{gbuffer.position, gbuffer.normal, gbuffer.albedo, frame.width, frame.height};
        if (!m_grid || !rsmData || rsmData->layers.empty()) {
            bb.add(IndirectData{addBlack(graph, frame), {}});
            return;
        }
        const VkFormat format = m_settings.halfFloat ? VK_FORMAT_R16G16B16A16_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT;
        lpv::RsmInput rsm{rsmData->position, rsmData->normal, rsmData->flux, rsmData->resolution,
                          uint32_t(rsmData->layers.size())};
        lpv::VoxelInput voxels;
        if (m_voxels) {
            const SceneHandles& scene = bb.get<SceneHandles>();
            VoxelGridData grid = addVoxelGridPasses(
                graph, *m_voxels, {scene.vertices, scene.indices, scene.instances, scene.materials, m_draws},
                m_voxelUpdate);
            m_voxelUpdate = VoxelUpdate::None;
            voxels = {grid.albedo, grid.normal, grid.params.originSize, grid.params.dims.x};
        }
        // One grid fitted to the lit region, or (directional light, cascades > 1) nested grids
        // following the camera.
        std::vector<gpu::LpvGrid> grids{*m_grid};
        if (m_settings.cascades > 1 && m_directional) {
            // The coarsest level spans twice the lit region, so it covers it from any camera inside.
            float finest = 2.0f * m_grid->origin.w / float(1u << (m_settings.cascades - 1));
            grids = lpv::fitCascades(frame.camera.position, glm::normalize(frame.camera.forward), finest,
                                     m_settings.gridSize, m_settings.cascades);
        }
        rg::ImageHandle indirect;
        for (size_t k = 0; k < grids.size(); ++k) {
            const gpu::LpvGrid& grid = grids[k];
            const glm::ivec3 cells(grid.size);
            const std::string prefix = k == 0 ? "gi.lpv" : "gi.lpv.c" + std::to_string(k);
            lpv::InjectionResult injected = lpv::addInjectionPasses(
                graph, m_injector, grid, format, rsm, lpv::createShVolume(graph, (prefix + ".wave.a").c_str(), cells, format),
                lpv::createShVolume(graph, (prefix + ".accumulation").c_str(), cells, format), {}, prefix);
            rg::ImageHandle gv;
            if (m_settings.occlusion)
                gv = lpv::addGeometryVolumePasses(graph, m_injector, grid, rsm, gb, prefix);
            lpv::PropagationVolumes volumes{injected.wavefront,
                                            lpv::createShVolume(graph, (prefix + ".wave.b").c_str(), cells, format),
                                            injected.accumulation};
            volumes = lpv::addPropagationPasses(graph, m_propagator, cells, format, volumes, gv, m_settings.iterations,
                                                voxels, grid.origin, prefix);
            lpv::CascadeBlend blend;
            blend.fadeBorder = grids.size() > 1;
            blend.accumulate = k > 0;
            for (size_t j = k >= 2 ? k - 2 : 0; j < k; ++j)
                blend.finer.push_back(grids[j]);
            indirect = lpv::addLookupPass(graph, m_injector, grid, volumes.accumulation, injected.buffer, gb,
                                          m_settings.damping, indirect, blend, prefix);
        }
        bb.add(IndirectData{indirect, {}});
    }

    uint64_t persistentBytes() const override { return m_voxels ? uint64_t(m_voxels->bytes()) : 0; }

private:
    // No lit geometry: a black indirect image (the lookup with an empty grid would read nothing).
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

    Context& m_ctx;
    LpvSettings m_settings;
    lpv::Propagator m_propagator;
    lpv::Injector m_injector;
    std::optional<gpu::LpvGrid> m_grid;
    bool m_directional = false;
    std::unique_ptr<VoxelGrid> m_voxels;
    std::vector<VoxelDraw> m_draws;
    VoxelUpdate m_voxelUpdate = VoxelUpdate::None;
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
    return std::unique_ptr<TechniqueModule>(new LpvTechnique(ctx, settings.lpv, *propagator, *injector));
}

} // namespace vkgi::gi
