// The voxel cone tracing passes (list, voxel light, mips, second bounce, soft shadows, trace):
// each compute pass declared, bound and dispatched in one place (rg::ComputePass).
#include "vct/vct_passes.hpp"

#include <algorithm>
#include <string>

#include "vkgi/rg/compute_pass.hpp"
#include "vk_check.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

using rg::Access;

namespace {

// The voxels a moved clipmap level keeps (VctPassOptions::shift): lo .. hi inclusive, empty
// (lo > hi) when the level did not move.
struct KeepBox {
    glm::ivec4 lo{1 << 20, 1 << 20, 1 << 20, 0};
    glm::ivec4 hi{-1, -1, -1, 0};
};

KeepBox keepBox(const VctPassOptions& options, uint32_t n) {
    KeepBox box;
    if (options.shifted) {
        box.lo = glm::ivec4(glm::max(-options.shift, glm::ivec3(0)), 0);
        box.hi = glm::ivec4(glm::ivec3(int(n) - 1) - glm::max(options.shift, glm::ivec3(0)), 0);
    }
    return box;
}

// Adds one pass per level k >= 1 of the directional volume, built from level k - 1, up to the
// tail, and one for the tail's levels ("prefix[t-L]"); returns the newest version. Level 1 is
// written at the listed occupied blocks only and keeps the zeros elsewhere (gi.vct.list.clear /
// .stale; no discard).
// With `jobs` (and the grid's normal volume) the level-1 pass also lists the second bounce's
// jobs into it.
// `keep`: the bounce blocks around kept voxels list no job (VoxelMipPush).
rg::ImageHandle addMipPasses(rg::RenderGraph& graph, const VctVolumes& v, rg::ImageHandle directional,
                             rg::BufferHandle list, const char* prefix, rg::BufferHandle* jobs = nullptr,
                             rg::ImageHandle normal = {}, rg::ImageHandle faces = {}, KeepBox keep = {}) {
    const VctVolumes::Pipelines& p = v.pipelines();
    const gpu::VoxelGridParams& params = v.grid().params();
    uint32_t tail = v.mipTailLevel(), last = v.directionalLevels() - 1;
    for (uint32_t level = 1; level <= std::min(tail, last); ++level) {
        uint32_t count = level == tail ? last - tail + 1 : 1;
        std::string name = std::string(prefix) + "[" + std::to_string(level) +
                           (count > 1 ? "-" + std::to_string(last) : std::string()) + "]";
        uint32_t size = std::max(1u, v.grid().resolution() >> level);
        gpu::VoxelMipPush push{params, glm::uvec4(level, size, 0u, 0u), keep.lo, keep.hi};
        const rg::SubresourceRange source = rg::SubresourceRange::mip(level - 1);
        if (level == 1 && jobs) { // the listed occupied blocks, and the bounce jobs (voxel_mip_body.glsl)
            rg::ComputePass(graph, name, p.mipListJobs)
                .push(push)
                .read(VCT_MIP_BINDING_SOURCE, directional, source)
                .write(VCT_MIP_BINDING_TARGET, directional, rg::SubresourceRange::mip(1))
                .read(VCT_MIP_BINDING_LIST, list)
                .read(VCT_MIP_BINDING_NORMAL, normal)
                .read(VCT_MIP_BINDING_FACES, faces)
                .write(VCT_MIP_BINDING_JOBS, *jobs)
                .dispatchIndirect(list, GI_VOXEL_LIST_BLOCKS * sizeof(uint32_t));
        } else if (level == 1) { // the listed occupied blocks only (voxel_mip_body.glsl)
            rg::ComputePass(graph, name, p.mipList)
                .push(push)
                .read(VCT_MIP_BINDING_SOURCE, directional, source)
                .write(VCT_MIP_BINDING_TARGET, directional, rg::SubresourceRange::mip(1))
                .read(VCT_MIP_BINDING_LIST, list)
                .dispatchIndirect(list, GI_VOXEL_LIST_BLOCKS * sizeof(uint32_t));
        } else if (level == tail) { // this level and all coarser ones, four at most
            VKGI_ASSERT(count <= 4, "the mip tail has at most four levels");
            push.info.z = count;
            // Tail bindings past the last level are bound to the last level and not touched.
            rg::ImageHandle levels[4] = {directional, directional, directional, directional};
            rg::ComputePass pass(graph, name, p.mipTail);
            pass.push(push).read(VCT_MIP_BINDING_SOURCE, directional, source);
            for (uint32_t i = 0; i < 4; ++i)
                pass.overwrite(VCT_MIP_BINDING_TAIL + i, levels[i],
                               rg::SubresourceRange::mip(std::min(level + i, last)));
            pass.dispatchGroups({1u, 1u, 1u});
            directional = levels[0];
        } else {
            rg::ComputePass(graph, name, p.mip)
                .push(push)
                .read(VCT_MIP_BINDING_SOURCE, directional, source)
                .overwrite(VCT_MIP_BINDING_TARGET, directional, rg::SubresourceRange::mip(level))
                .dispatch(glm::uvec3(size));
        }
    }
    return directional;
}

// Once per voxelization: the occupied-voxel list the light and bounce passes run over. The
// voxel light writes only the listed voxels' views, the level-1 mip only the listed blocks, and
// the rest must read empty: the first voxelization zeroes levels 0 and 1 (and the record of
// what they hold) by transfer clears, later ones only what went stale (gi.vct.list.stale, after
// the list is built). The list header and bits are zeroed here.
// `shifted` (VctPassOptions::shift): the grid moved and its saved level 0 is copied back
// shifted after the list (addShiftPass). The clear then zeroes levels 0 and 1 and the written
// record as at the first voxelization, and there is no stale pass, which would compare the last
// list's bits (at the old corner) with the new ones: the written bits are left unknown, and the
// next relight without a shift starts from the cleared state again (writtenKnown false).
void addListPasses(rg::RenderGraph& graph, VctVolumes& volumes, const VoxelGridData& grid, rg::BufferHandle& list,
                   rg::ImageHandle& directional, rg::ImageHandle& written, bool shifted) {
    const VctVolumes::Pipelines& p = volumes.pipelines();
    const uint32_t n = volumes.grid().resolution();
    const gpu::VoxelGridPush push{volumes.grid().params()};
    rg::BufferHandle writtenBits = graph.importBuffer("gi.vct.written_bits", volumes.writtenBitsState());
    const rg::SubresourceRange levels01{0, 2, 0, rg::kAll};
    const bool first = !volumes.writtenKnown(), clearLevels = first || shifted;
    graph.addPass(
        "gi.vct.list.clear",
        [&](rg::PassBuilder& b) {
            list = b.write(list, Access::TransferWrite);
            if (clearLevels) {
                directional = b.write(directional, Access::TransferWrite, levels01);
                written = b.write(written, Access::TransferWrite);
            }
            if (first)
                writtenBits = b.write(writtenBits, Access::TransferWrite);
        },
        [n, list, directional, written, writtenBits, first, clearLevels](rg::PassContext& ctx) {
            VkCommandBuffer cmd = ctx.cmd();
            VkBuffer l = ctx.buffer(list).buffer;
            VkDeviceSize slots = VkDeviceSize(n) * n * n + (n / 2) * (n / 2) * (n / 2);
            vkCmdFillBuffer(cmd, l, 0, GI_VOXEL_LIST_HEADER * sizeof(uint32_t), 0);
            vkCmdFillBuffer(cmd, l, (GI_VOXEL_LIST_HEADER + slots) * sizeof(uint32_t), VK_WHOLE_SIZE, 0);
            if (first)
                vkCmdFillBuffer(cmd, ctx.buffer(writtenBits).buffer, 0, VK_WHOLE_SIZE, 0);
            if (!clearLevels)
                return;
            VkClearColorValue zero{};
            VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            vkCmdClearColorImage(cmd, ctx.image(written).image, ctx.layout(written), &zero, 1, &all);
            // Level 0 whole; level 1 only the first N/2 layers of each direction, the ones it uses.
            VkImageSubresourceRange ranges[1 + GI_VCT_DIRECTIONS];
            ranges[0] = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, VK_REMAINING_ARRAY_LAYERS};
            for (uint32_t d = 0; d < GI_VCT_DIRECTIONS; ++d)
                ranges[1 + d] = {VK_IMAGE_ASPECT_COLOR_BIT, 1, 1, d * n, n / 2};
            vkCmdClearColorImage(cmd, ctx.image(directional).image, ctx.layout(directional), &zero,
                                 1 + GI_VCT_DIRECTIONS, ranges);
        });
    // One pass per touched list of the grid (the whole scene's or the static draws', then the
    // dynamic draws'), each an indirect dispatch over its list setting the list's occupancy
    // bits, then one pass listing the set bits in grid order.
    for (rg::BufferHandle touched : {grid.touched, grid.touchedDynamic}) {
        if (!touched.valid())
            continue;
        rg::ComputePass(graph, touched == grid.touched ? "gi.vct.list" : "gi.vct.list.dynamic", p.compact)
            .push(push)
            .read(VCT_COMPACT_BINDING_TOUCHED, touched)
            .write(VCT_COMPACT_BINDING_LIST, list)
            .dispatchIndirect(touched);
    }
    uint32_t words = (n * n * n + (n / 2) * (n / 2) * (n / 2)) / 32; // voxel and block bit words
    rg::ComputePass(graph, "gi.vct.list.append", p.listAppend)
        .push(push)
        .write(VCT_APPEND_BINDING_LIST, list)
        .dispatch({words, 1u, 1u});
    volumes.setListBuilt(true);
    if (shifted) {
        volumes.setWrittenKnown(false);
        return;
    }
    rg::ImageHandle level1 = directional; // both levels become this pass's version
    rg::ComputePass(graph, "gi.vct.list.stale", p.listStale)
        .push(push)
        .read(VCT_STALE_BINDING_LIST, list)
        .write(VCT_STALE_BINDING_WRITTEN_BITS, writtenBits)
        .write(VCT_STALE_BINDING_WRITTEN, written)
        .write(VCT_STALE_BINDING_LEVEL0, directional, rg::SubresourceRange::mip(0))
        .write(VCT_STALE_BINDING_LEVEL1, level1, rg::SubresourceRange::mip(1))
        .dispatch({gpu::voxelWrittenBitsWords(n), 1u, 1u});
    volumes.setListBuilt(true);
    volumes.setWrittenKnown(true);
}

