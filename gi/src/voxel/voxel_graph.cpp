#include "voxel/voxel_graph.hpp"

#include <string>

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

// Starts a voxelization into `target` (`physical`: the VoxelVolumes its handles were imported
// from): empties touched list `list` (its handle updated), zeroes the accumulation on the first
// voxelization, and the whole target volumes unless `keepTarget` (addClearStale then zeroes
// what the new voxelization leaves out). Transfer writes.
void addClear(rg::RenderGraph& graph, const VoxelGrid* grid, rg::BufferHandle& accum, rg::BufferHandle& bits,
              rg::BufferHandle& list,
              VolumeHandles& target, const VoxelVolumes* physical, bool clearAccum, bool keepTarget,
              const char* name) {
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
        [grid, physical, list, clearAccum, keepTarget, t = target](rg::PassContext& ctx) {
            grid->recordClear(ctx.cmd(), ctx.buffer(list).buffer, clearAccum);
            if (!keepTarget) {
                VkImageLayout layouts[4] = {ctx.layout(t.albedo), ctx.layout(t.normal), ctx.layout(t.emission),
                                            ctx.layout(t.faces)};
                grid->recordClearVolumes(ctx.cmd(), *physical, layouts);
            }
        });
}

// Between a voxelization into `target` and the listing of its touched bits: zeroes the voxels
// of `previous` (the list of the last voxelization into the same volumes) whose bit is not set.
void addClearStale(rg::RenderGraph& graph, const VoxelGrid* grid, rg::BufferHandle bits, rg::BufferHandle previous,
                   VolumeHandles& target, const VoxelVolumes* physical, const char* name) {
    graph.addPass(
        name,
        [&](rg::PassBuilder& b) {
            b.read(bits, Access::ComputeStorageRead);
            b.read(previous, Access::IndirectRead);
            b.read(previous, Access::ComputeStorageRead);
            for (rg::ImageHandle* h : {&target.albedo, &target.normal, &target.emission, &target.faces})
                *h = b.write(*h, Access::ComputeStorageWrite);
        },
        [grid, physical, previous](rg::PassContext& ctx) {
            grid->recordClearStale(ctx.cmd(), *physical, ctx.buffer(previous).buffer);
        });
}

// Averages the accumulated sums of the voxels in `list` into `target` (handles updated to their
// new versions; the other voxels keep the clear's zeros) and zeroes those records; `physical`
// is the VoxelVolumes those handles were imported from. A side effect: the zeroed
// accumulation is what the next voxelization relies on, even when nothing reads this grid.
void addResolve(rg::RenderGraph& graph, VoxelGrid* grid, rg::BufferHandle& accum, rg::BufferHandle list,
                VolumeHandles& target, const VoxelVolumes* physical, const char* name, bool commit) {
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
        [grid, physical, list, commit, planned = grid->planned()](rg::PassContext& ctx) {
            grid->recordResolve(ctx.cmd(), *physical, ctx.buffer(list).buffer);
            if (commit)
                grid->commitPlanned(planned); // this graph runs: its plan is the grid's state
        });
}

// Voxelizes the draws `set` into the accumulation and the touched bits.
void addVoxelize(rg::RenderGraph& graph, const VoxelGrid* grid, const VoxelSceneHandles& scene, rg::BufferHandle& accum,
                 rg::BufferHandle& bits, VoxelDrawSet set, const char* name) {
    VoxelSceneHandles s = scene;
    graph.addPass(
        name,
        [&](rg::PassBuilder& b) {
            for (rg::BufferHandle h : {s.vertices, s.indices, s.instances, s.materials})
                b.read(h, Access::ComputeStorageRead);
            accum = b.write(accum, Access::ComputeStorageReadWrite);
            bits = b.write(bits, Access::ComputeStorageReadWrite);
        },
        [grid, s, set](rg::PassContext& ctx) {
            VoxelSceneBuffers buffers{ctx.buffer(s.vertices).buffer, ctx.buffer(s.indices).buffer,
                                      ctx.buffer(s.instances).buffer, ctx.buffer(s.materials).buffer, s.draws};
            grid->recordVoxelize(ctx.cmd(), buffers, set);
        });
}

