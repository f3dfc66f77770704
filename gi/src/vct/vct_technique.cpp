// Voxel cone tracing as a GiSystem technique: owns the voxel grid and the VCT volumes, re-fits
// them when a scene is uploaded, and adds the voxel + VCT passes to each frame's graph. The
// grid is also published on the blackboard (VoxelGridData) for other techniques. With
// VctSettings::levels > 1 it owns one grid and VCT volumes per clipmap level instead, placed
// around the camera every frame (docs/vct.md "Clipmap").
#include "vct/vct_technique.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "vct/vct_passes.hpp"
#include "voxel/scene_voxel_grid.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

namespace {

// One clipmap level: a grid of voxels settings.voxel * 2^l around the camera, and its VCT volumes.
struct ClipLevel {
    std::unique_ptr<VoxelGrid> grid;
    std::unique_ptr<VctVolumes> volumes;
    glm::ivec3 cell{0};  // the grid's min corner in its own voxels
    bool placed = false; // `cell` holds where the grid was last voxelized
    VoxelUpdate update = VoxelUpdate::Full;
    bool lit = false;    // the volumes (and its layers of the clipmap volume) hold its voxel light
};

// Object-space bounds of each mesh of `scene`.
std::vector<Aabb> meshBounds(const Scene& scene) {
    std::vector<Aabb> bounds(scene.meshes.size());
    for (size_t m = 0; m < scene.meshes.size(); ++m)
        for (const glm::vec3& p : scene.meshes[m].positions)
            bounds[m].extend(p);
    return bounds;
}

// World bounds of the static draws (one per scene instance, same order): the clipmap's levels
// skip draws that cannot touch the box they voxelize. Dynamic draws move between uploads and
// keep invalid bounds (never skipped).
void setStaticDrawBounds(const Scene& scene, const std::vector<Aabb>& meshBounds, std::vector<VoxelDraw>& draws) {
    for (size_t i = 0; i < draws.size() && i < scene.instances.size(); ++i) {
        const Instance& inst = scene.instances[i];
        if (draws[i].dynamic || inst.mesh >= meshBounds.size() || !meshBounds[inst.mesh].valid())
            continue;
        const Aabb& b = meshBounds[inst.mesh];
        for (const glm::vec3& corner : b.corners())
            draws[i].bounds.extend(glm::vec3(inst.transform * glm::vec4(corner, 1.0f)));
    }
}

// How far ahead of the camera the clipmap levels' centres lie, in level extents, along the
// horizontal part of the view direction (docs/vct.md "Clipmap": what a camera in a large world
// sees lies ahead of it, and mostly along the ground).
constexpr float kClipAhead = 0.15f;

// kClipAhead of a level of n^3 voxels, in whole 2-voxel blocks of that level along x and z (the
// same for every level): 0 for a camera looking straight up or down.
glm::ivec3 clipAheadBlocks(const Camera& camera, uint32_t n) {
    const glm::vec2 ground(camera.forward.x, camera.forward.z);
    const float len = glm::length(ground);
    if (!(len > 1e-3f))
        return glm::ivec3(0);
    const glm::vec2 blocks = glm::round(ground * (0.5f * kClipAhead * float(n) / len));
    return glm::ivec3(int(blocks.x), 0, int(blocks.y));
}

// Min corner (in level voxels of edge `voxel`) of a level of n^3 voxels around `camera`: centred
// on the camera's position snapped to the level's 2-voxel blocks, then moved clipAheadBlocks
// ahead. A whole number of blocks, so a move shifts whole 2^3 blocks (mip 1); the levels stay
// nested (level l - 1's centre is clipAheadBlocks level-l voxels from level l's, well within the
// n/4 between their faces); and the corner moves with the position exactly as a centred level's,
// plus a step when a turn changes the blocks. Each level's voxels are centred on its own lattice
// (worldVoxelCorner), so level l's blocks and level l + 1's voxels are half a level-l voxel apart:
// nothing reads them as the same cells (a cone samples each level at its own coordinates).
glm::ivec3 clipCell(const Camera& camera, float voxel, uint32_t n) {
    glm::vec3 blocks = glm::floor(camera.position / (2.0f * voxel) + 0.5f);
    return 2 * (glm::ivec3(blocks) + clipAheadBlocks(camera, n)) - glm::ivec3(int(n / 2));
}

class VctTechnique final : public TechniqueModule {
public:
    explicit VctTechnique(Context& ctx, const VctSettings& settings)
        : m_ctx(ctx), m_requested(settings), m_settings(resolveVctLevels(settings, Aabb{}, Camera{})) {}
    ~VctTechnique() override {
        if (m_grid || !m_levels.empty())
            vkDeviceWaitIdle(m_ctx.device()); // persistent volumes may still be read by the last frame
        m_levels.clear();
        if (m_clipmap.image.image)
            destroyImage(m_ctx, m_clipmap.image);
    }

