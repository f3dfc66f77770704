#include "lpv/lpv_inject.hpp"

#include <algorithm>
#include <string>

#include "engine/context.hpp"

namespace vkgi::gi::lpv {

using rg::Access;

Result<Injector> Injector::create(Context& ctx) {
    Injector inj;
    struct Item {
        Pipeline* pipeline;
        const char* shader;
    } items[] = {{&inj.range, "gi/lpv/inject_range.comp"},
                 {&inj.inject, "gi/lpv/inject.comp"},
                 {&inj.lookup, "gi/lpv/lookup.comp"},
                 {&inj.resolve[0], "gi/lpv/inject_resolve_rgba16f.comp"},
                 {&inj.resolve[1], "gi/lpv/inject_resolve_rgba32f.comp"},
                 {&inj.gvRsm, "gi/lpv/gv_inject_rsm.comp"},
                 {&inj.gvCamera, "gi/lpv/gv_inject_camera.comp"},
                 {&inj.gvResolve, "gi/lpv/gv_resolve.comp"},
                 {&inj.reduce[0], "gi/lpv/inject_reduce.comp"},
                 {&inj.reduce[1], "gi/lpv/inject_reduce.comp"},
                 {&inj.sum[0], "gi/lpv/lookup_sum_rgba16f.comp"},
                 {&inj.sum[1], "gi/lpv/lookup_sum_rgba32f.comp"}};
    for (const Item& item : items) {
        std::vector<SpecConstant> spec;
        if (item.pipeline == &inj.reduce[0] || item.pipeline == &inj.reduce[1])
            spec.push_back({LPV_REDUCE_SPEC_FACTOR, item.pipeline == &inj.reduce[0] ? 2u : 4u});
        auto p = createComputePipeline(ctx, {item.shader, spec});
        if (!p) {
            inj.destroy(ctx);
            return p.error();
        }
        *item.pipeline = *p;
    }
    SamplerDesc linear;
    linear.mipmap = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    inj.linear = createSampler(ctx, linear);
    return inj;
}

void Injector::destroy(Context& ctx) {
    for (Pipeline* p :
         {&range, &inject, &lookup, &resolve[0], &resolve[1], &gvRsm, &gvCamera, &gvResolve, &reduce[0], &reduce[1],
          &sum[0], &sum[1]})
        if (p->pipeline != VK_NULL_HANDLE)
            destroyPipeline(ctx, *p);
    if (linear != VK_NULL_HANDLE) {
        vkDestroySampler(ctx.device(), linear, nullptr);
        linear = VK_NULL_HANDLE;
    }
}

VkDeviceSize injectionBufferBytes(glm::ivec3 cells) {
    return VkDeviceSize(LPV_INJECT_HEADER_INTS + LPV_INJECT_CELL_INTS * size_t(cells.x) * cells.y * cells.z) * 4;
}

RsmInput addRsmReducePass(rg::RenderGraph& graph, const Injector& injector, const RsmInput& rsm, uint32_t factor,
                          const std::string& prefix) {
    RsmInput out;
    out.resolution = (rsm.resolution + factor - 1) / factor;
    out.layers = rsm.layers;
    ImageDesc desc;
    desc.width = desc.height = out.resolution;
    desc.arrayLayers = std::max(rsm.layers, 2u); // more than one layer: the view is a 2D array
    desc.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    desc.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    out.position = graph.createImage(prefix + ".rsm.position", desc);
    out.flux = graph.createImage(prefix + ".rsm.flux", desc);
    desc.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    out.normal = graph.createImage(prefix + ".rsm.normal", desc);
    gpu::LpvInjectPush push{};
    push.rsm = glm::ivec4(int(rsm.resolution), int(rsm.layers), int(factor), int(out.resolution));
    const Pipeline* pipeline = &injector.reduce[factor == 4];
        graph.addPass((prefix + ".inject.reduce"),
                  [&](rg::PassBuilder& b) {
                      b.read(rsm.position, Access::ComputeStorageRead);
                      b.read(rsm.normal, Access::ComputeStorageRead);
                      b.read(rsm.flux, Access::ComputeStorageRead);
                      out.position = b.write(out.position, Access::ComputeStorageWriteDiscard);
                      out.normal = b.write(out.normal, Access::ComputeStorageWriteDiscard);
                      out.flux = b.write(out.flux, Access::ComputeStorageWriteDiscard);
                  },
                  [=](rg::PassContext& ctx) {
                      ctx.dispatch(*pipeline,
                                   rg::PassContext::groupsFor(*pipeline, {out.resolution, out.resolution, out.layers}),
                                   push,
                                   {ctx.storage(LPV_INJECT_BINDING_POSITION, rsm.position),
                                    ctx.storage(LPV_INJECT_BINDING_NORMAL, rsm.normal),
                                    ctx.storage(LPV_INJECT_BINDING_FLUX, rsm.flux),
                                    ctx.storage(LPV_REDUCE_BINDING_POSITION, out.position),
                                    ctx.storage(LPV_REDUCE_BINDING_NORMAL, out.normal),
                                    ctx.storage(LPV_REDUCE_BINDING_FLUX, out.flux)});
                  });
    return out;
}

InjectionResult addInjectionPasses(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                   VkFormat format, const RsmInput& rsm, ShHandles wavefront, ShHandles accumulation,
                                   rg::BufferHandle buffer, const std::string& prefix) {
    const glm::ivec3 cells(grid.size);
    if (!buffer.valid())
        buffer = graph.createBuffer((prefix + ".injection"), {injectionBufferBytes(cells), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT});
    gpu::LpvInjectPush push{};
    push.grid = grid;
    push.rsm = glm::ivec4(int(rsm.resolution), int(rsm.layers), 0, 0);
    push.params = glm::vec4(gpu::lpvFixedPointScale(float(rsm.resolution) * float(rsm.resolution) * float(rsm.layers)),
                            0.0f, 0.0f, 0.0f);
    const Injector* inj = &injector;
    rg::BufferHandle buf = buffer;
    graph.addPass(
        (prefix + ".inject.clear"), [&](rg::PassBuilder& b) { buf = b.write(buf, Access::TransferWrite); },
        [=](rg::PassContext& ctx) { vkCmdFillBuffer(ctx.cmd(), ctx.buffer(buf).buffer, 0, VK_WHOLE_SIZE, 0); });
    graph.addPass(
        (prefix + ".inject.range"),
        [&](rg::PassBuilder& b) {
            b.read(rsm.position, Access::ComputeStorageRead);
            b.read(rsm.flux, Access::ComputeStorageRead);
            buf = b.write(buf, Access::ComputeStorageReadWrite);
        },
        [=](rg::PassContext& ctx) {
            ctx.dispatch(inj->range, rg::PassContext::groupsFor(inj->range, {rsm.resolution, rsm.resolution, rsm.layers}),
                         push,
                         {ctx.storage(LPV_INJECT_BINDING_POSITION, rsm.position),
                          ctx.storage(LPV_INJECT_BINDING_FLUX, rsm.flux),
                          ctx.buffer(LPV_INJECT_BINDING_BUFFER, buf)});
        });
    graph.addPass(
        prefix + ".inject",
        [&](rg::PassBuilder& b) {
            b.read(rsm.position, Access::ComputeStorageRead);
            b.read(rsm.normal, Access::ComputeStorageRead);
            b.read(rsm.flux, Access::ComputeStorageRead);
            buf = b.write(buf, Access::ComputeStorageReadWrite);
        },
        [=](rg::PassContext& ctx) {
            uint32_t runs = (rsm.resolution + LPV_INJECT_RUN - 1) / LPV_INJECT_RUN;
            ctx.dispatch(inj->inject, rg::PassContext::groupsFor(inj->inject, {runs, rsm.resolution, rsm.layers}), push,
                         {ctx.storage(LPV_INJECT_BINDING_POSITION, rsm.position),
                          ctx.storage(LPV_INJECT_BINDING_NORMAL, rsm.normal),
                          ctx.storage(LPV_INJECT_BINDING_FLUX, rsm.flux),
                          ctx.buffer(LPV_INJECT_BINDING_BUFFER, buf)});
        });
    const Pipeline* resolve = &injector.resolve[format == VK_FORMAT_R32G32B32A32_SFLOAT];
    ShHandles wave = wavefront, acc = accumulation;
    graph.addPass(
        (prefix + ".inject.resolve"),
        [&](rg::PassBuilder& b) {
            b.read(buf, Access::ComputeStorageRead);
            for (int c = 0; c < 3; ++c) {
                wave.channel[c] = b.write(wave.channel[c], Access::ComputeStorageWriteDiscard);
                acc.channel[c] = b.write(acc.channel[c], Access::ComputeStorageWriteDiscard);
            }
        },
        [=](rg::PassContext& ctx) {
            ctx.dispatch(*resolve, rg::PassContext::groupsFor(*resolve, glm::uvec3(cells)), push,
                         {ctx.buffer(LPV_RESOLVE_BINDING_BUFFER, buf),
                          ctx.storage(LPV_RESOLVE_BINDING_WAVEFRONT_R, wave.channel[0]),
                          ctx.storage(LPV_RESOLVE_BINDING_WAVEFRONT_G, wave.channel[1]),
                          ctx.storage(LPV_RESOLVE_BINDING_WAVEFRONT_B, wave.channel[2]),
                          ctx.storage(LPV_RESOLVE_BINDING_ACCUMULATION_R, acc.channel[0]),
                          ctx.storage(LPV_RESOLVE_BINDING_ACCUMULATION_G, acc.channel[1]),
                          ctx.storage(LPV_RESOLVE_BINDING_ACCUMULATION_B, acc.channel[2])});
        });
    return {wave, acc, buf};
}

rg::ImageHandle addGeometryVolumePasses(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                        const RsmInput& rsm, const GBufferInput& gbuffer,
                                        const std::string& prefix) {
    const glm::ivec3 corners = glm::ivec3(grid.size) + 1;
    const size_t cornerCount = size_t(corners.x) * corners.y * corners.z;
    rg::BufferHandle buf = graph.createBuffer(
        (prefix + ".gv.sums"), {VkDeviceSize(LPV_INJECT_HEADER_INTS + 2 * 4 * cornerCount) * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT});
    ImageDesc desc;
    desc.type = VK_IMAGE_TYPE_3D;
    desc.format = kGeometryVolumeFormat;
    desc.width = uint32_t(corners.x);
    desc.height = uint32_t(corners.y);
    desc.depth = uint32_t(corners.z);
    desc.usage = VK_IMAGE_USAGE_STORAGE_BIT;
    rg::ImageHandle gv = graph.createImage(prefix + ".gv", desc);
    gpu::LpvInjectPush push{};
    push.grid = grid;
    push.params = glm::vec4(float(LPV_GEOMETRY_VOLUME_FIXED_SCALE), 0.0f, 0.0f, 0.0f);
    const Injector* inj = &injector;
    graph.addPass(
        (prefix + ".gv.clear"), [&](rg::PassBuilder& b) { buf = b.write(buf, Access::TransferWrite); },
        [=](rg::PassContext& ctx) { vkCmdFillBuffer(ctx.cmd(), ctx.buffer(buf).buffer, 0, VK_WHOLE_SIZE, 0); });
    struct Source {
        std::string name;
        rg::ImageHandle position, normal;
        const Pipeline* pipeline;
        glm::uvec3 texels;
    } sources[2] = {{(prefix + ".gv.rsm"), rsm.position, rsm.normal, &injector.gvRsm,
                     {rsm.resolution, rsm.resolution, rsm.layers}},
                    {(prefix + ".gv.camera"), gbuffer.position, gbuffer.normal, &injector.gvCamera,
                     {gbuffer.width, gbuffer.height, 1}}};
    // The camera's G-buffer is sampled every `stride` pixels per axis, each sample's area estimated
    // from the samples `stride` pixels away (the same area estimator, stride^2 times the area, so
    // the coverage sum is unchanged). The stride keeps at least 4 samples per LPV cell per axis
    // when the whole grid spans the image (kGvCameraSamplesPerCell); closer views sample denser.
    // Cornell 256^2 with 32^3: stride 2 (4x fewer G-buffer surfels); 64^2 images: stride 1.
    constexpr uint32_t kGvCameraSamplesPerCell = 4;
    const uint32_t cells = uint32_t(std::max({grid.size.x, grid.size.y, grid.size.z, 1}));
    const uint32_t cameraStride =
        std::clamp(std::max(gbuffer.width, gbuffer.height) / (kGvCameraSamplesPerCell * cells), 1u, 4u);
    sources[1].texels = glm::uvec3((gbuffer.width + cameraStride - 1) / cameraStride,
                                   (gbuffer.height + cameraStride - 1) / cameraStride, 1);
    for (int slot = 0; slot < 2; ++slot) {
        const Source src = sources[slot];
        if (!src.position.valid())
            continue;
        const uint32_t stride = slot == 1 ? cameraStride : 1u;
        push.rsm = slot == 1 ? glm::ivec4(int(gbuffer.width), 1, slot, int(gbuffer.height))
                             : glm::ivec4(int(src.texels.x), int(src.texels.z), slot, int(src.texels.y));
        push.params.y = float(stride);
        graph.addPass(
            src.name,
            [&](rg::PassBuilder& b) {
                b.read(src.position, Access::ComputeStorageRead);
                b.read(src.normal, Access::ComputeStorageRead);
                buf = b.write(buf, Access::ComputeStorageReadWrite);
            },
            [=](rg::PassContext& ctx) {
                ctx.dispatch(*src.pipeline, rg::PassContext::groupsFor(*src.pipeline, src.texels), push,
                             {ctx.storage(LPV_GEOMETRY_VOLUME_BINDING_POSITION, src.position),
                              ctx.storage(LPV_GEOMETRY_VOLUME_BINDING_NORMAL, src.normal),
                              ctx.buffer(LPV_GEOMETRY_VOLUME_BINDING_SUMS, buf)});
            });
    }
    graph.addPass(
        (prefix + ".gv.resolve"),
        [&](rg::PassBuilder& b) {
            b.read(buf, Access::ComputeStorageRead);
            gv = b.write(gv, Access::ComputeStorageWriteDiscard);
        },
        [=](rg::PassContext& ctx) {
            ctx.dispatch(inj->gvResolve, rg::PassContext::groupsFor(inj->gvResolve, glm::uvec3(corners)), push,
                         {ctx.buffer(LPV_GEOMETRY_VOLUME_BINDING_SUMS, buf), ctx.storage(LPV_GEOMETRY_VOLUME_BINDING_OUTPUT, gv)});
        });
    return gv;
}

rg::ImageHandle addAccumulationSumPass(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                      const ShHandles& accumulation, rg::ImageHandle sum, const std::string& prefix) {
    const ImageDesc& accDesc = graph.imageDesc(accumulation.channel[0]);
    const glm::uvec3 cells(accDesc.width, accDesc.height, accDesc.depth);
    if (!sum.valid())
        sum = graph.createImage(prefix + ".accumulation.sum", shImageDesc(glm::ivec3(cells), accDesc.format));
    const Pipeline* pipeline = &injector.sum[accDesc.format == VK_FORMAT_R32G32B32A32_SFLOAT];
    gpu::LpvInjectPush push{};
    push.grid = grid;
    ShHandles acc = accumulation;
    graph.addPass(
        (prefix + ".lookup.sum"),
        [&](rg::PassBuilder& b) {
            for (int c = 0; c < 3; ++c)
                b.read(acc.channel[c], Access::ComputeStorageRead);
            sum = b.write(sum, Access::ComputeStorageWriteDiscard);
        },
        [=](rg::PassContext& ctx) {
            ctx.dispatch(*pipeline, rg::PassContext::groupsFor(*pipeline, cells), push,
                         {ctx.storage(LPV_SUM_BINDING_ACCUMULATION_R, acc.channel[0]),
                          ctx.storage(LPV_SUM_BINDING_ACCUMULATION_G, acc.channel[1]),
                          ctx.storage(LPV_SUM_BINDING_ACCUMULATION_B, acc.channel[2]),
                          ctx.storage(LPV_SUM_BINDING_OUTPUT, sum)});
        });
    return sum;
}

rg::ImageHandle addLookupPass(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                              const ShHandles& accumulation, rg::BufferHandle buffer, const GBufferInput& gbuffer,
                              float damping, rg::ImageHandle output, const CascadeBlend& blend,
                              const std::string& prefix, rg::ImageHandle sum) {
    if (!output.valid()) {
        ImageDesc desc;
        desc.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        desc.width = gbuffer.width;
        desc.height = gbuffer.height;
        desc.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
        output = graph.createImage((prefix + ".indirect"), desc);
    }
    gpu::LpvLookupPush push{};
    push.grid = grid;
    push.image = glm::ivec4(int(gbuffer.width), int(gbuffer.height), 0, 0);
    push.params = glm::vec4(damping, blend.fadeBorder ? 1.0f : 0.0f, blend.accumulate ? 1.0f : 0.0f, 0.0f);
    push.image.z = int(std::min<size_t>(blend.finer.size(), 2));
    for (size_t k = 0; k < blend.finer.size() && k < 2; ++k)
        push.finer[k] = blend.finer[k];
    const Access outAccess = blend.accumulate ? Access::ComputeStorageReadWrite : Access::ComputeStorageWriteDiscard;
    const Injector* inj = &injector;
    rg::ImageHandle out = output;
    ShHandles acc = accumulation;
    // The channel sum the damping reads (one fetch per damping point instead of three).
    if (damping > 0.0f && !sum.valid())
        sum = addAccumulationSumPass(graph, injector, grid, acc, {}, prefix);
    graph.addPass(
        (prefix + ".lookup"),
        [&](rg::PassBuilder& b) {
            b.read(gbuffer.position, Access::ComputeStorageRead);
            b.read(gbuffer.normal, Access::ComputeStorageRead);
            b.read(gbuffer.albedo, Access::ComputeStorageRead);
            for (int c = 0; c < 3; ++c)
                b.read(acc.channel[c], Access::ComputeSampledRead);
            b.read(sum.valid() ? sum : acc.channel[0], Access::ComputeSampledRead);
            b.read(buffer, Access::ComputeStorageRead);
            out = b.write(out, outAccess);
        },
        [=](rg::PassContext& ctx) {
            ctx.dispatch(inj->lookup, rg::PassContext::groupsFor(inj->lookup, {gbuffer.width, gbuffer.height, 1}), push,
                         {ctx.storage(LPV_LOOKUP_BINDING_POSITION, gbuffer.position),
                          ctx.storage(LPV_LOOKUP_BINDING_NORMAL, gbuffer.normal),
                          ctx.storage(LPV_LOOKUP_BINDING_ALBEDO, gbuffer.albedo),
                          ctx.sampled(LPV_LOOKUP_BINDING_ACCUMULATION_R, acc.channel[0], inj->linear),
                          ctx.sampled(LPV_LOOKUP_BINDING_ACCUMULATION_G, acc.channel[1], inj->linear),
                          ctx.sampled(LPV_LOOKUP_BINDING_ACCUMULATION_B, acc.channel[2], inj->linear),
                          ctx.sampled(LPV_LOOKUP_BINDING_SUM, sum.valid() ? sum : acc.channel[0], inj->linear),
                          ctx.buffer(LPV_LOOKUP_BINDING_BUFFER, buffer),
                          ctx.storage(LPV_LOOKUP_BINDING_OUTPUT, out)});
        });
    return out;
}

} // namespace vkgi::gi::lpv