// Lists the voxels of the touched bits in `list` (grid order) and zeroes the bits.
void addTouchedList(rg::RenderGraph& graph, const VoxelGrid* grid, rg::BufferHandle& bits, rg::BufferHandle& list,
                    const char* listName) {
    graph.addPass(
        listName,
        [&](rg::PassBuilder& b) {
            bits = b.write(bits, Access::ComputeStorageReadWrite);
            list = b.write(list, Access::ComputeStorageReadWrite);
        },
        [grid, list](rg::PassContext& ctx) { grid->recordTouchedList(ctx.cmd(), ctx.buffer(list).buffer); });
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
    const VoxelVolumes* physical = isStatic ? &grid.staticVolumes() : &grid.volumes();
    const VoxelGrid* g = &grid;
    addClear(graph, g, accum, bits, touched, target, physical, plan.clearAccum, previous.valid(),
             isStatic ? "gi.voxel.clear.static" : "gi.voxel.clear");
    addVoxelize(graph, g, scene, accum, bits, set, isStatic ? "gi.voxel.voxelize.static" : "gi.voxel.voxelize");
    if (previous.valid())
        addClearStale(graph, g, bits, previous, target, physical, isStatic ? "gi.voxel.stale.static" : "gi.voxel.stale");
    addTouchedList(graph, g, bits, touched, isStatic ? "gi.voxel.list.static" : "gi.voxel.list");
    addResolve(graph, &grid, accum, touched, target, physical, isStatic ? "gi.voxel.resolve.static" : "gi.voxel.resolve",
               commit);
}

} // namespace

VoxelGridData addVoxelGridPasses(rg::RenderGraph& graph, VoxelGrid& grid, const VoxelSceneHandles& scene,
                                 VoxelUpdate update) {
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
    rg::BufferHandle accum = graph.importBuffer("gi.voxel.accumulation", grid.accumulationState());
    rg::BufferHandle bits = graph.importBuffer("gi.voxel.touched_bits", grid.touchedBitsState());
    if (!anyDynamic) {
        // Static scene: one voxelization straight into the grid (no static copy, no merge).
        addVoxelization(graph, grid, scene, accum, bits, data.touched, out, VoxelDrawSet::All, true);
        return {out.albedo, out.normal, out.emission, out.faces, grid.params(), true, data.touched};
    }
    VolumeHandles st = importVolumes(graph, grid.staticState(), "gi.voxel.static");
    if (update == VoxelUpdate::Full)
        addVoxelization(graph, grid, scene, accum, bits, data.touched, st, VoxelDrawSet::Static, false);
    else
        data.touched = graph.importBuffer("gi.voxel.touched", grid.touchedState(VoxelDrawSet::Static));
    // The grid starts as a copy of the static volumes; the merge writes only the dynamic voxels
    // outside them, so nothing of an earlier frame's dynamic voxels survives.
    const VoxelGrid* g = &grid;
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
        [g, clearAccum, st, d = data](rg::PassContext& ctx) {
            g->recordClear(ctx.cmd(), ctx.buffer(d.touchedDynamic).buffer, clearAccum);
            VkImageLayout src[4] = {ctx.layout(st.albedo), ctx.layout(st.normal), ctx.layout(st.emission),
                                    ctx.layout(st.faces)};
            VkImageLayout dst[4] = {ctx.layout(d.albedo), ctx.layout(d.normal), ctx.layout(d.emission),
                                    ctx.layout(d.faces)};
            g->recordCopyStatic(ctx.cmd(), src, dst);
        });
    addVoxelize(graph, g, scene, accum, bits, VoxelDrawSet::Dynamic, "gi.voxel.voxelize.dynamic");
    addTouchedList(graph, g, bits, data.touchedDynamic, "gi.voxel.list.dynamic");
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
        [gm = &grid, planned = grid.planned()](rg::PassContext& ctx) {
            gm->recordResolveMerge(ctx.cmd());
            gm->commitPlanned(planned); // this graph runs: its plan is the grid's state
        });
    data.changed = true;
    return data;
}