// "gi.vct.shift", a moved clipmap level (VctPassOptions::shift = d): the saved level 0
// (VctVolumes::litState) copied back into level 0 of the directional volume, which the list's
// clear zeroed, moved by -d: grid voxel c at the new corner was c + d at the old one. The voxel
// light then restores the kept voxels' written record and lights the new ones; level 1 is
// rebuilt at the listed blocks from the zeros.
void addShiftPass(rg::RenderGraph& graph, const VctVolumes& volumes, glm::ivec3 d, rg::ImageHandle lit,
                  rg::ImageHandle& directional) {
    const uint32_t n = volumes.grid().resolution();
    graph.addPass(
        "gi.vct.shift",
        [&](rg::PassBuilder& b) {
            b.read(lit, Access::TransferRead);
            directional = b.write(directional, Access::TransferWrite, rg::SubresourceRange::mip(0));
        },
        [n, d, lit, directional](rg::PassContext& ctx) {
            const glm::ivec3 src = glm::max(d, glm::ivec3(0)), dst = glm::max(-d, glm::ivec3(0));
            const glm::ivec3 extent = glm::ivec3(int(n)) - glm::abs(d);
            // View v of axis k: layer v N + c_k, 2D coordinates the other two axes in order
            // (vctDirectionalTexel).
            VkImageCopy regions[GI_VCT_DIRECTIONS];
            for (uint32_t v = 0; v < GI_VCT_DIRECTIONS; ++v) {
                const int k = int(v >> 1u), a = k == 0 ? 1 : 0, b = k == 2 ? 1 : 2;
                regions[v] = {{VK_IMAGE_ASPECT_COLOR_BIT, 0, v * n + uint32_t(src[k]), uint32_t(extent[k])},
                              {src[a], src[b], 0},
                              {VK_IMAGE_ASPECT_COLOR_BIT, 0, v * n + uint32_t(dst[k]), uint32_t(extent[k])},
                              {dst[a], dst[b], 0},
                              {uint32_t(extent[a]), uint32_t(extent[b]), 1}};
            }
            vkCmdCopyImage(ctx.cmd(), ctx.image(lit).image, ctx.layout(lit), ctx.image(directional).image,
                           ctx.layout(directional), GI_VCT_DIRECTIONS, regions);
        });
}

