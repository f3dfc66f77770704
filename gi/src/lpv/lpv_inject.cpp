#include "lpv/lpv_inject.hpp"

#include <algorithm>
#include <string>

#include "direct/direct_passes.hpp"
#include "vkgi/context.hpp"
#include "vkgi/rg/compute_pass.hpp"
#include "vk_dispatch.hpp"

namespace vkgi::gi::lpv {

using rg::Access;

Result<Injector> Injector::create(Context& ctx) {
    Injector injector;
    struct Item {
        Pipeline* pipeline;
        const char* shader;
        uint32_t reduceFactor; // LPV_REDUCE_SPEC_FACTOR of inject_reduce.comp, 0 for the other shaders
    } items[] = {{&injector.fluxRange, "gi/lpv/inject_range.comp", 0},
                 {&injector.inject, "gi/lpv/inject.comp", 0},
                 {&injector.lookup, "gi/lpv/lookup.comp", 0},
                 {&injector.resolve[0], "gi/lpv/inject_resolve_rgba16f.comp", 0},
                 {&injector.resolve[1], "gi/lpv/inject_resolve_rgba32f.comp", 0},
                 {&injector.geometryFromRsm, "gi/lpv/gv_inject_rsm.comp", 0},
                 {&injector.geometryFromCamera, "gi/lpv/gv_inject_camera.comp", 0},
                 {&injector.geometryResolve, "gi/lpv/gv_resolve.comp", 0},
                 {&injector.rsmReduce[0], "gi/lpv/inject_reduce.comp", 2},
                 {&injector.rsmReduce[1], "gi/lpv/inject_reduce.comp", 4},
                 {&injector.channelSum[0], "gi/lpv/lookup_sum_rgba16f.comp", 0},
                 {&injector.channelSum[1], "gi/lpv/lookup_sum_rgba32f.comp", 0}};
    for (const Item& item : items) {
        std::vector<SpecConstant> spec;
        if (item.reduceFactor != 0)
            spec.push_back({LPV_REDUCE_SPEC_FACTOR, item.reduceFactor});
        auto pipeline = createComputePipeline(ctx, {item.shader, spec});
        if (!pipeline) {
            injector.destroy(ctx);
            return pipeline.error();
        }
        *item.pipeline = *pipeline;
    }
    SamplerDesc linear;
    linear.mipmap = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    injector.linearSampler = createSampler(ctx, linear);
    return injector;
}

void Injector::destroy(Context& ctx) {
    for (Pipeline* p : {&fluxRange, &inject, &lookup, &resolve[0], &resolve[1], &geometryFromRsm, &geometryFromCamera,
                        &geometryResolve, &rsmReduce[0], &rsmReduce[1], &channelSum[0], &channelSum[1]})
        if (p->pipeline != VK_NULL_HANDLE)
            destroyPipeline(ctx, *p);
    if (linearSampler != VK_NULL_HANDLE) {
        vkDestroySampler(ctx.device(), linearSampler, nullptr);
        linearSampler = VK_NULL_HANDLE;
    }
}

VkDeviceSize injectionBufferBytes(glm::ivec3 cells) {
    return VkDeviceSize(LPV_INJECT_HEADER_INTS + LPV_INJECT_CELL_INTS * size_t(cells.x) * cells.y * cells.z) * 4;
}

namespace {

// A pass that zeroes `buffer` (fixed-point sums start at zero; the header's M too).
void addClearPass(rg::RenderGraph& graph, const std::string& name, rg::BufferHandle& buffer) {
    graph.addPass(
        name, [&](rg::PassBuilder& b) { buffer = b.write(buffer, Access::TransferWrite); },
        [cleared = buffer](rg::PassContext& ctx) {
            vkCmdFillBuffer(ctx.cmd(), ctx.buffer(cleared).buffer, 0, VK_WHOLE_SIZE, 0);
        });
}

} // namespace

RsmInput addRsmReducePass(rg::RenderGraph& graph, const Injector& injector, const RsmInput& rsm, uint32_t factor,
                          float mergeRadius, const std::string& prefix) {
    RsmInput reduced;
    reduced.resolution = (rsm.resolution + factor - 1) / factor;
    reduced.layers = rsm.layers;
    reduced.sourcePosition = rsm.position;
    reduced.sourceNormal = rsm.normal;
    reduced.sourceFlux = rsm.flux;
    reduced.sourceResolution = rsm.resolution;
    reduced.views = rsm.views;
    reduced.nearLightRadius = rsm.nearLightRadius;
    reduced.factor = factor;
    const RsmImages images = createRsmImages(graph, prefix + ".rsm", reduced.resolution, rsm.layers);
    reduced.position = images.position;
    reduced.normal = images.normal;
    reduced.flux = images.flux;
    gpu::LpvInjectPush push{};
    push.rsm = glm::ivec4(int(rsm.resolution), int(rsm.layers), int(factor), int(reduced.resolution));
    push.params.y = mergeRadius;
    rg::ComputePass(graph, prefix + ".inject.reduce", injector.rsmReduce[factor == 4])
        .push(push)
        .read(LPV_INJECT_BINDING_POSITION, rsm.position)
        .read(LPV_INJECT_BINDING_NORMAL, rsm.normal)
        .read(LPV_INJECT_BINDING_FLUX, rsm.flux)
        .overwrite(LPV_REDUCE_BINDING_POSITION, reduced.position)
        .overwrite(LPV_REDUCE_BINDING_NORMAL, reduced.normal)
        .overwrite(LPV_REDUCE_BINDING_FLUX, reduced.flux)
        .dispatch({reduced.resolution, reduced.resolution, reduced.layers});
    return reduced;
}

InjectionResult addInjectionPasses(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                   VkFormat format, const std::vector<RsmInput>& rsms, ShHandles wavefront,
                                   ShHandles accumulation, rg::BufferHandle buffer, const std::string& prefix) {
    const glm::ivec3 cells(grid.size);
    if (!buffer.valid())
        buffer = graph.createBuffer(prefix + ".injection",
                                    {injectionBufferBytes(cells), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT});
    // One fixed-point scale for all sums: every texel of every RSM may land in one cell.
    float texels = 0.0f;
    for (const RsmInput& rsm : rsms)
        texels += float(rsm.resolution) * float(rsm.resolution) * float(rsm.layers);
    auto pushFor = [&](const RsmInput& rsm) {
        gpu::LpvInjectPush push{};
        push.grid = grid;
        push.rsm = glm::ivec4(int(rsm.resolution), int(rsm.layers), int(rsm.factor), int(rsm.sourceResolution));
        push.params = glm::vec4(gpu::lpvFixedPointScale(texels), rsm.nearLightRadius, 0.0f, 0.0f);
        return push;
    };
    addClearPass(graph, prefix + ".inject.clear", buffer);
    // Every range pass before the first injection: each texel is divided by the final M.
    for (const RsmInput& rsm : rsms)
        rg::ComputePass(graph, prefix + ".inject" + rsm.label + ".range", injector.fluxRange)
            .push(pushFor(rsm))
            .read(LPV_INJECT_BINDING_POSITION, rsm.position)
            .read(LPV_INJECT_BINDING_FLUX, rsm.flux)
            .write(LPV_INJECT_BINDING_BUFFER, buffer)
            .dispatch({rsm.resolution, rsm.resolution, rsm.layers});
    for (const RsmInput& rsm : rsms) {
        // One invocation per run of LPV_INJECT_RUN texels of a row.
        const uint32_t runs = (rsm.resolution + LPV_INJECT_RUN - 1) / LPV_INJECT_RUN;
        // Without reduction the source bindings take the RSM itself (the shader never reads them then).
        const bool reduced = rsm.factor > 1;
        rg::ComputePass(graph, prefix + ".inject" + rsm.label, injector.inject)
            .push(pushFor(rsm))
            .read(LPV_INJECT_BINDING_POSITION, rsm.position)
            .read(LPV_INJECT_BINDING_NORMAL, rsm.normal)
            .read(LPV_INJECT_BINDING_FLUX, rsm.flux)
            .read(LPV_INJECT_BINDING_SOURCE_POSITION, reduced ? rsm.sourcePosition : rsm.position)
            .read(LPV_INJECT_BINDING_SOURCE_NORMAL, reduced ? rsm.sourceNormal : rsm.normal)
            .read(LPV_INJECT_BINDING_SOURCE_FLUX, reduced ? rsm.sourceFlux : rsm.flux)
            .read(LPV_INJECT_BINDING_SHADOW_VIEWS, rsm.views)
            .write(LPV_INJECT_BINDING_BUFFER, buffer)
            .dispatch({runs, rsm.resolution, rsm.layers});
    }
    rg::ComputePass(graph, prefix + ".inject.resolve", injector.resolve[format == VK_FORMAT_R32G32B32A32_SFLOAT])
        .push(pushFor(rsms.front()))
        .read(LPV_RESOLVE_BINDING_BUFFER, buffer)
        .overwrite(LPV_RESOLVE_BINDING_WAVEFRONT_R, wavefront.channel[0])
        .overwrite(LPV_RESOLVE_BINDING_WAVEFRONT_G, wavefront.channel[1])
        .overwrite(LPV_RESOLVE_BINDING_WAVEFRONT_B, wavefront.channel[2])
        .overwrite(LPV_RESOLVE_BINDING_ACCUMULATION_R, accumulation.channel[0])
        .overwrite(LPV_RESOLVE_BINDING_ACCUMULATION_G, accumulation.channel[1])
        .overwrite(LPV_RESOLVE_BINDING_ACCUMULATION_B, accumulation.channel[2])
        .dispatch(glm::uvec3(cells));
    return {wavefront, accumulation, buffer};
}

namespace {

// The camera's G-buffer is sampled every `stride` pixels per axis, each sample's area estimated
// from the samples `stride` pixels away (the same area estimator, stride^2 times the area, so
// the coverage sum is unchanged). The stride keeps at least kSamplesPerCell samples per LPV cell
// per axis when the whole grid spans the image; closer views sample denser. Small images, or
// fine grids, get stride 1.
uint32_t cameraSampleStride(const gpu::LpvGrid& grid, const GBufferInput& gbuffer) {
    constexpr uint32_t kSamplesPerCell = 4;
    const uint32_t cells = uint32_t(std::max({grid.size.x, grid.size.y, grid.size.z, 1}));
    return std::clamp(std::max(gbuffer.width, gbuffer.height) / (kSamplesPerCell * cells), 1u, 4u);
}

// One source's surfels (every `stride`-th texel per axis of `texels`) added to the slot
// `push.rsm.z` of the geometry volume sums.
// The RSM pass also binds the full RSM behind a reduced one (`source`; the RSM itself otherwise).
void addSurfelPass(rg::RenderGraph& graph, const std::string& name, const Pipeline& pipeline,
                   const gpu::LpvInjectPush& push, rg::ImageHandle position, rg::ImageHandle normal, glm::uvec3 threads,
                   rg::BufferHandle& sums, const RsmInput* source = nullptr) {
    rg::ComputePass pass(graph, name, pipeline);
    pass.push(push)
        .read(LPV_GEOMETRY_VOLUME_BINDING_POSITION, position)
        .read(LPV_GEOMETRY_VOLUME_BINDING_NORMAL, normal)
        .write(LPV_GEOMETRY_VOLUME_BINDING_SUMS, sums);
    if (source) {
        const bool reduced = source->factor > 1;
        pass.read(LPV_GEOMETRY_VOLUME_BINDING_SOURCE_POSITION, reduced ? source->sourcePosition : position)
            .read(LPV_GEOMETRY_VOLUME_BINDING_SOURCE_NORMAL, reduced ? source->sourceNormal : normal);
    }
    pass.dispatch(threads);
}

} // namespace

rg::ImageHandle addGeometryVolumePasses(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                        const RsmInput& rsm, const GBufferInput& gbuffer, const std::string& prefix) {
    const glm::ivec3 corners = glm::ivec3(grid.size) + 1;
    const size_t cornerCount = size_t(corners.x) * corners.y * corners.z;
    rg::BufferHandle sums =
        graph.createBuffer(prefix + ".gv.sums", {VkDeviceSize(LPV_INJECT_HEADER_INTS + 2 * 4 * cornerCount) * 4,
                                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT});
    ImageDesc desc;
    desc.type = VK_IMAGE_TYPE_3D;
    desc.format = kGeometryVolumeFormat;
    desc.width = uint32_t(corners.x);
    desc.height = uint32_t(corners.y);
    desc.depth = uint32_t(corners.z);
    desc.usage = VK_IMAGE_USAGE_STORAGE_BIT;
    rg::ImageHandle geometryVolume = graph.createImage(prefix + ".gv", desc);
    gpu::LpvInjectPush push{};
    push.grid = grid;
    push.params = glm::vec4(float(LPV_GEOMETRY_VOLUME_FIXED_SCALE), 0.0f, 0.0f, 0.0f);
    addClearPass(graph, prefix + ".gv.clear", sums);
    if (rsm.position.valid()) {
        push.rsm = glm::ivec4(int(rsm.resolution), int(rsm.layers), 0, int(rsm.resolution)); // slot 0
        push.params.y = 1.0f;
        push.params.z = float(rsm.factor);
        push.params.w = float(rsm.sourceResolution);
        addSurfelPass(graph, prefix + ".gv.rsm", injector.geometryFromRsm, push, rsm.position, rsm.normal,
                      {rsm.resolution, rsm.resolution, rsm.layers}, sums, &rsm);
        push.params.z = push.params.w = 0.0f;
    }
    if (gbuffer.position.valid()) {
        const uint32_t stride = cameraSampleStride(grid, gbuffer);
        push.rsm = glm::ivec4(int(gbuffer.width), 1, 1, int(gbuffer.height)); // slot 1
        push.params.y = float(stride);
        addSurfelPass(graph, prefix + ".gv.camera", injector.geometryFromCamera, push, gbuffer.position, gbuffer.normal,
                      {(gbuffer.width + stride - 1) / stride, (gbuffer.height + stride - 1) / stride, 1}, sums);
    }
    rg::ComputePass(graph, prefix + ".gv.resolve", injector.geometryResolve)
        .push(push)
        .read(LPV_GEOMETRY_VOLUME_BINDING_SUMS, sums)
        .overwrite(LPV_GEOMETRY_VOLUME_BINDING_OUTPUT, geometryVolume)
        .dispatch(glm::uvec3(corners));
    return geometryVolume;
}

rg::ImageHandle addAccumulationSumPass(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                       const ShHandles& accumulation, rg::ImageHandle sum, const std::string& prefix) {
    // A copy: creating the sum below may grow the graph's resource table.
    const ImageDesc accumulationDesc = graph.imageDesc(accumulation.channel[0]);
    const glm::uvec3 cells(accumulationDesc.width, accumulationDesc.height, accumulationDesc.depth);
    if (!sum.valid())
        sum = graph.createImage(prefix + ".accumulation.sum", shImageDesc(glm::ivec3(cells), accumulationDesc.format));
    gpu::LpvInjectPush push{};
    push.grid = grid;
    rg::ComputePass(graph, prefix + ".lookup.sum",
                    injector.channelSum[accumulationDesc.format == VK_FORMAT_R32G32B32A32_SFLOAT])
        .push(push)
        .read(LPV_SUM_BINDING_ACCUMULATION_R, accumulation.channel[0])
        .read(LPV_SUM_BINDING_ACCUMULATION_G, accumulation.channel[1])
        .read(LPV_SUM_BINDING_ACCUMULATION_B, accumulation.channel[2])
        .overwrite(LPV_SUM_BINDING_OUTPUT, sum)
        .dispatch(cells);
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
        output = graph.createImage(prefix + ".indirect", desc);
    }
    gpu::LpvLookupPush push{};
    push.grid = grid;
    push.image = glm::ivec4(int(gbuffer.width), int(gbuffer.height), 0, 0);
    push.params = glm::vec4(damping, blend.fadeBorder ? 1.0f : 0.0f, blend.accumulate ? 1.0f : 0.0f, 0.0f);
    push.image.z = int(std::min<size_t>(blend.finer.size(), 2));
    for (size_t k = 0; k < blend.finer.size() && k < 2; ++k)
        push.finer[k] = blend.finer[k];
    // The channel sum the damping reads (one fetch per damping point instead of three). Without
    // damping the shader never samples it, and the binding takes the red channel instead.
    if (damping > 0.0f && !sum.valid())
        sum = addAccumulationSumPass(graph, injector, grid, accumulation, {}, prefix);
    const VkSampler linear = injector.linearSampler;
    rg::ComputePass pass(graph, prefix + ".lookup", injector.lookup);
    pass.push(push)
        .read(LPV_LOOKUP_BINDING_POSITION, gbuffer.position)
        .read(LPV_LOOKUP_BINDING_NORMAL, gbuffer.normal)
        .read(LPV_LOOKUP_BINDING_ALBEDO, gbuffer.albedo)
        .sample(LPV_LOOKUP_BINDING_ACCUMULATION_R, accumulation.channel[0], linear)
        .sample(LPV_LOOKUP_BINDING_ACCUMULATION_G, accumulation.channel[1], linear)
        .sample(LPV_LOOKUP_BINDING_ACCUMULATION_B, accumulation.channel[2], linear)
        .sample(LPV_LOOKUP_BINDING_SUM, sum.valid() ? sum : accumulation.channel[0], linear)
        .read(LPV_LOOKUP_BINDING_BUFFER, buffer);
    // A finer cascade wrote the output first: this one adds to it, otherwise it replaces it.
    if (blend.accumulate)
        pass.write(LPV_LOOKUP_BINDING_OUTPUT, output);
    else
        pass.overwrite(LPV_LOOKUP_BINDING_OUTPUT, output);
    pass.dispatch({gbuffer.width, gbuffer.height, 1});
    return output;
}

} // namespace vkgi::gi::lpv
