#include "lpv/lpv_passes.hpp"

#include <string>

#include "vkgi/rg/compute_pass.hpp"

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
    // Every specialization declares the geometry volume and voxel bindings: without occlusion or
    // bounce they take the propagator's stand-in images, which the step never reads.
    const bool occlusion = geometryVolume.valid();
    const bool bounce = voxels.albedo.valid();
    if (!occlusion)
        geometryVolume = graph.importImage("gi.lpv.gv.none", propagator.noGeometry(), Access::ComputeStorageRead);
    rg::ImageHandle voxelAlbedo = voxels.albedo, voxelNormal = voxels.normal;
    if (!bounce)
        voxelAlbedo = voxelNormal =
            graph.importImage("gi.lpv.voxels.none", propagator.noVoxels(), Access::ComputeSampledRead);
    gpu::LpvPropagatePush push{};
    push.gridSize = glm::ivec4(cells, 0);
    push.lpvOrigin = lpvOrigin;
    if (bounce)
        push.voxelOrigin =
            glm::vec4(glm::vec3(voxels.originSize), 1.0f / (voxels.originSize.w * float(voxels.resolution)));
    const VkSampler voxelSampler = propagator.voxelSampler();
    for (uint32_t k = 0; k < iterations; ++k) {
        ShHandles source = volumes.wavefront, target = volumes.scratch;
        ShHandles& accumulation = volumes.accumulation;
        // Steps accumulate in pairs: the second of each adds both wavefronts; an unpaired last step its own.
        const uint32_t accumulate = k % 2 == 1            ? LPV_ACCUMULATE_PAIR
                                    : k + 1 == iterations ? LPV_ACCUMULATE_OWN
                                                          : LPV_ACCUMULATE_NONE;
        rg::ComputePass(graph, prefix + ".propagate[" + std::to_string(k) + "]",
                        propagator.pipeline(format, occlusion, bounce, accumulate))
            .push(push)
            .read(LPV_PROPAGATE_BINDING_SOURCE_R, source.channel[0])
            .read(LPV_PROPAGATE_BINDING_SOURCE_G, source.channel[1])
            .read(LPV_PROPAGATE_BINDING_SOURCE_B, source.channel[2])
            .overwrite(LPV_PROPAGATE_BINDING_TARGET_R, target.channel[0])
            .overwrite(LPV_PROPAGATE_BINDING_TARGET_G, target.channel[1])
            .overwrite(LPV_PROPAGATE_BINDING_TARGET_B, target.channel[2])
            .write(LPV_PROPAGATE_BINDING_ACCUMULATION_R, accumulation.channel[0])
            .write(LPV_PROPAGATE_BINDING_ACCUMULATION_G, accumulation.channel[1])
            .write(LPV_PROPAGATE_BINDING_ACCUMULATION_B, accumulation.channel[2])
            .read(LPV_PROPAGATE_BINDING_GEOMETRY_VOLUME, geometryVolume)
            .sample(LPV_PROPAGATE_BINDING_VOXEL_ALBEDO, voxelAlbedo, voxelSampler)
            .sample(LPV_PROPAGATE_BINDING_VOXEL_NORMAL, voxelNormal, voxelSampler)
            .dispatch(glm::uvec3(cells));
        volumes.scratch = source;
        volumes.wavefront = target;
    }
    return volumes;
}

} // namespace vkgi::gi::lpv