// "gi.vct.lit.save": level 0 of the directional volume as the voxel light left it into the saved
// copy a later move shifts (VctVolumes::litState).
void addLitSavePass(rg::RenderGraph& graph, VctVolumes& volumes, rg::ImageHandle directional, rg::ImageHandle lit) {
    const uint32_t n = volumes.grid().resolution();
    graph.addPass(
        "gi.vct.lit.save",
        [&](rg::PassBuilder& b) {
            b.read(directional, Access::TransferRead, rg::SubresourceRange::mip(0));
            lit = b.write(lit, Access::TransferWrite);
        },
        [n, lit, directional](rg::PassContext& ctx) {
            const uint32_t layers = GI_VCT_DIRECTIONS * n;
            VkImageCopy region{{VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, layers},
                               {0, 0, 0},
                               {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, layers},
                               {0, 0, 0},
                               {n, n, 1}};
            vkCmdCopyImage(ctx.cmd(), ctx.image(directional).image, ctx.layout(directional), ctx.image(lit).image,
                           ctx.layout(lit), 1, &region);
        });
    volumes.setLitKnown(true);
}

// "gi.vct.light": grid volumes + lights (+ the emission volume unless `options.emission` is
// false) -> the six level-0 views of the directional volume at the listed voxels (indirect over
// the list); reads and updates the written volume. The shadow-atlas variant with
// VctOcclusion::ShadowMap and an atlas, else the ray march of `settings.occlusion`.
void addLightPass(rg::RenderGraph& graph, const VctVolumes& volumes, const VoxelGridData& grid, rg::BufferHandle lights,
                  uint32_t lightCount, const VctSettings& settings, const VctPassOptions& options,
                  rg::BufferHandle list, rg::ImageHandle& directional, rg::ImageHandle& written) {
    const VctVolumes::Pipelines& p = volumes.pipelines();
    bool useShadowMap = settings.occlusion == VctOcclusion::ShadowMap && options.shadowAtlas.valid();
    bool soft = !useShadowMap && settings.occlusion == VctOcclusion::RayMarchSoft;
    uint32_t mode = settings.occlusion == VctOcclusion::RayMarchSoft ? GI_VCT_OCCLUSION_SOFT : GI_VCT_OCCLUSION_HARD;
    // The voxels both corners cover may keep their shifted views (voxel_light_body.glsl), but
    // not with the shadow atlas, which follows the camera.
    const KeepBox keep = useShadowMap ? KeepBox{} : keepBox(options, volumes.grid().resolution());
    gpu::VoxelLightPush push{volumes.grid().params(),
                             glm::uvec4(lightCount, mode, options.emission ? GI_VOXEL_LIGHT_EMISSION : 0u,
                                        options.shadowWindow == ~0u ? 0u : options.shadowWindow + 1u),
                             keep.lo, keep.hi};
    rg::ComputePass pass(graph, "gi.vct.light", useShadowMap ? p.lightShadowMap : soft ? p.lightSoft : p.light);
    pass.push(push);
    if (useShadowMap)
        pass.sample(VCT_LIGHT_BINDING_SHADOW_ATLAS, options.shadowAtlas, options.shadowSampler)
            .read(VCT_LIGHT_BINDING_SHADOW_VIEWS, options.shadowViews)
            .read(VCT_LIGHT_BINDING_LIGHT_SHADOWS, options.lightShadows);
    pass.read(VCT_LIGHT_BINDING_LIST, list).read(VCT_LIGHT_BINDING_LIGHTS, lights);
    // Only the soft march filters the occupancy; the others load texels.
    if (soft)
        pass.sample(VCT_LIGHT_BINDING_OCCUPANCY, grid.albedo, volumes.occupancySampler());
    else
        pass.read(VCT_LIGHT_BINDING_OCCUPANCY, grid.albedo);
    pass.read(VCT_LIGHT_BINDING_FACES, grid.faces)
        .read(VCT_LIGHT_BINDING_EMISSION, grid.emission)
        .write(VCT_LIGHT_BINDING_WRITTEN, written)
        .write(VCT_LIGHT_BINDING_DIRECTIONAL, directional, rg::SubresourceRange::mip(0)); // the listed voxels
    if (!useShadowMap && !soft)
        pass.readTexels(VCT_LIGHT_BINDING_LIST_WORDS, list, volumes.listWords());
    pass.dispatchIndirect(list);
}

