#include "lpv/lpv_passes.hpp"

#include <string>
#include <utility>

namespace vkgi::gi::lpv {

using rg::Access;

ImageDesc shImageDesc(glm::ivec3 cells, VkFormat format) {
    ImageDesc desc;
    desc.type = VK_IMAGE_TYPE_3D;
    desc.format = format;
    desc.width = uint32_t(cells.x);
    desc.height = uint32_t(cells.y);
    desc.depth = uint32_t(cells.z);
    desc.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
    return desc;
}

ShHandles createShVolume(rg::RenderGraph& graph, const char* name, glm::ivec3 cells, VkFormat format) {
    ShHandles h;
    const char* suffix[3] = {".r", ".g", ".b"};
    for (int c = 0; c < 3; ++c)
        h.channel[c] = graph.createImage(std::string(name) + suffix[c], shImageDesc(cells, format));
    return h;
}

PropagationVolumes addPropagationPasses(rg::RenderGraph& graph, const Propagator& propagator, glm::ivec3 cells,
                                        VkFormat format, PropagationVolumes volumes, rg::ImageHandle geometryVolume,
                                        uint32_t iterations, const VoxelInput& voxels, glm::vec4 lpvOrigin,
                                        const std::string& prefix) {
    if (iterations == 0)
        return volumes;
    const bool occlusion = geometryVolume.valid();
    const bool bounce = voxels.albedo.valid();
    rg::ImageHandle gv = occlusion ? geometryVolume : graph.importImage("gi.lpv.gv.none", propagator.noGeometry(),
                                                                         Access::ComputeStorageRead);
    rg::ImageHandle voxelAlbedo = voxels.albedo, voxelNormal = voxels.normal;
    if (!bounce)
        voxelAlbedo = voxelNormal =
            graph.importImage("gi.lpv.voxels.none", propagator.noVoxels(), Access::ComputeSampledRead);
    PropagateStep step;
    step.cells = cells;
    step.format = format;
    step.occlusion = occlusion;
    step.bounce = bounce;
    step.lpvOrigin = lpvOrigin;
    if (bounce)
        step.voxelOrigin = glm::vec4(glm::vec3(voxels.originSize), 1.0f / (voxels.originSize.w * float(voxels.resolution)));
    const Propagator* prop = &propagator;
    for (uint32_t k = 0; k < iterations; ++k) {
        ShHandles src = volumes.wavefront, dst = volumes.scratch, acc = volumes.accumulation;
        // Steps accumulate in pairs: the second of each adds both wavefronts; an unpaired last step its own.
        const uint32_t accumulate = k % 2 == 1 ? LPV_ACCUMULATE_PAIR
                                    : k + 1 == iterations ? LPV_ACCUMULATE_OWN
                                                          : LPV_ACCUMULATE_NONE;
        graph.addPass(
            prefix + ".propagate[" + std::to_string(k) + "]",
            [&](rg::PassBuilder& b) {
                b.read(gv, Access::ComputeStorageRead);
                b.read(voxelAlbedo, Access::ComputeSampledRead);
                if (voxelNormal.index != voxelAlbedo.index)
                    b.read(voxelNormal, Access::ComputeSampledRead);
                for (int c = 0; c < 3; ++c) {
                    b.read(src.channel[c], Access::ComputeStorageRead);
                    dst.channel[c] = b.write(dst.channel[c], Access::ComputeStorageWriteDiscard);
                    acc.channel[c] = b.write(acc.channel[c], Access::ComputeStorageReadWrite);
                }
            },
            [=](rg::PassContext& ctx) {
                ShViews s, d, a;
                for (int c = 0; c < 3; ++c) {
                    s.channel[c] = ctx.view(src.channel[c]);
                    d.channel[c] = ctx.view(dst.channel[c]);
                    a.channel[c] = ctx.view(acc.channel[c]);
                }
                PropagateStep bound = step;
                bound.accumulate = accumulate;
                bound.geometryVolume = ctx.view(gv);
                bound.voxelAlbedo = ctx.view(voxelAlbedo);
                bound.voxelNormal = ctx.view(voxelNormal);
                prop->record(ctx.context(), ctx.cmd(), bound, s, d, a);
            });
        volumes.scratch = src;
        volumes.wavefront = dst;
        volumes.accumulation = acc;
    }
    return volumes;
}

} // namespace vkgi::gi::lpv
