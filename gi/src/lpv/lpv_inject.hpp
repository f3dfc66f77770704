#pragma once
// LPV injection from the shared RSM and the per-pixel lookup, as render-graph passes:
//   gi.lpv.inject.clear    zero the injection buffer
//   gi.lpv.inject.range    M = largest RSM texel flux (the unit of every stored SH value)
//   gi.lpv.inject          surfels -> fixed-point SH sums per cell (integer atomics)
//   gi.lpv.inject.resolve  sums -> first wavefront and accumulation volumes
//   gi.lpv.gv.*            geometry volume from RSM and camera surfels, combined by max
//   gi.lpv.lookup.sum      channel sum R + G + B of the accumulated SH (the damping's input)
//   gi.lpv.lookup          accumulated SH -> indirect radiance per G-buffer pixel
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "vkgi/rg/render_graph.hpp"
#include "gi/lpv_passes.h"
#include "lpv/lpv_passes.hpp"

namespace vkgi::gi::lpv {

// The pipelines and the sampler of the passes around propagation: RSM reduction, injection,
// geometry volume, channel sum and lookup. The graph code in lpv_inject.cpp binds every resource.
class Injector {
public:
    static Result<Injector> create(Context& ctx);
    void destroy(Context& ctx);

    Pipeline fluxRange;                           // inject_range.comp: M, the largest RSM texel flux
    Pipeline inject;                              // inject.comp: surfels -> fixed-point SH sums
    Pipeline resolve[2];                          // inject_resolve: [RGBA32F?]
    Pipeline rsmReduce[2];                        // inject_reduce.comp: factor 2, 4
    Pipeline geometryFromRsm, geometryFromCamera; // gv_inject_rsm / gv_inject_camera.comp
    Pipeline geometryResolve;                     // gv_resolve.comp
    Pipeline channelSum[2];                       // lookup_sum: [RGBA32F?]
    Pipeline lookup;                              // lookup.comp
    VkSampler linearSampler = VK_NULL_HANDLE;     // trilinear SH lookup, clamp to edge (RSM and G-buffer: imageLoad)
};

// The reflective shadow map as the direct-lighting module publishes it (vkgi/frame_data.hpp):
// 2D arrays, position RGBA32F (w = 1 valid), normal RGBA16F, flux RGBA32F.
struct RsmInput {
    rg::ImageHandle position, normal, flux;
    uint32_t resolution = 0;
    uint32_t layers = 0;
    // A reduced RSM (addRsmReducePass) keeps the full one it came from: blocks that one surfel
    // cannot stand for are read from it texel by texel. factor = 1: not reduced (no source).
    rg::ImageHandle sourcePosition, sourceNormal, sourceFlux;
    uint32_t sourceResolution = 0;
    uint32_t factor = 1;
    // The shadow atlas's GpuShadowView per layer (ShadowData::views): the injection leaves out
    // surfels closer than nearLightRadius (world units) to their point or spot light
    // (gpu::lpvInjectsNearLight).
    rg::BufferHandle views;
    float nearLightRadius = 0.0f;
    // Inserted after "<prefix>.inject" in the names of this RSM's injection passes ("" for the
    // lights' RSM, ".emitter" for the emitter proxies' RSM: "gi.lpv.inject.emitter").
    std::string label;
};

struct GBufferInput {
    rg::ImageHandle position, normal, albedo;
    uint32_t width = 0, height = 0;
};

struct InjectionResult {
    ShHandles wavefront;
    ShHandles accumulation;
    rg::BufferHandle buffer; // the injection buffer: its header holds M, read by the lookup
};

// The RSM reduced by `factor` per axis (gi.lpv.inject.reduce, inject_reduce.comp): one surfel per
// factor x factor block, flux summed, position and normal flux-weighted means (the normal not
// renormalised). Injection and the geometry volume then read factor^2 fewer texels. A block
// whose texels lie off their mean plane by an RMS distance above mergeRadius (world units;
// mergeRadius is half the finest cell: a roof's edge over the ground), or whose unit normals'
// mean is shorter than 1/2 (a sharp fold), is marked split and read texel by texel from `rsm`.
// Returns transient images in the RSM's formats.
RsmInput addRsmReducePass(rg::RenderGraph& graph, const Injector& injector, const RsmInput& rsm, uint32_t factor,
                          float mergeRadius, const std::string& prefix = "gi.lpv");

// Injects every texel of every RSM in `rsms` (at least one) into `grid`, writing (fully) the
// given wavefront and accumulation volumes. M is the largest texel flux over all of them.
// `buffer` is the injection buffer, e.g. an imported one kept for the lookup of later frames
// (invalid handle: a transient is created).
InjectionResult addInjectionPasses(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                   VkFormat format, const std::vector<RsmInput>& rsms, ShHandles wavefront,
                                   ShHandles accumulation, rg::BufferHandle buffer = {},
                                   const std::string& prefix = "gi.lpv");

// Size in bytes of the injection buffer of a grid.
VkDeviceSize injectionBufferBytes(glm::ivec3 cells);

// Geometry volume ((cells + 1)^3, RGBA16F, centred on the LPV cell corners) from the RSM
// surfels and the camera's G-buffer surfels, in separate sums combined by max. Either source may
// be absent (invalid position handle). Returns the (transient) GV image.
rg::ImageHandle addGeometryVolumePasses(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                        const RsmInput& rsm, const GBufferInput& gbuffer,
                                        const std::string& prefix = "gi.lpv");

// How one cascade's lookup blends with the others: it is weighted by its own border fade
// (when `fadeBorder`) times (1 - fade) of each finer cascade, and added to `output` when
// `accumulate` (the finest cascade writes first).
struct CascadeBlend {
    bool fadeBorder = false;
    bool accumulate = false;
    std::vector<gpu::LpvGrid> finer; // at most 2
};

// The channel sum R + G + B of the accumulated SH volume (`<prefix>.lookup.sum`, same size and
// format), which the lookup's damping reads, written into `sum` (invalid: a transient is created).
rg::ImageHandle addAccumulationSumPass(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                                       const ShHandles& accumulation, rg::ImageHandle sum = {},
                                       const std::string& prefix = "gi.lpv");

// Indirect radiance (RGBA32F, G-buffer size) written into `output` (invalid: a transient is
// created). `damping` is the light-bleeding damping strength (0 = off); it reads `sum`, the
// accumulation's channel sum (addAccumulationSumPass), which is added as a transient when invalid.
rg::ImageHandle addLookupPass(rg::RenderGraph& graph, const Injector& injector, const gpu::LpvGrid& grid,
                              const ShHandles& accumulation, rg::BufferHandle buffer, const GBufferInput& gbuffer,
                              float damping, rg::ImageHandle output = {}, const CascadeBlend& blend = {},
                              const std::string& prefix = "gi.lpv", rg::ImageHandle sum = {});

} // namespace vkgi::gi::lpv