// Second bounce: one gather per (block, normal class), its misfit voxels one each
// (gi/vct_passes.h), into level 0 of the directional volume at the listed voxels, then its mips
// again; `jobs` is the job list the level-1 mip built.
// With `options.saveLit` (clipmap levels) every listed voxel's bounce is kept for the next move
// (VctVolumes::bounceState); a moved level (`keep` not empty) copies it back shifted
// ("gi.vct.bounce.shift") and its kept voxels take it instead of the gathers, whose blocks around
// them list no job (addMipPasses).
// Bounce `bounce` = 3 gathers again over the radiance the second left in `directional` and adds
// only the third bounce (voxel_bounce_apply.comp); `voxels` holds the per-voxel bounce volume
// and the kept copy the second bounce's passes made, which the third reads. Pass names carry the
// bounce index from the third on ("gi.vct.bounce3.*").
struct BounceVoxels {
    rg::BufferHandle results; // the gathers' results
    rg::ImageHandle bounce;   // each listed voxel's bounce (stored when kept or subtracted later)
    rg::ImageHandle kept;     // a moved level's bounce of before the move, shifted
    rg::ImageHandle keptStandIn; // bound as `kept` when no voxel is kept (VctVolumes::keptStandIn)
};
rg::ImageHandle addBouncePasses(rg::RenderGraph& graph, VctVolumes& volumes, const VoxelGridData& grid,
                                const gpu::ConeParams& cones, rg::BufferHandle list, rg::BufferHandle& jobs,
                                rg::ImageHandle directional, const VctPassOptions& options, KeepBox keep,
                                uint32_t bounce, uint32_t bounces, BounceVoxels& voxels) {
    const VctVolumes::Pipelines& p = volumes.pipelines();
    const std::string prefix = bounce == 2 ? "gi.vct.bounce" : "gi.vct.bounce" + std::to_string(bounce);
    const gpu::VoxelBouncePush push{volumes.grid().params(), cones,
                                    glm::uvec4(options.clipLevel, bounce > 2 ? 1u : 0u, 0u, 0u)};
    // A clipmap level's gathers read the clipmap volume, into which the caller copied this level's
    // first bounce (addVctPasses), and its parameters.
    const bool clip = options.clipmap != nullptr;
    const rg::ImageHandle source = clip ? *options.clipmap : directional;
    if (bounce == 2)
        voxels.results = graph.importBuffer("gi.vct.bounce.results", volumes.bounceResultsState());
    rg::BufferHandle& results = voxels.results;
    rg::BufferHandle gatherArgs = jobs; // the gathers' dispatch, before they append the misfits
    rg::ComputePass gathers(graph, prefix + ".blocks", clip ? p.bounceClip : p.bounce);
    gathers.push(push)
        .sample(VCT_CONE_BINDING_DIRECTIONAL, source, volumes.sampler())
        .read(VCT_BOUNCE_BINDING_NORMAL, grid.normal)
        .read(VCT_BOUNCE_BINDING_FACES, grid.faces)
        .write(VCT_BOUNCE_BINDING_JOBS, jobs) // the misfit list
        .write(VCT_BOUNCE_BINDING_RESULTS, results)
        .read(VCT_BOUNCE_BINDING_LIST, list);
    if (clip)
        gathers.read(VCT_TRACE_BINDING_CLIPMAP, options.clipParams);
    gathers.dispatchIndirect(gatherArgs);
    ImageDesc bounceDesc;
    bounceDesc.type = VK_IMAGE_TYPE_3D;
    bounceDesc.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    bounceDesc.width = bounceDesc.height = bounceDesc.depth = volumes.grid().resolution();
    // The misfits first: they read level 0 of the first bounce, which the apply then adds to.
    // Only the misfit voxels are written; the apply reads no others.
    rg::ImageHandle light = graph.createImage(prefix + ".light", bounceDesc);
    rg::ComputePass misfits(graph, prefix + ".misfits", clip ? p.bounceMisfitsClip : p.bounceMisfits);
    misfits.push(push)
        .sample(VCT_CONE_BINDING_DIRECTIONAL, source, volumes.sampler())
        .read(VCT_MISFITS_BINDING_ALBEDO, grid.albedo)
        .read(VCT_MISFITS_BINDING_NORMAL, grid.normal)
        .overwrite(VCT_MISFITS_BINDING_OUTPUT, light)
        .read(VCT_MISFITS_BINDING_JOBS, jobs);
    if (clip)
        misfits.read(VCT_TRACE_BINDING_CLIPMAP, options.clipParams);
    misfits.dispatchIndirect(jobs, GI_BOUNCE_MISFITS * sizeof(uint32_t));
    // Each voxel's bounce: kept in the clipmap levels, and stored for a third bounce to subtract;
    // otherwise the apply writes none and binds a 1^3 stand-in (no GI_VCT_APPLY_STORE).
    const bool store = options.saveLit || bounces > 2;
    if (bounce == 2) {
        ImageDesc voxelDesc = bounceDesc;
        voxelDesc.format = VK_FORMAT_R32G32B32A32_UINT; // float bits, or four sides' rgb9e5 (voxel_bounce_apply.comp)
        if (!store)
            voxelDesc.width = voxelDesc.height = voxelDesc.depth = 1;
        voxels.bounce = options.saveLit ? graph.importImage("gi.vct.bounce.voxels", volumes.bounceState())
                                        : graph.createImage("gi.vct.bounce.voxels", voxelDesc);
    }
    rg::ImageHandle& voxelBounce = voxels.bounce;
    if (bounce == 2 && keep.lo.x <= keep.hi.x) {
        ImageDesc keptDesc = bounceDesc;
        keptDesc.format = VK_FORMAT_R32G32B32A32_UINT;
        rg::ImageHandle kept = graph.createImage("gi.vct.bounce.kept", keptDesc);
        const glm::ivec3 d = options.shift, n = glm::ivec3(int(volumes.grid().resolution()));
        graph.addPass(
            "gi.vct.bounce.shift",
            [&](rg::PassBuilder& b) {
                b.read(voxelBounce, Access::TransferRead);
                kept = b.write(kept, Access::TransferWrite);
            },
            [voxelBounce, kept, d, n](rg::PassContext& ctx) {
                const glm::ivec3 src = glm::max(d, glm::ivec3(0)), dst = glm::max(-d, glm::ivec3(0)),
                                 extent = n - glm::abs(d);
                VkImageCopy region{};
                region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.srcOffset = {src.x, src.y, src.z};
                region.dstOffset = {dst.x, dst.y, dst.z};
                region.extent = {uint32_t(extent.x), uint32_t(extent.y), uint32_t(extent.z)};
                vkCmdCopyImage(ctx.cmd(), ctx.image(voxelBounce).image, ctx.layout(voxelBounce), ctx.image(kept).image,
                               ctx.layout(kept), 1, &region);
            });
        voxels.kept = kept;
    }
    // Not read unless `keep` holds voxels. A kept voxel takes its whole bounce of before the move
    // in the second bounce's apply, and adds nothing in the third's.
    if (!voxels.kept.valid() && !voxels.keptStandIn.valid())
        voxels.keptStandIn = graph.importImage("gi.vct.bounce.kept_stand_in", volumes.keptStandIn());
    const rg::ImageHandle kept = voxels.kept.valid() ? voxels.kept : voxels.keptStandIn;
    const int flags = (store ? GI_VCT_APPLY_STORE : 0) | (bounce > 2 ? GI_VCT_APPLY_ADDED : 0);
    rg::ComputePass(graph, prefix, p.bounceApply)
        .push(gpu::VoxelApplyPush{volumes.grid().params(), keep.lo, glm::ivec4(glm::ivec3(keep.hi), flags)})
        .read(VCT_APPLY_BINDING_KEPT, kept)
        .write(VCT_APPLY_BINDING_BOUNCE, voxelBounce)
        .read(VCT_APPLY_BINDING_ALBEDO, grid.albedo)
        .read(VCT_APPLY_BINDING_NORMAL, grid.normal)
        .read(VCT_APPLY_BINDING_JOBS, jobs)
        .read(VCT_APPLY_BINDING_MISFITS, light)
        .read(VCT_APPLY_BINDING_LIST, list)
        .read(VCT_APPLY_BINDING_RESULTS, results)
        .read(VCT_APPLY_BINDING_FACES, grid.faces)
        .write(VCT_APPLY_BINDING_DIRECTIONAL, directional, rg::SubresourceRange::mip(0)) // the listed voxels
        .dispatchIndirect(list);
    return addMipPasses(graph, volumes, directional, list, (prefix + ".mip").c_str());
}