namespace {

// Adds one pass per level k >= 1 of aniso, built from level k - 1, up to the tail, and one for
// the tail's levels ("prefix[t-L]"); returns the newest version. Level 1 is written at the listed
// occupied blocks only and keeps the zeros elsewhere (gi.vct.list.clear / .stale; no discard).
// With `jobs` (and the grid's normal volume) the level-1 pass also lists the second bounce's
// jobs into it (VctVolumes::recordMip).
rg::ImageHandle addMipPasses(rg::RenderGraph& graph, const VctVolumes* v, rg::ImageHandle aniso, rg::BufferHandle list,
                             const char* prefix, rg::BufferHandle* jobs = nullptr, rg::ImageHandle normal = {}) {
    uint32_t tail = v->mipTailLevel(), last = v->anisoLevels() - 1;
    for (uint32_t level = 1; level <= std::min(tail, last); ++level) {
        uint32_t count = level == tail ? last - tail + 1 : 1;
        std::string name = std::string(prefix) + "[" + std::to_string(level) +
                           (count > 1 ? "-" + std::to_string(last) : std::string()) + "]";
        graph.addPass(
            name,
            [&](rg::PassBuilder& b) {
                b.read(aniso, Access::ComputeStorageRead, rg::SubresourceRange::mip(level - 1));
                if (level == 1) {
                    b.read(list, Access::IndirectRead);
                    b.read(list, Access::ComputeStorageRead);
                    if (jobs) {
                        b.read(normal, Access::ComputeStorageRead);
                        *jobs = b.write(*jobs, Access::ComputeStorageReadWrite);
                    }
                }
                aniso = b.write(aniso, level == 1 ? Access::ComputeStorageWrite : Access::ComputeStorageWriteDiscard,
                                rg::SubresourceRange{level, count, 0, rg::kAll});
            },
            [v, level, jobBuffer = level == 1 && jobs ? *jobs : rg::BufferHandle{}](rg::PassContext& ctx) {
                v->recordMip(ctx.cmd(), level, jobBuffer.valid() ? ctx.buffer(jobBuffer).buffer : VK_NULL_HANDLE);
            });
    }
    return aniso;
}

// The per-pixel passes ("gi.vct.trace" and, at low resolution, the upsample and refine) through
// out.aniso.
VctOutputs addTracePasses(rg::RenderGraph& graph, VctVolumes& volumes, VctOutputs out, const VctSettings& settings,
                          const VctGBufferHandles* gbuffer, bool glossyImage);

// "gi.vct.shadow": direct light with cone-traced visibility through out.aniso into out.direct.
// Only with VctSettings::softShadows and a G-buffer with emission.
VctOutputs addSoftShadowPass(rg::RenderGraph& graph, VctVolumes& volumes, VctOutputs out, const VctSettings& settings,
                             const VctGBufferHandles* gbuffer, rg::BufferHandle lights, uint32_t lightCount) {
    if (!settings.softShadows || !gbuffer || !gbuffer->emission.valid())
        return out;
    const VctVolumes* v = &volumes;
    VctGBufferHandles g = *gbuffer;
    gpu::VctShadowPush push{volumes.grid().params(), volumes.coneParams(settings, g.width, g.height),
                            glm::uvec4(lightCount, g.width, g.height, 0u)};
    struct ShadowPassData {
        rg::ImageHandle direct;
    };
    const ShadowPassData& data = graph.addPass<ShadowPassData>(
        "gi.vct.shadow",
        [&](rg::PassBuilder& b, ShadowPassData& d) {
            b.read(out.aniso, Access::ComputeSampledRead);
            b.read(g.position, Access::ComputeStorageRead);
            b.read(g.normal, Access::ComputeStorageRead);
            b.read(g.albedo, Access::ComputeStorageRead);
            b.read(g.emission, Access::ComputeStorageRead);
            b.read(lights, Access::ComputeStorageRead);
            ImageDesc desc;
            desc.format = VK_FORMAT_R32G32B32A32_SFLOAT;
            desc.width = g.width;
            desc.height = g.height;
            d.direct = b.write(b.create("gi.vct.direct_soft", desc), Access::ComputeStorageWriteDiscard);
        },
        [v, push, aniso = out.aniso, g, lights](const ShadowPassData& d, rg::PassContext& ctx) {
            VctTraceTargets t{&ctx.image(g.position), &ctx.image(g.normal), &ctx.image(g.albedo), nullptr, nullptr,
                              VK_NULL_HANDLE,         &ctx.image(g.emission), &ctx.image(d.direct)};
            v->recordSoftShadow(ctx.cmd(), push, ctx.buffer(lights).buffer, t, ctx.layout(aniso));
        });
    out.direct = data.direct;
    return out;
}

} // namespace