    Result<void> sceneChanged(Context& ctx, const Scene& scene, const GpuScene& gpu, bool uploaded) override {
        m_draws = voxelDraws(gpu);
        if (uploaded)
            m_meshBounds = meshBounds(scene); // the geometry only changes with an upload
        setStaticDrawBounds(scene, m_meshBounds, m_draws);
        m_lightCount = gpu.lightCount;
        if (!uploaded)
            return {}; // what moved arrives as PassSelection::changes with the next frame
        m_settings = resolveVctLevels(m_requested, scene.bounds(), scene.cameraOrDefault());
        if (m_settings.levels > 1)
            return createClipmap(ctx, scene);
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
        if (m_grid || !m_levels.empty())
            vkDeviceWaitIdle(ctx.device());
        m_volumes.reset();
        m_grid.reset();
        m_levels.clear(); // the last scene's clipmap (automatic levels)
        if (m_clipmap.image.image)
            destroyImage(ctx, m_clipmap.image);
        m_clipmap = {};
        params->dims.z = 1u; // the half-voxel bits the trace's skipped segments read (gi/voxel_grid.h)
        params->dims.w = m_settings.prefilter == VctPrefilter::On ? 1u : 0u; // the fill
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
        if (!m_levels.empty())
            return addClipmapPasses(graph, in);
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
            options.shadowSampler = sd->pointSampler;
            options.shadowWindow = 0; // the grid's box (shadowWindows)
        }
        VctOutputs out = addVctPasses(graph, *m_volumes, grid, scene.lights, m_lightCount, settings, &g, options);
        in.blackboard.add(out);
        // Soft shadows: the cone-traced direct image replaces the deferred pass's (whose shadow-map
        // visibility it replaces, vct_soft_shadow.comp); the composite and the direct output read it.
        return {out.indirect, settings.ambientOcclusion ? out.indirect : rg::ImageHandle{},
                settings.glossy ? out.glossy : rg::ImageHandle{}, out.direct};
    }

    // The voxel light's shadow-map visibility reads the atlas inside the grid: one window per
    // clipmap level (the level's box this frame, the same cell addClipmapPasses places it at), or
    // the fitted grid's box. A window no finer than the light's whole-scene layer is not made.
    std::vector<Aabb> shadowWindows(const FrameData& frame) const override {
        if (m_settings.occlusion != VctOcclusion::ShadowMap)
            return {};
        if (m_grid) {
            const gpu::VoxelGridParams& p = m_grid->params();
            Aabb box;
            box.min = glm::vec3(p.originSize);
            box.max = box.min + p.originSize.w * float(p.dims.x);
            return {box};
        }
        std::vector<Aabb> boxes;
        const uint32_t n = m_settings.gridResolution;
        for (const ClipLevel& level : m_levels) {
            const float voxel = level.grid->params().originSize.w;
            Aabb box;
            box.min = worldVoxelCorner(clipCell(frame.camera, voxel, n), voxel);
            box.max = box.min + voxel * float(n);
            boxes.push_back(box);
        }
        return boxes;
    }

    uint64_t persistentBytes() const override {
        uint64_t bytes = (m_grid ? m_grid->bytes() : 0) + (m_volumes ? m_volumes->bytes() : 0);
        for (const ClipLevel& level : m_levels)
            bytes += level.grid->bytes() + level.volumes->bytes();
        if (m_clipmap.image.image)
            bytes += imageBytes(m_clipmap.image.desc);
        return bytes;
    }

private:
    // Levels of settings.gridResolution^3 voxels of voxel * 2^l, placed at the first frame. Only
    // the finest voxel sets a length scale (the radiance scale); the scene's bounds set none.
    Result<void> createClipmap(Context& ctx, const Scene& scene) {
        if (!m_levels.empty() || m_grid)
            vkDeviceWaitIdle(ctx.device());
        m_levels.clear();
        m_volumes.reset(); // the last scene's fitted grid (automatic levels)
        m_grid.reset();
        if (m_clipmap.image.image)
            destroyImage(ctx, m_clipmap.image);
        m_clipmap = {};
        const uint32_t n = m_settings.gridResolution;
        const float finest = vctFinestVoxel(m_settings);
        // One radiance scale for all levels: the finest voxels hold the brightest radiance.
        const float scale = chooseRadianceScale(sceneMaxRadiance(scene, finest));
        for (uint32_t l = 0; l < m_settings.levels; ++l) {
            const float voxel = std::ldexp(finest, int(l));
            gpu::VoxelGridParams params{};
            params.originSize = glm::vec4(glm::vec3(0.0f), voxel);
            params.scales = glm::vec4(1.0f / voxel, scale, 1.0f / scale, 0.0f);
            // The half-voxel bits (the trace's skipped segments), and the fill unless it is off.
            params.dims = glm::uvec4(n, uint32_t(std::countr_zero(n)), 1u, m_settings.prefilter != VctPrefilter::Off);
            ClipLevel level;
            auto grid = VoxelGrid::create(ctx, params);
            if (!grid)
                return grid.error();
            level.grid = std::move(*grid);
            auto volumes = VctVolumes::create(ctx, *level.grid);
            if (!volumes)
                return volumes.error();
            level.volumes = std::move(*volumes);
            level.volumes->litState(); // created now, so that the memory report counts them from the start
            level.volumes->bounceState();
            m_levels.push_back(std::move(level));
        }
        ImageDesc d;
        d.type = VK_IMAGE_TYPE_2D;
        d.format = VK_FORMAT_R16G16B16A16_SFLOAT;
        d.width = d.height = n;
        d.arrayLayers = GI_VCT_DIRECTIONS * n * m_settings.levels;
        d.mipLevels = m_levels[0].volumes->directionalLevels();
        d.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        m_clipmap.image = createImage(ctx, d, "vct.clipmap");
        return {};
    }