// The per-pixel passes ("gi.vct.trace" and, at low resolution, the upsample and refine) through
// out.directional; `occupancy` is the grid's (clipmap: level 0's) normal volume, whose half-voxel
// bits the skipped segments read.
VctOutputs addTracePasses(rg::RenderGraph& graph, const VctVolumes& volumes, VctOutputs out,
                          const VctSettings& settings, const VctGBufferHandles& g, bool glossyImage,
                          rg::ImageHandle occupancy, const VctClipmapHandles* clip = nullptr);

// "gi.vct.shadow": direct light with cone-traced visibility through out.directional into out.direct.
// Only with VctSettings::softShadows and a G-buffer with emission.
VctOutputs addSoftShadowPass(rg::RenderGraph& graph, const VctVolumes& volumes, VctOutputs out,
                             const VctSettings& settings, const VctGBufferHandles* gbuffer, rg::BufferHandle lights,
                             uint32_t lightCount) {
    if (!settings.softShadows || !gbuffer || !gbuffer->emission.valid())
        return out;
    const VctGBufferHandles& g = *gbuffer;
    gpu::VctShadowPush push{volumes.grid().params(), volumes.coneParams(settings, g.width, g.height),
                            glm::uvec4(lightCount, g.width, g.height, 0u)};
    ImageDesc desc;
    desc.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    desc.width = g.width;
    desc.height = g.height;
    out.direct = graph.createImage("gi.vct.direct_soft", desc);
    rg::ComputePass(graph, "gi.vct.shadow", volumes.pipelines().softShadow)
        .push(push)
        .sample(VCT_CONE_BINDING_DIRECTIONAL, out.directional, volumes.sampler())
        .read(VCT_SHADOW_BINDING_POSITION, g.position)
        .read(VCT_SHADOW_BINDING_NORMAL, g.normal)
        .read(VCT_SHADOW_BINDING_ALBEDO, g.albedo)
        .read(VCT_SHADOW_BINDING_EMISSION, g.emission)
        .read(VCT_SHADOW_BINDING_LIGHTS, lights)
        .overwrite(VCT_SHADOW_BINDING_DIRECT, out.direct)
        .dispatch({g.width, g.height, 1u});
    return out;
}

