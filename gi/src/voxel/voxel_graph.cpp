#include "voxel/voxel_graph.hpp"

#include <bit>
#include <optional>
#include <string>
#include <vector>

#include "vkgi/rg/compute_pass.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi {

using rg::Access;

namespace {

struct VolumeHandles {
    rg::ImageHandle albedo, normal, emission, faces;
};

VolumeHandles importVolumes(rg::RenderGraph& graph, VoxelVolumes& v, const char* prefix) {
    std::string p = prefix;
    return {graph.importImage(p + ".albedo", v.albedo), graph.importImage(p + ".normal", v.normal),
            graph.importImage(p + ".emission", v.emission), graph.importImage(p + ".faces", v.faces)};
}

// Empties touched list `list`: header (0, 1, 1, 0), no groups and no voxels yet, dispatch
// y = z = 1 (disjoint fills); with `accum` also zeroes the accumulation and the touched bits
// (transfer fills stream at memset speed, the first voxelization's N^3 records).
void fillClear(const rg::PassContext& ctx, rg::BufferHandle list, rg::BufferHandle accum, rg::BufferHandle bits,
               bool clearAccum) {
    VkCommandBuffer cmd = ctx.cmd();
    if (clearAccum) {
        vkCmdFillBuffer(cmd, ctx.buffer(accum).buffer, 0, VK_WHOLE_SIZE, 0);
        vkCmdFillBuffer(cmd, ctx.buffer(bits).buffer, 0, VK_WHOLE_SIZE, 0);
    }
    VkBuffer l = ctx.buffer(list).buffer;
    vkCmdFillBuffer(cmd, l, 0, sizeof(uint32_t), 0);
    vkCmdFillBuffer(cmd, l, sizeof(uint32_t), 2 * sizeof(uint32_t), 1);
    vkCmdFillBuffer(cmd, l, 3 * sizeof(uint32_t), sizeof(uint32_t), 0);
}

// Starts a voxelization into `target`: empties touched list `list` (its handle updated), zeroes
// the accumulation on the first voxelization, and the whole target volumes unless `keepTarget`
// (addClearStale then zeroes what the new voxelization leaves out). Transfer writes.
void addClear(rg::RenderGraph& graph, rg::BufferHandle& accum, rg::BufferHandle& bits, rg::BufferHandle& list,
              VolumeHandles& target, bool clearAccum, bool keepTarget, const char* name) {
    graph.addPass(
        name,
        [&](rg::PassBuilder& b) {
            if (clearAccum) {
                accum = b.write(accum, Access::TransferWrite);
                bits = b.write(bits, Access::TransferWrite);
            }
            list = b.write(list, Access::TransferWrite);
            if (!keepTarget)
                for (rg::ImageHandle* h : {&target.albedo, &target.normal, &target.emission, &target.faces})
                    *h = b.write(*h, Access::TransferWrite);
        },
        [list, accum, bits, clearAccum, keepTarget, t = target](rg::PassContext& ctx) {
            fillClear(ctx, list, accum, bits, clearAccum);
            if (keepTarget)
                return;
            VkClearColorValue zero{};
            VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            for (rg::ImageHandle h : {t.albedo, t.normal, t.emission, t.faces})
                vkCmdClearColorImage(ctx.cmd(), ctx.image(h).image, ctx.layout(h), &zero, 1, &range);
        });
}

// Between a voxelization into `target` and the listing of its touched bits: zeroes the voxels
// of `previous` (the list of the last voxelization into the same volumes) whose bit is not set.
void addClearStale(rg::RenderGraph& graph, const VoxelGrid& grid, rg::BufferHandle bits, rg::BufferHandle previous,
                   VolumeHandles& target, const char* name) {
    rg::ComputePass(graph, name, grid.pipelines().clearStale)
        .push(gpu::VoxelGridPush{grid.params()})
        .read(VOXEL_STALE_BINDING_TOUCHED_BITS, bits)
        .write(VOXEL_STALE_BINDING_ALBEDO, target.albedo)
        .write(VOXEL_STALE_BINDING_NORMAL, target.normal)
        .write(VOXEL_STALE_BINDING_EMISSION, target.emission)
        .write(VOXEL_STALE_BINDING_FACES, target.faces)
        .read(VOXEL_STALE_BINDING_PREVIOUS, previous)
        .dispatchIndirect(previous);
}

// The accumulation records at VOXEL_ACC_BINDING_RECORDS + k (voxel_acc.glsl): ranges of one
// buffer, which rg::ComputePass cannot bind (it binds whole buffers), so the passes that read
// them are recorded through a PassContext.
void appendRecords(std::vector<DescriptorItem>& items, const rg::PassContext& ctx, const VoxelGrid& grid,
                   rg::BufferHandle accum) {
    for (uint32_t k = 0; k < GI_VOXEL_ACC_SLABS; ++k) {
        DescriptorItem item = ctx.buffer(VOXEL_ACC_BINDING_RECORDS + k, accum);
        item.buffer.offset = grid.accumulationRangeOffset(k);
        item.buffer.range = grid.accumulationRangeBytes();
        items.push_back(item);
    }
}

// Averages the accumulated sums of the voxels in `list` into `target` (handles updated to their
// new versions; the other voxels keep the clear's zeros) and zeroes those records. A side
// effect: the zeroed accumulation is what the next voxelization relies on, even when nothing
// reads this grid. Records ranges of the accumulation: see appendRecords.
void addResolve(rg::RenderGraph& graph, VoxelGrid& grid, rg::BufferHandle& accum, rg::BufferHandle list,
                VolumeHandles& target, const char* name, bool commit) {
    graph.addPass(
        name,
        [&](rg::PassBuilder& b) {
            accum = b.write(accum, Access::ComputeStorageReadWrite);
            b.read(list, Access::IndirectRead);
            b.read(list, Access::ComputeStorageRead);
            for (rg::ImageHandle* h : {&target.albedo, &target.normal, &target.emission, &target.faces})
                *h = b.write(*h, Access::ComputeStorageWrite);
            b.sideEffect();
        },
        [g = &grid, accum, list, t = target, commit, planned = grid.planned()](rg::PassContext& ctx) {
            std::vector<DescriptorItem> items{ctx.storage(VOXEL_RESOLVE_BINDING_ALBEDO, t.albedo),
                                              ctx.storage(VOXEL_RESOLVE_BINDING_NORMAL, t.normal),
                                              ctx.storage(VOXEL_RESOLVE_BINDING_EMISSION, t.emission),
                                              ctx.storage(VOXEL_RESOLVE_BINDING_FACES, t.faces),
                                              ctx.buffer(VOXEL_RESOLVE_BINDING_TOUCHED, list)};
            appendRecords(items, ctx, *g, accum);
            gpu::VoxelGridPush push{g->params()};
            ctx.dispatchIndirect(g->pipelines().resolve, list, 0, &push, sizeof(push), items);
            if (commit)
                g->commitPlanned(planned); // this graph runs: its plan is the grid's state
        });
}

// A box of grid voxels, inclusive.
struct VoxelBox {
    glm::ivec3 lo, hi;
};

// Voxelizes the draws `set` into the accumulation and the touched bits: one dispatch per draw
// and box of `boxes` (the whole grid if empty; boxes must be disjoint), binding ranges of the
// accumulation (appendRecords).
void addVoxelize(rg::RenderGraph& graph, const VoxelGrid& grid, const VoxelSceneHandles& scene, rg::BufferHandle& accum,
                 rg::BufferHandle& bits, VoxelDrawSet set, const char* name, std::vector<VoxelBox> boxes = {}) {
    struct Draw {
        glm::uvec3 groups;
        gpu::VoxelizePush push;
    };
    // Row slices per triangle (voxelize.comp), for draws that fit in one work group (one CPU
    // thread otherwise; the Cornell walls): about 8 rows each for a grid-wide triangle. Draws
    // of more triangles already spread over work groups, and their triangles are mostly small:
    // slicing them only repeats each triangle's setup.
    const Pipeline& pipeline = grid.pipelines().voxelize;
    const uint32_t slices = std::max(1u, grid.resolution() / 8u);
    std::vector<Draw> draws;
    if (boxes.empty())
        boxes.push_back({glm::ivec3(0), glm::ivec3(int(grid.resolution()) - 1)});
    for (const VoxelDraw& d : scene.draws) {
        if (d.triangleCount == 0 || (set == VoxelDrawSet::Static && d.dynamic) ||
            (set == VoxelDrawSet::Dynamic && !d.dynamic))
            continue;
        bool shared = d.triangleCount <= pipeline.localSize[0];
        glm::uvec3 groups = shared ? glm::uvec3(d.triangleCount, slices, 1u)
                                   : glm::uvec3(groupCount(d.triangleCount, pipeline.localSize[0]), 1u, 1u);
        for (const VoxelBox& box : boxes) {
            if (grid.worldVoxels() && d.bounds.valid()) {
                // The box widened by a voxel (more than the voxelizer's slack and the rounding of
                // the bounds): a draw outside it has no triangle that could touch the box.
                const float v = grid.params().originSize.w;
                const glm::vec3 lo = worldVoxelCorner(grid.cell() + box.lo - 1, v);
                const glm::vec3 hi = worldVoxelCorner(grid.cell() + box.hi + 2, v);
                if (glm::any(glm::greaterThan(d.bounds.min, hi)) || glm::any(glm::lessThan(d.bounds.max, lo)))
                    continue;
            }
            gpu::VoxelizePush push{
                grid.params(),
                glm::uvec4(d.instance, d.firstIndex, d.triangleCount, std::bit_cast<uint32_t>(d.vertexOffset)),
                glm::uvec4(shared ? 1u : 0u, grid.worldVoxels() ? 1u : 0u, 0u, 0u),
                glm::ivec4(grid.worldVoxels() ? grid.cell() : glm::ivec3(0), 0),
                glm::ivec4(box.lo, 0),
                glm::ivec4(box.hi, 0)};
            draws.push_back({groups, push});
        }
    }
    VoxelSceneHandles s = scene;
    s.draws.clear();
    graph.addPass(
        name,
        [&](rg::PassBuilder& b) {
            for (rg::BufferHandle h : {s.vertices, s.indices, s.instances, s.materials})
                b.read(h, Access::ComputeStorageRead);
            accum = b.write(accum, Access::ComputeStorageReadWrite);
            bits = b.write(bits, Access::ComputeStorageReadWrite);
        },
        [g = &grid, s, accum, bits, draws = std::move(draws)](rg::PassContext& ctx) {
            std::vector<DescriptorItem> items{
                ctx.buffer(VOXELIZE_BINDING_VERTICES, s.vertices), ctx.buffer(VOXELIZE_BINDING_INDICES, s.indices),
                ctx.buffer(VOXELIZE_BINDING_INSTANCES, s.instances),
                ctx.buffer(VOXELIZE_BINDING_MATERIALS, s.materials), ctx.buffer(VOXELIZE_BINDING_TOUCHED_BITS, bits)};
            appendRecords(items, ctx, *g, accum);
            for (const Draw& d : draws)
                ctx.dispatch(g->pipelines().voxelize, d.groups, &d.push, sizeof(d.push), items);
        });
}

// Lists the voxels of the touched bits in `list` (grid order) and zeroes the bits.
void addTouchedList(rg::RenderGraph& graph, const VoxelGrid& grid, rg::BufferHandle& bits, rg::BufferHandle& list,
                    const char* name) {
    uint32_t n = grid.resolution();
    rg::ComputePass(graph, name, grid.pipelines().touchedList)
        .push(gpu::VoxelGridPush{grid.params()})
        .write(VOXEL_TOUCHED_BINDING_BITS, bits)
        .write(VOXEL_TOUCHED_BINDING_LIST, list)
        .dispatch({n * n * n / 32, 1u, 1u});
}

// Clear, voxelize and resolve of the draws `set` (All or Static) into `target`.
void addVoxelization(rg::RenderGraph& graph, VoxelGrid& grid, const VoxelSceneHandles& scene, rg::BufferHandle& accum,
                     rg::BufferHandle& bits, rg::BufferHandle& touched, VolumeHandles& target, VoxelDrawSet set,
                     bool commit) {
    bool isStatic = set == VoxelDrawSet::Static;
    VoxelizationPlan plan = grid.beginVoxelization(set);
    rg::BufferHandle previous;
    if (plan.previous >= 0)
        previous = graph.importBuffer("gi.voxel.touched.previous", grid.listState(plan.previous));
    touched = graph.importBuffer("gi.voxel.touched", grid.listState(plan.next));
    addClear(graph, accum, bits, touched, target, plan.clearAccum, previous.valid(),
             isStatic ? "gi.voxel.clear.static" : "gi.voxel.clear");
    addVoxelize(graph, grid, scene, accum, bits, set, isStatic ? "gi.voxel.voxelize.static" : "gi.voxel.voxelize");
    if (previous.valid())
        addClearStale(graph, grid, bits, previous, target, isStatic ? "gi.voxel.stale.static" : "gi.voxel.stale");
    addTouchedList(graph, grid, bits, touched, isStatic ? "gi.voxel.list.static" : "gi.voxel.list");
    addResolve(graph, grid, accum, touched, target, isStatic ? "gi.voxel.resolve.static" : "gi.voxel.resolve", commit);
}

// The dynamic draws' voxelization of a scene with dynamic draws: the grid starts as a copy of
// the static volumes `st`; the merge writes only the dynamic voxels outside them, so nothing of
// an earlier frame's dynamic voxels survives.
void addDynamicVoxelization(rg::RenderGraph& graph, VoxelGrid& grid, const VoxelSceneHandles& scene,
                            rg::BufferHandle& accum, rg::BufferHandle& bits, VolumeHandles st, VoxelGridData& data) {
    bool clearAccum = grid.beginVoxelization(VoxelDrawSet::Dynamic).clearAccum;
    graph.addPass(
        "gi.voxel.clear.dynamic",
        [&](rg::PassBuilder& b) {
            if (clearAccum) {
                accum = b.write(accum, Access::TransferWrite);
                bits = b.write(bits, Access::TransferWrite);
            }
            data.touchedDynamic = b.write(data.touchedDynamic, Access::TransferWrite);
            for (rg::ImageHandle h : {st.albedo, st.normal, st.emission, st.faces})
                b.read(h, Access::TransferRead);
            for (rg::ImageHandle* h : {&data.albedo, &data.normal, &data.emission, &data.faces})
                *h = b.write(*h, Access::TransferWrite);
        },
        [n = grid.resolution(), accum, bits, clearAccum, st, d = data](rg::PassContext& ctx) {
            fillClear(ctx, d.touchedDynamic, accum, bits, clearAccum);
            VkImageCopy region{};
            region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.extent = {n, n, n};
            rg::ImageHandle from[] = {st.albedo, st.normal, st.emission, st.faces};
            rg::ImageHandle to[] = {d.albedo, d.normal, d.emission, d.faces};
            for (int i = 0; i < 4; ++i)
                vkCmdCopyImage(ctx.cmd(), ctx.image(from[i]).image, ctx.layout(from[i]), ctx.image(to[i]).image,
                               ctx.layout(to[i]), 1, &region);
        });
    addVoxelize(graph, grid, scene, accum, bits, VoxelDrawSet::Dynamic, "gi.voxel.voxelize.dynamic");
    addTouchedList(graph, grid, bits, data.touchedDynamic, "gi.voxel.list.dynamic");
    graph.addPass(
        "gi.voxel.merge",
        [&](rg::PassBuilder& b) {
            accum = b.write(accum, Access::ComputeStorageReadWrite);
            b.read(data.touchedDynamic, Access::IndirectRead);
            b.read(data.touchedDynamic, Access::ComputeStorageRead);
            b.read(st.albedo, Access::ComputeStorageRead);
            for (rg::ImageHandle* h : {&data.albedo, &data.normal, &data.emission, &data.faces})
                *h = b.write(*h, Access::ComputeStorageWrite);
            b.sideEffect(); // the zeroed accumulation (addResolve)
        },
        [g = &grid, accum, st, d = data, planned = grid.planned()](rg::PassContext& ctx) {
            std::vector<DescriptorItem> items{ctx.storage(VOXEL_RESOLVE_BINDING_ALBEDO, d.albedo),
                                              ctx.storage(VOXEL_RESOLVE_BINDING_NORMAL, d.normal),
                                              ctx.storage(VOXEL_RESOLVE_BINDING_EMISSION, d.emission),
                                              ctx.storage(VOXEL_RESOLVE_BINDING_FACES, d.faces),
                                              ctx.storage(VOXEL_RESOLVE_BINDING_STATIC_ALBEDO, st.albedo),
                                              ctx.buffer(VOXEL_RESOLVE_BINDING_TOUCHED, d.touchedDynamic)};
            appendRecords(items, ctx, *g, accum);
            gpu::VoxelGridPush push{g->params()};
            ctx.dispatchIndirect(g->pipelines().resolveMerge, d.touchedDynamic, 0, &push, sizeof(push), items);
            g->commitPlanned(planned); // this graph runs: its plan is the grid's state
        });
    data.changed = true;
}

// The static or whole-scene voxelization after the grid's corner moved by `move` voxels (|move| < N):
// what both corners cover is kept (shifted to its new place), only the slabs the grid newly covers
// are voxelized. The touched list then lists the kept voxels (voxel_mark.comp) and the slabs'
// (their records, the only nonzero ones, are resolved), so it covers the volumes as a full
// voxelization's would (the mark reads the last voxelization's list, which the caller checked
// covers the volumes: plan.previous). `scratch` holds the old content while it is copied back
// shifted: the static volumes of a scene without dynamic draws, the grid's otherwise (the
// dynamic voxelization overwrites them after). `set`: All into the grid, or Static.
void addShiftedVoxelization(rg::RenderGraph& graph, VoxelGrid& grid, const VoxelSceneHandles& scene,
                            rg::BufferHandle& accum, rg::BufferHandle& bits, rg::BufferHandle& touched,
                            VolumeHandles& target, VolumeHandles& scratch, VoxelDrawSet set, glm::ivec3 move,
                            bool commit) {
    const int n = int(grid.resolution());
    const bool isStatic = set == VoxelDrawSet::Static;
    VoxelizationPlan plan = grid.beginVoxelization(set);
    grid.planVolumesOverwritten(isStatic ? 0 : 1);
    rg::BufferHandle previous = graph.importBuffer("gi.voxel.touched.previous", grid.listState(plan.previous));
    touched = graph.importBuffer("gi.voxel.touched", grid.listState(plan.next));
    graph.addPass(
        isStatic ? "gi.voxel.shift.save.static" : "gi.voxel.shift.save",
        [&](rg::PassBuilder& b) {
            for (rg::ImageHandle h : {target.albedo, target.normal, target.emission, target.faces})
                b.read(h, Access::TransferRead);
            for (rg::ImageHandle* h : {&scratch.albedo, &scratch.normal, &scratch.emission, &scratch.faces})
                *h = b.write(*h, Access::TransferWrite);
        },
        [n, from = target, to = scratch](rg::PassContext& ctx) {
            VkImageCopy region{};
            region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.extent = {uint32_t(n), uint32_t(n), uint32_t(n)};
            rg::ImageHandle src[] = {from.albedo, from.normal, from.emission, from.faces};
            rg::ImageHandle dst[] = {to.albedo, to.normal, to.emission, to.faces};
            for (int i = 0; i < 4; ++i)
                vkCmdCopyImage(ctx.cmd(), ctx.image(src[i]).image, ctx.layout(src[i]), ctx.image(dst[i]).image,
                               ctx.layout(dst[i]), 1, &region);
        });
    // Grid voxel x at the new corner was x + move at the old one.
    const glm::ivec3 srcOffset = glm::max(move, glm::ivec3(0)), dstOffset = glm::max(-move, glm::ivec3(0));
    const glm::ivec3 extent = glm::ivec3(n) - glm::abs(move);
    addClear(graph, accum, bits, touched, target, plan.clearAccum, false,
             isStatic ? "gi.voxel.clear.static" : "gi.voxel.clear");
    graph.addPass(
        isStatic ? "gi.voxel.shift.static" : "gi.voxel.shift",
        [&](rg::PassBuilder& b) {
            for (rg::ImageHandle h : {scratch.albedo, scratch.normal, scratch.emission, scratch.faces})
                b.read(h, Access::TransferRead);
            for (rg::ImageHandle* h : {&target.albedo, &target.normal, &target.emission, &target.faces})
                *h = b.write(*h, Access::TransferWrite);
        },
        [from = scratch, to = target, srcOffset, dstOffset, extent](rg::PassContext& ctx) {
            VkImageCopy region{};
            region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            region.srcOffset = {srcOffset.x, srcOffset.y, srcOffset.z};
            region.dstOffset = {dstOffset.x, dstOffset.y, dstOffset.z};
            region.extent = {uint32_t(extent.x), uint32_t(extent.y), uint32_t(extent.z)};
            rg::ImageHandle src[] = {from.albedo, from.normal, from.emission, from.faces};
            rg::ImageHandle dst[] = {to.albedo, to.normal, to.emission, to.faces};
            for (int i = 0; i < 4; ++i)
                vkCmdCopyImage(ctx.cmd(), ctx.image(src[i]).image, ctx.layout(src[i]), ctx.image(dst[i]).image,
                               ctx.layout(dst[i]), 1, &region);
        });
    rg::ComputePass(graph, isStatic ? "gi.voxel.mark.static" : "gi.voxel.mark", grid.pipelines().mark)
        .push(gpu::VoxelMarkPush{grid.params(), glm::ivec4(move, 0)})
        .read(VOXEL_MARK_BINDING_PREVIOUS, previous)
        .write(VOXEL_MARK_BINDING_BITS, bits)
        .dispatchIndirect(previous);
    // Disjoint slabs: along each moved axis the voxels the old corner did not cover, within
    // what the earlier axes kept.
    std::vector<VoxelBox> slabs;
    VoxelBox rest{glm::ivec3(0), glm::ivec3(n - 1)};
    for (int a = 0; a < 3; ++a) {
        if (move[a] == 0)
            continue;
        VoxelBox slab = rest;
        if (move[a] > 0) {
            slab.lo[a] = n - move[a];
            rest.hi[a] = n - move[a] - 1;
        } else {
            slab.hi[a] = -move[a] - 1;
            rest.lo[a] = -move[a];
        }
        slabs.push_back(slab);
    }
    addVoxelize(graph, grid, scene, accum, bits, set,
                isStatic ? "gi.voxel.voxelize.slab.static" : "gi.voxel.voxelize.slab", slabs);
    addTouchedList(graph, grid, bits, touched, isStatic ? "gi.voxel.list.static" : "gi.voxel.list");
    addResolve(graph, grid, accum, touched, target, isStatic ? "gi.voxel.resolve.static" : "gi.voxel.resolve", commit);
}

} // namespace