VctOutputs addVctPasses(rg::RenderGraph& graph, VctVolumes& volumes, const VoxelGridData& grid,
                        rg::BufferHandle lights, uint32_t lightCount, const VctSettings& settings,
                        const VctGBufferHandles* gbuffer, VctPassOptions options) {
    const VctVolumes* v = &volumes;
    VctOutputs out;
    rg::BufferHandle list = graph.importBuffer("gi.vct.voxel_list", volumes.listState());
    out.aniso = graph.importImage("gi.vct.aniso", volumes.anisoState());
    if (!options.relight) {
        // Nothing the voxel light depends on changed: the trace reads the kept volume and mips.
        out = addSoftShadowPass(graph, volumes, out, settings, gbuffer, lights, lightCount);
        return gbuffer ? addTracePasses(graph, volumes, out, settings, gbuffer, options.glossyImage) : out;
    }
    const rg::SubresourceRange level0 = rg::SubresourceRange::mip(0);
    // The axes whose level-0 views each voxel last stored (gi/vct_passes.h): the voxel light
    // zeroes those its faces no longer cover, gi.vct.list.stale those of emptied voxels.
    rg::ImageHandle written = graph.importImage("gi.vct.written", volumes.writtenState());
    if (grid.changed || !volumes.listBuilt()) {
        // Once per voxelization: the occupied-voxel list the light and bounce passes run over.
        // The voxel light writes only the listed voxels' views, the level-1 mip only the listed
        // blocks, and the rest must read empty: the first voxelization zeroes levels 0 and 1 (and
        // the record of what they hold) by transfer clears, later ones only what went stale
        // (gi.vct.list.stale, after the list is built). The list header and bits are zeroed here.
        rg::BufferHandle writtenBits = graph.importBuffer("gi.vct.written_bits", volumes.writtenBitsState());
        const rg::SubresourceRange levels01{0, 2, 0, rg::kAll};
        bool first = !volumes.writtenKnown();
        graph.addPass(
            "gi.vct.list.clear",
            [&](rg::PassBuilder& b) {
                list = b.write(list, Access::TransferWrite);
                if (first) {
                    out.aniso = b.write(out.aniso, Access::TransferWrite, levels01);
                    written = b.write(written, Access::TransferWrite);
                    writtenBits = b.write(writtenBits, Access::TransferWrite);
                }
            },
            [v, list, aniso = out.aniso, written, first](rg::PassContext& ctx) {
                v->recordClearList(ctx.cmd(), ctx.buffer(list).buffer);
                if (first)
                    v->recordClearLevels01(ctx.cmd(), ctx.layout(aniso), ctx.layout(written));
            });
        // One pass per touched list of the grid (the whole scene's or the static draws', then
        // the dynamic draws'), each an indirect dispatch over its list setting the list's
        // occupancy bits, then one pass listing the set bits in grid order.
        for (rg::BufferHandle touched : {grid.touched, grid.touchedDynamic}) {
            if (!touched.valid())
                continue;
            graph.addPass(
                touched == grid.touched ? "gi.vct.list" : "gi.vct.list.dynamic",
                [&](rg::PassBuilder& b) {
                    b.read(touched, Access::IndirectRead);
                    b.read(touched, Access::ComputeStorageRead);
                    list = b.write(list, Access::ComputeStorageReadWrite);
                },
                [v, touched](rg::PassContext& ctx) { v->recordCompact(ctx.cmd(), ctx.buffer(touched).buffer); });
        }
        graph.addPass(
            "gi.vct.list.append", [&](rg::PassBuilder& b) { list = b.write(list, Access::ComputeStorageReadWrite); },
            [v](rg::PassContext& ctx) { v->recordListAppend(ctx.cmd()); });
        graph.addPass(
            "gi.vct.list.stale",
            [&](rg::PassBuilder& b) {
                b.read(list, Access::ComputeStorageRead);
                writtenBits = b.write(writtenBits, Access::ComputeStorageReadWrite);
                written = b.write(written, Access::ComputeStorageReadWrite);
                out.aniso = b.write(out.aniso, Access::ComputeStorageWrite, levels01);
            },
            [v](rg::PassContext& ctx) { v->recordListStale(ctx.cmd()); });
        volumes.setListBuilt(true);
        volumes.setWrittenKnown(true);
    }
    VctOcclusion occlusion = settings.occlusion;
    bool emission = options.emission;
    bool useShadowMap = occlusion == VctOcclusion::ShadowMap && options.shadowAtlas.valid();
    graph.addPass(
        "gi.vct.light",
        [&](rg::PassBuilder& b) {
            if (useShadowMap) {
                b.read(options.shadowAtlas, Access::ComputeSampledRead);
                b.read(options.shadowViews, Access::ComputeStorageRead);
                b.read(options.lightShadows, Access::ComputeStorageRead);
            }
            b.read(list, Access::IndirectRead);
            b.read(list, Access::ComputeStorageRead);
            b.read(lights, Access::ComputeStorageRead);
            // Only the soft march filters the occupancy; the others load texels.
            bool soft = !useShadowMap && occlusion == VctOcclusion::RayMarchSoft;
            b.read(grid.albedo, soft ? Access::ComputeSampledRead : Access::ComputeStorageRead);
            b.read(grid.faces, Access::ComputeStorageRead);
            b.read(grid.emission, Access::ComputeStorageRead);
            written = b.write(written, Access::ComputeStorageReadWrite);
            out.aniso = b.write(out.aniso, Access::ComputeStorageWrite, level0); // the listed voxels
        },
        [v, lights, lightCount, occlusion, emission, albedo = grid.albedo, useShadowMap, options](rg::PassContext& ctx) {
            VctShadowInputs in;
            if (useShadowMap)
                in = {ctx.buffer(options.lightShadows).buffer, ctx.buffer(options.shadowViews).buffer,
                      &ctx.image(options.shadowAtlas), options.shadowSampler, ctx.layout(options.shadowAtlas)};
            v->recordLight(ctx.cmd(), ctx.buffer(lights).buffer, lightCount, occlusion, ctx.layout(albedo), emission,
                           useShadowMap ? &in : nullptr);
        });
    // Second bounce: one gather per (block, normal class), its misfit voxels one each
    // (gi/vct_passes.h); the level-1 mip lists the jobs after the clear.
    rg::BufferHandle jobs;
    if (settings.bounces >= 2) {
        jobs = graph.importBuffer("gi.vct.bounce.jobs", volumes.bounceJobsState());
        graph.addPass(
            "gi.vct.bounce.jobs.clear", [&](rg::PassBuilder& b) { jobs = b.write(jobs, Access::TransferWrite); },
            [v, jobs](rg::PassContext& ctx) { v->recordClearBounceJobs(ctx.cmd(), ctx.buffer(jobs).buffer); });
    }
    out.aniso = addMipPasses(graph, v, out.aniso, list, "gi.vct.mip", jobs.valid() ? &jobs : nullptr, grid.normal);
    gpu::ConeParams cones = volumes.coneParams(settings, gbuffer ? gbuffer->width : 0, gbuffer ? gbuffer->height : 0);
    if (settings.bounces >= 2) {
        struct Jobs {
            rg::BufferHandle jobs;
        };
        rg::BufferHandle results = graph.importBuffer("gi.vct.bounce.results", volumes.bounceResultsState());
        const Jobs& blocks = graph.addPass<Jobs>(
            "gi.vct.bounce.blocks",
            [&](rg::PassBuilder& b, Jobs& d) {
                b.read(jobs, Access::IndirectRead);
                b.read(list, Access::ComputeStorageRead);
                b.read(out.aniso, Access::ComputeSampledRead);
                b.read(grid.normal, Access::ComputeStorageRead);
                d.jobs = b.write(jobs, Access::ComputeStorageReadWrite); // the misfit list
                results = b.write(results, Access::ComputeStorageWrite);
            },
            [v, cones, aniso = out.aniso, results](const Jobs& d, rg::PassContext& ctx) {
                v->recordBounceBlocks(ctx.cmd(), cones, ctx.buffer(d.jobs).buffer, ctx.buffer(results).buffer,
                                      ctx.layout(aniso));
            });
        ImageDesc bounceDesc;
        bounceDesc.type = VK_IMAGE_TYPE_3D;
        bounceDesc.format = VK_FORMAT_R16G16B16A16_SFLOAT;
        bounceDesc.width = bounceDesc.height = bounceDesc.depth = volumes.grid().resolution();
        struct Gathered {
            rg::ImageHandle image;
        };
        // The misfits first: they read level 0 of the first bounce, which the apply then adds to.
        const Gathered& misfits = graph.addPass<Gathered>(
            "gi.vct.bounce.misfits",
            [&](rg::PassBuilder& b, Gathered& d) {
                b.read(blocks.jobs, Access::IndirectRead);
                b.read(blocks.jobs, Access::ComputeStorageRead);
                b.read(out.aniso, Access::ComputeSampledRead);
                b.read(grid.albedo, Access::ComputeStorageRead);
                b.read(grid.normal, Access::ComputeStorageRead);
                // Only the misfit voxels are written; the apply reads no others.
                d.image = b.write(b.create("gi.vct.bounce.light", bounceDesc), Access::ComputeStorageWriteDiscard);
            },
            [v, cones, aniso = out.aniso, jobs = blocks.jobs](const Gathered& d, rg::PassContext& ctx) {
                v->recordBounceMisfits(ctx.cmd(), cones, ctx.buffer(jobs).buffer, ctx.image(d.image), ctx.layout(aniso));
            });
        graph.addPass(
            "gi.vct.bounce",
            [&](rg::PassBuilder& b) {
                b.read(list, Access::IndirectRead);
                b.read(list, Access::ComputeStorageRead);
                b.read(grid.albedo, Access::ComputeStorageRead);
                b.read(grid.normal, Access::ComputeStorageRead);
                b.read(grid.faces, Access::ComputeStorageRead);
                b.read(blocks.jobs, Access::ComputeStorageRead);
                b.read(results, Access::ComputeStorageRead);
                b.read(misfits.image, Access::ComputeStorageRead);
                out.aniso = b.write(out.aniso, Access::ComputeStorageReadWrite, level0); // the listed voxels
            },
            [v, jobs = blocks.jobs, results, light = misfits.image](rg::PassContext& ctx) {
                v->recordBounceApply(ctx.cmd(), ctx.buffer(jobs).buffer, ctx.buffer(results).buffer, ctx.image(light));
            });
        out.aniso = addMipPasses(graph, v, out.aniso, list, "gi.vct.bounce.mip");
    }
    out = addSoftShadowPass(graph, volumes, out, settings, gbuffer, lights, lightCount);
    return gbuffer ? addTracePasses(graph, volumes, out, settings, gbuffer, options.glossyImage) : out;
}