// The passes every frame runs after the voxel light and mips: soft shadows and the trace.
VctOutputs addPixelPasses(rg::RenderGraph& graph, const VctVolumes& volumes, VctOutputs out,
                          const VctSettings& settings, const VctGBufferHandles* gbuffer, rg::BufferHandle lights,
                          uint32_t lightCount, bool glossyImage, rg::ImageHandle occupancy) {
    out = addSoftShadowPass(graph, volumes, out, settings, gbuffer, lights, lightCount);
    return gbuffer ? addTracePasses(graph, volumes, out, settings, *gbuffer, glossyImage, occupancy) : out;
}

} // namespace

VctOutputs addVctPasses(rg::RenderGraph& graph, VctVolumes& volumes, const VoxelGridData& grid, rg::BufferHandle lights,
                        uint32_t lightCount, const VctSettings& settings, const VctGBufferHandles* gbuffer,
                        VctPassOptions options) {
    VctOutputs out;
    rg::BufferHandle list = graph.importBuffer("gi.vct.voxel_list", volumes.listState());
    out.directional = graph.importImage("gi.vct.directional", volumes.directionalState());
    if (!options.relight) // nothing the voxel light depends on changed: the kept volume and mips
        return addPixelPasses(graph, volumes, out, settings, gbuffer, lights, lightCount, options.glossyImage,
                              grid.normal);
    // The axes whose level-0 views each voxel last stored (gi/vct_passes.h): the voxel light
    // zeroes those its faces no longer cover, gi.vct.list.stale those of emptied voxels.
    rg::ImageHandle written = graph.importImage("gi.vct.written", volumes.writtenState());
    if (options.shifted && !(volumes.litKnown() && grid.changed))
        options.shifted = false; // nothing saved to shift (or no new list): relight whole
    if (grid.changed || !volumes.listBuilt())
        addListPasses(graph, volumes, grid, list, out.directional, written, options.shifted);
    // The saved level 0, imported once (the graph tracks its layout across both uses).
    rg::ImageHandle lit;
    if (options.saveLit || options.shifted)
        lit = graph.importImage("gi.vct.lit", volumes.litState());
    if (options.shifted)
        addShiftPass(graph, volumes, options.shift, lit, out.directional);
    addLightPass(graph, volumes, grid, lights, lightCount, settings, options, list, out.directional, written);
    if (options.saveLit)
        addLitSavePass(graph, volumes, out.directional, lit);
    else
        volumes.setLitKnown(false);
    // The second bounce's jobs: the level-1 mip lists them after this clear of the header, class
    // masks and misfit bits (gi/vct_passes.h).
    rg::BufferHandle jobs;
    if (settings.bounces >= 2) {
        jobs = graph.importBuffer("gi.vct.bounce.jobs", volumes.bounceJobsState());
        graph.addPass(
            "gi.vct.bounce.jobs.clear", [&](rg::PassBuilder& b) { jobs = b.write(jobs, Access::TransferWrite); },
            [jobs, n = volumes.grid().resolution()](rg::PassContext& ctx) {
                // Header: the gathers' dispatch (x = 0, one work-group row per class), the
                // misfits' (x = 0), zero counts; then every block's class mask, the misfit bits
                // and the sums 0.
                VkBuffer buffer = ctx.buffer(jobs).buffer;
                uint32_t header[GI_BOUNCE_HEADER] = {0u, GI_BOUNCE_CLASSES, 1u, 0u, 0u, 1u, 1u, 0u};
                vkCmdUpdateBuffer(ctx.cmd(), buffer, 0, sizeof(header), header);
                vkCmdFillBuffer(ctx.cmd(), buffer, sizeof(header),
                                VkDeviceSize(gpu::bounceBlockCount(n)) * sizeof(uint32_t), 0);
                vkCmdFillBuffer(ctx.cmd(), buffer,
                                sizeof(header) + VkDeviceSize(gpu::bounceMisfitBitsOffset(n)) * sizeof(uint32_t),
                                VkDeviceSize(n * n * n / 32 + gpu::bounceGeometryWords(n)) * sizeof(uint32_t), 0);
            });
    }
    // A moved level's kept voxels keep their second bounce when the last relight kept it.
    const KeepBox keepBounce = options.saveLit && volumes.bounceKnown() && settings.bounces >= 2
                                   ? keepBox(options, volumes.grid().resolution())
                                   : KeepBox{};
    out.directional = addMipPasses(graph, volumes, out.directional, list, "gi.vct.mip", jobs.valid() ? &jobs : nullptr,
                                   grid.normal, grid.faces, keepBounce);
    if (settings.bounces >= 2) {
        gpu::ConeParams cones =
            volumes.coneParams(settings, gbuffer ? gbuffer->width : 0, gbuffer ? gbuffer->height : 0);
        BounceVoxels voxels;
        for (uint32_t bounce = 2; bounce <= settings.bounces; ++bounce) {
            // Each bounce's gathers see this level's radiance up to the bounce before.
            if (options.clipmap)
                *options.clipmap = addClipmapCopyPass(graph, out.directional, *options.clipmap, options.clipLevel,
                                                      volumes.grid().resolution(), volumes.directionalLevels(),
                                                      bounce == 2 ? "gi.vct.clip.lit" : "gi.vct.clip.lit3");
            out.directional = addBouncePasses(graph, volumes, grid, cones, list, jobs, out.directional, options,
                                              keepBounce, bounce, settings.bounces, voxels);
        }
    }
    volumes.setBounceKnown(options.saveLit && settings.bounces >= 2);
    return addPixelPasses(graph, volumes, out, settings, gbuffer, lights, lightCount, options.glossyImage,
                          grid.normal);
}