    // The clipmap's frame: per level, the voxel and VCT passes (named "...@l") if its origin
    // moved, an object moved or a light changed, its copy into the clipmap volume, then the
    // per-pixel passes through the clipmap.
    IndirectOutputs addClipmapPasses(rg::RenderGraph& graph, const TechniqueInputs& in) {
        const FrameData& frame = in.frame;
        const GBufferData& gbuffer = in.gbuffer;
        PassSelection& selection = in.selection;
        const SceneChanges& changes = selection.changes;
        const uint32_t n = m_settings.gridResolution;
        VctSettings settings = m_settings;
        if (settings.glossy && !selection.features.metallic && !selection.request.glossy) {
            settings.glossy = false;
            selection.leaveOut("gi.vct.trace:glossy-cone", LeftOutReason::NotNeeded, "no metallic material");
        }
        VctPassOptions options{true, selection.features.emissive};
        options.glossyImage = selection.request.glossy;
        if (!options.glossyImage)
            selection.leaveOut("gi.vct.trace:glossy-image", LeftOutReason::NotNeeded,
                               "the glossy image is not requested");
        options.shadowAtlas = in.shadow.atlas;
        options.shadowViews = in.shadow.views;
        options.lightShadows = in.shadow.lightShadows;
        options.shadowSampler = in.shadow.pointSampler;
        VoxelSceneHandles handles{in.scene.vertices, in.scene.indices, in.scene.instances, in.scene.materials,
                                  m_draws};
        const VoxelUpdate sceneUpdate = voxelUpdateFor(changes);
        rg::ImageHandle clipmap = graph.importImage("gi.vct.clipmap", m_clipmap);
        gpu::VctClipmapParams params{};
        params.info = glm::uvec4(uint32_t(m_levels.size()), n, 0u, 0u);
        const glm::ivec3 cell0 = clipCell(frame.camera, m_levels[0].grid->params().originSize.w, n);
        for (uint32_t l = 0; l < m_levels.size(); ++l) {
            const glm::ivec3 cell = clipCell(frame.camera, m_levels[l].grid->params().originSize.w, n);
            // Level l's corner is worldVoxelCorner(cell, 2^l v): its voxels are centred on their own
            // lattice, half a level-l voxel against half a finest one.
            const glm::vec3 corner = glm::vec3(cell * (1 << l) - cell0) - 0.5f * float((1 << l) - 1);
            params.level[l] = glm::vec4(corner, float(1u << l));
        }
        // The second bounce of a level gathers through the clipmap volume into the coarser levels,
        // so the levels are lit coarsest first: a level's gathers find the coarser levels' layers
        // complete (first and second bounce) and its own first bounce, copied in before them.
        const rg::BufferHandle clipParams = addClipmapParamsPass(graph, params);
        rg::ImageHandle occupancy[2];
        for (uint32_t l = uint32_t(m_levels.size()); l-- > 0;) {
            ClipLevel& level = m_levels[l];
            const float voxel = level.grid->params().originSize.w;
            const glm::ivec3 cell = clipCell(frame.camera, voxel, n);
            const bool moved = !level.placed || cell != level.cell;
            std::optional<glm::ivec3> move;
            if (moved) {
                // What both corners cover is kept, unless the level was never voxelized
                // (addVoxelGridPasses decides whether it can be).
                if (level.placed && level.update == VoxelUpdate::None)
                    move = cell - level.cell;
                level.grid->setCell(cell);
                level.cell = cell;
                level.placed = true;
                level.update = VoxelUpdate::Full;
            }
            const std::string at = "@" + std::to_string(l);
            const VoxelUpdate update = std::max(level.update, sceneUpdate);
            if (update == VoxelUpdate::None)
                selection.leaveOut("gi.voxel.*" + at, LeftOutReason::NotDirty,
                                   "level " + std::to_string(l) + "'s origin did not move and no object moved");
            else if (update == VoxelUpdate::Dynamic)
                selection.leaveOut("gi.voxel.*.static" + at, LeftOutReason::NotDirty, "no static object moved");
            const bool relight = !level.lit || update != VoxelUpdate::None || changes.anyLight();
            if (!relight) {
                std::string why = "level " + std::to_string(l) +
                                  " did not move and no light or object changed since it was lit";
                for (const std::string pass : {"gi.vct.light", "gi.vct.mip[*]", "gi.vct.bounce*", "gi.vct.clip.lit",
                                                "gi.vct.clip.lit3", "gi.vct.clip.copy"})
                    if ((settings.bounces >= 2 || (pass != "gi.vct.bounce*" && pass != "gi.vct.clip.lit")) &&
                        (settings.bounces >= 3 || pass != "gi.vct.clip.lit3"))
                        selection.leaveOut(pass + at, LeftOutReason::NotDirty, why);
            } else if (!selection.features.emissive) {
                selection.leaveOut("gi.vct.light:emission" + at, LeftOutReason::NotNeeded, "no emissive material");
            }
            graph.setPassNameSuffix(at);
            // A moved static object makes the kept content stale too.
            if (sceneUpdate == VoxelUpdate::Full)
                move.reset();
            VoxelGridData grid = addVoxelGridPasses(graph, *level.grid, handles, update, move);
            level.update = VoxelUpdate::None;
            if (l == 0)
                in.blackboard.add(grid); // the finest level stands for the grid
            if (l < 2)
                occupancy[l] = grid.normal; // the trace's skipped segments (VctClipmapHandles)
            if (relight) {
                // A move alone keeps the light of the voxels both corners cover; a light or an
                // object change relights the level whole.
                VctPassOptions levelOptions = options;
                levelOptions.saveLit = true;
                levelOptions.clipmap = &clipmap;
                levelOptions.clipParams = clipParams;
                levelOptions.clipLevel = l;
                levelOptions.shadowWindow = l; // the level's box (shadowWindows)
                if (move && sceneUpdate == VoxelUpdate::None && !changes.anyLight() && level.lit &&
                    glm::all(glm::lessThan(glm::abs(*move), glm::ivec3(int(n))))) {
                    levelOptions.shifted = true;
                    levelOptions.shift = *move;
                }
                VctOutputs lit = addVctPasses(graph, *level.volumes, grid, in.scene.lights, m_lightCount, settings,
                                              nullptr, levelOptions);
                clipmap = addClipmapCopyPass(graph, lit.directional, clipmap, l, n,
                                             level.volumes->directionalLevels());
                level.lit = true;
            }
            graph.setPassNameSuffix("");
        }
        if (m_settings.bounces < 2)
            selection.leaveOut("gi.vct.bounce*", LeftOutReason::NotNeeded, "vct.bounces = 1");
        VctClipmapHandles clip{clipmap, clipParams, {occupancy[0], occupancy[1]}};
        VctGBufferHandles g{gbuffer.position, gbuffer.normal, gbuffer.albedo,       gbuffer.emission,
                            frame.width,      frame.height,   frame.camera.position};
        VctOutputs out =
            addVctClipmapTracePasses(graph, *m_levels[0].volumes, clip, settings, g, options.glossyImage);
        in.blackboard.add(out);
        return {out.indirect, settings.ambientOcclusion ? out.indirect : rg::ImageHandle{},
                settings.glossy ? out.glossy : rg::ImageHandle{}, rg::ImageHandle{}};
    }

    Context& m_ctx;
    VctSettings m_requested; // as the caller gave them (levels may be 0: automatic)
    VctSettings m_settings;  // levels resolved for the current scene
    std::unique_ptr<VoxelGrid> m_grid;
    std::unique_ptr<VctVolumes> m_volumes;
    std::vector<VoxelDraw> m_draws;
    std::vector<Aabb> m_meshBounds; // object-space bounds per mesh of the uploaded scene
    uint32_t m_lightCount = 0;
    VoxelUpdate m_update = VoxelUpdate::Full; // Full until a new grid's first frame
    bool m_lit = false;                       // the volumes hold the voxel light of the current grid
    std::vector<ClipLevel> m_levels;          // levels > 1: the clipmap levels, finest first
    rg::PersistentImage m_clipmap;            // levels > 1: the levels' directional volumes stacked
};

} // namespace

Result<std::unique_ptr<TechniqueModule>> createVctTechnique(Context& ctx, const VctSettings& settings) {
    auto valid = validateVctSettings(settings);
    if (!valid)
        return valid.error();
    return std::unique_ptr<TechniqueModule>(new VctTechnique(ctx, settings));
}

} // namespace vkgi::gi