namespace {

VctOutputs addTracePasses(rg::RenderGraph& graph, VctVolumes& volumes, VctOutputs out, const VctSettings& settings,
                          const VctGBufferHandles* gbuffer, bool glossyImage) {
    const VctVolumes* v = &volumes;
    gpu::ConeParams cones = volumes.coneParams(settings, gbuffer->width, gbuffer->height);
    if (glossyImage)
        cones.info.y |= GI_VCT_FLAG_GLOSSY_IMAGE;
    VctGBufferHandles g = *gbuffer;
    const uint32_t f = settings.lowResFactor;
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
    struct TraceData {
        rg::ImageHandle indirect, glossy;
        rg::BufferHandle list;
    };
    const TraceData& data = graph.addPass<TraceData>(
        "gi.vct.trace",
        [&](rg::PassBuilder& b, TraceData& d) {
            b.read(out.aniso, Access::ComputeSampledRead);
            b.read(g.position, Access::ComputeStorageRead);
            b.read(g.normal, Access::ComputeStorageRead);
            b.read(g.albedo, Access::ComputeStorageRead);
            ImageDesc desc = image(push.lowRes.y, push.lowRes.z);
            d.indirect = b.write(b.create(f == 1 ? "gi.vct.indirect" : "gi.vct.indirect.low", desc),
                                 Access::ComputeStorageWriteDiscard);
            d.glossy = b.write(b.create(f == 1 ? "gi.vct.glossy" : "gi.vct.glossy.low", desc),
                               Access::ComputeStorageWriteDiscard);
            // The refine list of the upsample and refine, whose header the trace zeroes (at f = 1
            // the header alone, unused: one shader for both).
            BufferDesc list;
            list.size = VkDeviceSize(GI_VCT_REFINE_HEADER + (f == 1 ? 0u : 2u * push.lowRes.w)) * sizeof(uint32_t);
            list.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
            d.list = b.write(b.create("gi.vct.refine_list", list), Access::ComputeStorageWrite);
        },
        [v, push, aniso = out.aniso, g](const TraceData& d, rg::PassContext& ctx) {
            VctTraceTargets t{&ctx.image(g.position), &ctx.image(g.normal),   &ctx.image(g.albedo),
                              &ctx.image(d.indirect), &ctx.image(d.glossy), ctx.buffer(d.list).buffer};
            v->recordTrace(ctx.cmd(), VctTraceMode::Grid, push, t, ctx.layout(aniso));
        });
    if (f == 1) {
        out.indirect = data.indirect;
        out.glossy = data.glossy;
        return out;
    }
    // Low-res: upsample + refine list, then the listed pixels at full resolution.
    struct UpsampleData {
        rg::ImageHandle indirect, glossy;
        rg::BufferHandle list;
    };
    const UpsampleData& us = graph.addPass<UpsampleData>(
        "gi.vct.upsample",
        [&](rg::PassBuilder& b, UpsampleData& d) {
            b.read(g.position, Access::ComputeStorageRead);
            b.read(g.normal, Access::ComputeStorageRead);
            b.read(g.albedo, Access::ComputeStorageRead);
            b.read(data.indirect, Access::ComputeStorageRead);
            b.read(data.glossy, Access::ComputeStorageRead);
            ImageDesc desc = image(g.width, g.height);
            d.indirect = b.write(b.create("gi.vct.indirect", desc), Access::ComputeStorageWriteDiscard);
            d.glossy = b.write(b.create("gi.vct.glossy", desc), Access::ComputeStorageWriteDiscard);
            d.list = b.write(data.list, Access::ComputeStorageReadWrite);
        },
        [v, push, g, low = data](const UpsampleData& d, rg::PassContext& ctx) {
            VctTraceTargets t{&ctx.image(g.position), &ctx.image(g.normal),   &ctx.image(g.albedo),
                              &ctx.image(d.indirect), &ctx.image(d.glossy), ctx.buffer(d.list).buffer};
            v->recordUpsample(ctx.cmd(), push, ctx.image(low.indirect), ctx.image(low.glossy), t);
        });
    const UpsampleData& rf = graph.addPass<UpsampleData>(
        "gi.vct.refine",
        [&](rg::PassBuilder& b, UpsampleData& d) {
            b.read(out.aniso, Access::ComputeSampledRead);
            b.read(g.position, Access::ComputeStorageRead);
            b.read(g.normal, Access::ComputeStorageRead);
            b.read(g.albedo, Access::ComputeStorageRead);
            b.read(us.list, Access::IndirectRead);
            b.read(us.list, Access::ComputeStorageRead);
            d.indirect = b.write(us.indirect, Access::ComputeStorageWrite);
            d.glossy = b.write(us.glossy, Access::ComputeStorageWrite);
        },
        [v, push, aniso = out.aniso, g, list = us.list](const UpsampleData& d, rg::PassContext& ctx) {
            VctTraceTargets t{&ctx.image(g.position), &ctx.image(g.normal),   &ctx.image(g.albedo),
                              &ctx.image(d.indirect), &ctx.image(d.glossy), ctx.buffer(list).buffer};
            v->recordTrace(ctx.cmd(), VctTraceMode::Refine, push, t, ctx.layout(aniso));
        });
    out.indirect = rf.indirect;
    out.glossy = rf.glossy;
    return out;
}

} // namespace

} // namespace vkgi::gi