rg::BufferHandle addClipmapParamsPass(rg::RenderGraph& graph, const gpu::VctClipmapParams& params) {
    BufferDesc desc;
    desc.size = sizeof(gpu::VctClipmapParams);
    desc.usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    rg::BufferHandle buffer = graph.createBuffer("gi.vct.clip.params", desc);
    graph.addPass(
        "gi.vct.clip.params", [&](rg::PassBuilder& b) { buffer = b.write(buffer, Access::TransferWrite); },
        [buffer, params](rg::PassContext& ctx) {
            vkCmdUpdateBuffer(ctx.cmd(), ctx.buffer(buffer).buffer, 0, sizeof(params), &params);
        });
    return buffer;
}

rg::ImageHandle addClipmapCopyPass(rg::RenderGraph& graph, rg::ImageHandle directional, rg::ImageHandle clipmap,
                                   uint32_t level, uint32_t n, uint32_t mips, const char* name) {
    const uint32_t layers = GI_VCT_DIRECTIONS * n;
    const rg::SubresourceRange target{0, mips, level * layers, layers};
    graph.addPass(
        name,
        [&](rg::PassBuilder& b) {
            b.read(directional, Access::TransferRead);
            clipmap = b.write(clipmap, Access::TransferWrite, target);
        },
        [directional, clipmap, level, n, mips, layers](rg::PassContext& ctx) {
            // Level k of a view uses its stack's first N >> k layers (vct_passes.h); the copy
            // takes whole stacks, which keeps it one region per mip.
            VkImageCopy regions[9 /* log2(GI_VOXEL_MAX_RESOLUTION) + 1 */];
            for (uint32_t m = 0; m < mips; ++m) {
                uint32_t size = std::max(1u, n >> m);
                regions[m] = {{VK_IMAGE_ASPECT_COLOR_BIT, m, 0, layers},
                              {0, 0, 0},
                              {VK_IMAGE_ASPECT_COLOR_BIT, m, level * layers, layers},
                              {0, 0, 0},
                              {size, size, 1}};
            }
            vkCmdCopyImage(ctx.cmd(), ctx.image(directional).image, ctx.layout(directional),
                           ctx.image(clipmap).image, ctx.layout(clipmap), mips, regions);
        });
    return clipmap;
}

rg::ImageHandle addVctFilterPasses(rg::RenderGraph& graph, const Pipeline& pipeline, const VctGBufferHandles& g,
                                   rg::ImageHandle light, rg::ImageHandle glossy, uint32_t f, uint32_t side) {
    // The tangent-plane tolerance, a fraction of the distance to the camera: the VPL
    // reconstruction's default (VplSettings::interleaveTolerance).
    constexpr float kVctFilterTolerance = 0.02f;
    const uint32_t w = (g.width + f - 1) / f, h = (g.height + f - 1) / f;
    gpu::VctFilterPush push{glm::vec4(g.eye, kVctFilterTolerance), glm::uvec4(w, h, f, side),
                            glm::uvec4(0u, 0u, g.width, g.height)};
    ImageDesc desc;
    desc.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    desc.width = w;
    desc.height = h;
    auto pass = [&](const char* name, rg::ImageHandle input, const char* outputName) {
        rg::ImageHandle output = graph.createImage(outputName, desc);
        rg::ComputePass(graph, name, pipeline)
            .push(push)
            .read(VCT_FILTER_BINDING_POSITION, g.position)
            .read(VCT_FILTER_BINDING_NORMAL, g.normal)
            .read(VCT_FILTER_BINDING_ALBEDO, g.albedo)
            .read(VCT_FILTER_BINDING_INPUT, input)
            .read(VCT_FILTER_BINDING_GLOSSY, glossy)
            .overwrite(VCT_FILTER_BINDING_OUTPUT, output)
            .dispatch({w, h, 1u});
        return output;
    };
    rg::ImageHandle rows = pass("gi.vct.filter.rows", light, "gi.vct.filter.rows");
    push.info.x = 1u;
    push.info.y = f == 1 ? 1u : 0u;
    return pass("gi.vct.filter.columns", rows, f == 1 ? "gi.vct.indirect" : "gi.vct.incoming.filtered");
}

VctOutputs addVctClipmapTracePasses(rg::RenderGraph& graph, const VctVolumes& level0, const VctClipmapHandles& clip,
                                    const VctSettings& settings, const VctGBufferHandles& gbuffer, bool glossyImage) {
    VctOutputs out;
    out.directional = clip.volume;
    return addTracePasses(graph, level0, out, settings, gbuffer, glossyImage, clip.occupancy[0], &clip);
}