VoxelGridData addVoxelGridPasses(rg::RenderGraph& graph, VoxelGrid& grid, const VoxelSceneHandles& scene,
                                 VoxelUpdate update, std::optional<glm::ivec3> move) {
    VolumeHandles out = importVolumes(graph, grid.volumesState(), "gi.voxel.grid");
    VoxelGridData data{out.albedo, out.normal, out.emission, out.faces, grid.params()};
    bool anyDynamic = false;
    for (const VoxelDraw& d : scene.draws)
        anyDynamic = anyDynamic || (d.dynamic && d.triangleCount > 0);
    if (anyDynamic)
        data.touchedDynamic = graph.importBuffer("gi.voxel.touched.dynamic", grid.touchedState(VoxelDrawSet::Dynamic));
    // Without dynamic draws the grid only changes with the scene: a Dynamic update has nothing to do.
    if (update == VoxelUpdate::None || (update == VoxelUpdate::Dynamic && !anyDynamic)) {
        data.touched = graph.importBuffer("gi.voxel.touched", grid.touchedState(VoxelDrawSet::All));
        return data;
    }
    grid.startPlanning();
    // After a move of the grid, the static (or whole-scene) content is kept where both corners
    // cover it if the target volumes (0: the grid's, 1: the static ones) hold the last such
    // voxelization, whose list covers them.
    auto shiftable = [&](int target) {
        return update == VoxelUpdate::Full && move && grid.planned().cover[target] >= 0 &&
               glm::all(glm::lessThan(glm::abs(*move), glm::ivec3(int(grid.resolution()))));
    };
    rg::BufferHandle accum = graph.importBuffer("gi.voxel.accumulation", grid.accumulationState());
    rg::BufferHandle bits = graph.importBuffer("gi.voxel.touched_bits", grid.touchedBitsState());
    if (!anyDynamic) {
        // Static scene: one voxelization straight into the grid (no static copy, no merge).
        if (shiftable(0)) {
            VolumeHandles scratch = importVolumes(graph, grid.staticState(), "gi.voxel.static");
            addShiftedVoxelization(graph, grid, scene, accum, bits, data.touched, out, scratch, VoxelDrawSet::All,
                                   *move, true);
        } else {
            addVoxelization(graph, grid, scene, accum, bits, data.touched, out, VoxelDrawSet::All, true);
        }
        return {out.albedo, out.normal, out.emission, out.faces, grid.params(), true, data.touched};
    }
    VolumeHandles st = importVolumes(graph, grid.staticState(), "gi.voxel.static");
    if (shiftable(1)) {
        // The grid's volumes are the scratch: the dynamic voxelization below overwrites them with
        // the static volumes anyway.
        addShiftedVoxelization(graph, grid, scene, accum, bits, data.touched, st, out, VoxelDrawSet::Static, *move,
                               false);
        data.albedo = out.albedo;
        data.normal = out.normal;
        data.emission = out.emission;
        data.faces = out.faces;
    } else if (update == VoxelUpdate::Full)
        addVoxelization(graph, grid, scene, accum, bits, data.touched, st, VoxelDrawSet::Static, false);
    else
        data.touched = graph.importBuffer("gi.voxel.touched", grid.touchedState(VoxelDrawSet::Static));
    addDynamicVoxelization(graph, grid, scene, accum, bits, st, data);
    return data;
}

} // namespace vkgi::gi