namespace {

VctOutputs addTracePasses(rg::RenderGraph& graph, const VctVolumes& volumes, VctOutputs out,
                          const VctSettings& settings, const VctGBufferHandles& g, bool glossyImage,
                          rg::ImageHandle occupancy, const VctClipmapHandles* clip) {
    const VctVolumes::Pipelines& p = volumes.pipelines();
    const Pipeline& tracePipeline = clip ? p.traceClip : p.trace;
    const Pipeline& refinePipeline = clip ? p.traceRefineClip : p.traceRefine;
    gpu::ConeParams cones = volumes.coneParams(settings, g.width, g.height);
    if (glossyImage)
        cones.info.y |= GI_VCT_FLAG_GLOSSY_IMAGE;
    const uint32_t f = settings.lowResFactor;
    const bool filter = settings.filter > 1;
    if (filter) // the trace, upsample and refine write the incoming light; the filter applies the albedo
        cones.info.y |= GI_VCT_FLAG_INCOMING | GI_VCT_FLAG_ROTATE; // and averages the cone rotations
    gpu::VctTracePush push{volumes.grid().params(), cones, glm::vec4(g.eye, settings.refineThreshold),
                           glm::uvec4(f, (g.width + f - 1) / f, (g.height + f - 1) / f, g.width * g.height)};
    push.cones.info.z = g.width;
    push.cones.info.w = g.height;
    auto image = [](uint32_t w, uint32_t h) {
        ImageDesc d;
        d.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        d.width = w;
        d.height = h;
        return d;
    };
    ImageDesc lowDesc = image(push.lowRes.y, push.lowRes.z);
    const char* traceName = f > 1 ? "gi.vct.indirect.low" : (filter ? "gi.vct.incoming" : "gi.vct.indirect");
    rg::ImageHandle indirect = graph.createImage(traceName, lowDesc);
    rg::ImageHandle glossy = graph.createImage(f == 1 ? "gi.vct.glossy" : "gi.vct.glossy.low", lowDesc);
    // The refine list of the upsample and refine, whose header the trace zeroes (at f = 1 the
    // header alone, unused: one shader for both).
    BufferDesc listDesc;
    listDesc.size = VkDeviceSize(GI_VCT_REFINE_HEADER + (f == 1 ? 0u : 2u * push.lowRes.w)) * sizeof(uint32_t);
    listDesc.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    rg::BufferHandle refineList = graph.createBuffer("gi.vct.refine_list", listDesc);
    rg::ComputePass trace(graph, "gi.vct.trace", tracePipeline);
    trace.push(push)
        .sample(VCT_CONE_BINDING_DIRECTIONAL, out.directional, volumes.sampler())
        .read(VCT_TRACE_BINDING_POSITION, g.position)
        .read(VCT_TRACE_BINDING_NORMAL, g.normal)
        .read(VCT_TRACE_BINDING_ALBEDO, g.albedo)
        .overwrite(VCT_TRACE_BINDING_INDIRECT, indirect)
        .overwrite(VCT_TRACE_BINDING_GLOSSY, glossy)
        .write(VCT_TRACE_BINDING_REFINE_LIST, refineList)
        .read(VCT_TRACE_BINDING_OCCUPANCY, occupancy);
    if (clip)
        trace.read(VCT_TRACE_BINDING_CLIPMAP, clip->params)
            .read(VCT_TRACE_BINDING_OCCUPANCY_COARSE, clip->occupancy[1]);
    trace.dispatch({push.lowRes.y, push.lowRes.z, 1u});
    if (f == 1) {
        out.indirect = filter ? addVctFilterPasses(graph, p.filter, g, indirect, glossy, 1u, settings.filter)
                              : indirect;
        out.glossy = glossy;
        return out;
    }
    // Low-res: upsample + refine list, then the listed pixels at full resolution.
    ImageDesc fullDesc = image(g.width, g.height);
    out.indirect = graph.createImage(filter ? "gi.vct.incoming" : "gi.vct.indirect", fullDesc);
    out.glossy = graph.createImage("gi.vct.glossy", fullDesc);
    // 4x4 pixel blocks from -f / 2 on (vctRefineBlockOrigin in vct_refine.glsl).
    auto blocks = [shift = f / 2u](uint32_t size) { return (size + shift + 3u) / 4u; };
    rg::ComputePass(graph, "gi.vct.upsample", p.upsample)
        .push(push)
        .read(VCT_UPSAMPLE_BINDING_POSITION, g.position)
        .read(VCT_UPSAMPLE_BINDING_NORMAL, g.normal)
        .read(VCT_UPSAMPLE_BINDING_LOW_INDIRECT, indirect)
        .read(VCT_UPSAMPLE_BINDING_LOW_GLOSSY, glossy)
        .overwrite(VCT_UPSAMPLE_BINDING_INDIRECT, out.indirect)
        .overwrite(VCT_UPSAMPLE_BINDING_GLOSSY, out.glossy)
        .write(VCT_UPSAMPLE_BINDING_REFINE_LIST, refineList)
        .read(VCT_UPSAMPLE_BINDING_ALBEDO, g.albedo)
        .dispatch({blocks(g.width), blocks(g.height), 1u});
    // Work groups counted by the upsample (header words 1..3, gi/vct_passes.h).
    rg::ComputePass refine(graph, "gi.vct.refine", refinePipeline);
    refine.push(push)
        .sample(VCT_CONE_BINDING_DIRECTIONAL, out.directional, volumes.sampler())
        .read(VCT_TRACE_BINDING_POSITION, g.position)
        .read(VCT_TRACE_BINDING_NORMAL, g.normal)
        .read(VCT_TRACE_BINDING_ALBEDO, g.albedo)
        .write(VCT_TRACE_BINDING_INDIRECT, out.indirect)
        .write(VCT_TRACE_BINDING_GLOSSY, out.glossy)
        .read(VCT_TRACE_BINDING_REFINE_LIST, refineList)
        .read(VCT_TRACE_BINDING_OCCUPANCY, occupancy);
    if (clip)
        refine.read(VCT_TRACE_BINDING_CLIPMAP, clip->params)
            .read(VCT_TRACE_BINDING_OCCUPANCY_COARSE, clip->occupancy[1]);
    refine.dispatchIndirect(refineList, sizeof(uint32_t));
    if (filter) // at full resolution, so that the refined pixels are filtered too
        out.indirect = addVctFilterPasses(graph, p.filter, g, out.indirect, out.glossy, 1u, settings.filter);
    return out;
}

} // namespace

} // namespace vkgi::gi
