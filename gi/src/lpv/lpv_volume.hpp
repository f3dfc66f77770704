#pragma once
// GPU side of the light propagation volume: SH volumes are one 3D image per colour channel with
// 4 coefficients per texel, and the Propagator owns what a propagation step binds besides
// them. The graph code in lpv_passes.cpp declares, binds and dispatches every step; layouts and
// barriers come from the render graph.
#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "vkgi/pipeline.hpp"
#include "vkgi/resources.hpp"
#include "vkgi/result.hpp"
#include "gi/lpv.h"

namespace vkgi::gi::lpv {

// Storage formats of SH volumes: RGBA16F halves bandwidth, RGBA32F is the reference.
bool isSupportedShFormat(VkFormat format);

// Geometry-volume storage format (blocking potential SH in [0, 1] per coefficient magnitude).
constexpr VkFormat kGeometryVolumeFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

// The compute pipelines of one propagation step, for both SH formats and every combination of
// occlusion, bounce and accumulation (specialization constants, so the free-space step carries
// no dead code), with the sampler and the stand-in images of the optional bindings.
class Propagator {
public:
    static Result<Propagator> create(Context& ctx);
    void destroy(Context& ctx);

    // The step dst = propagate(src) that adds dst, src + dst or nothing to the accumulation
    // (`accumulate`: LPV_ACCUMULATE_*, gi/lpv.h), in SH `format` (isSupportedShFormat).
    const Pipeline& pipeline(VkFormat format, bool occlusion, bool bounce, uint32_t accumulate) const;
    // Trilinear, clamp-to-edge sampler of the voxel grid's albedo and normal volumes.
    VkSampler voxelSampler() const { return m_voxelSampler; }

    // 1^3 RGBA16F image in GENERAL layout, bound as the geometry volume when occlusion is off
    // (the binding exists in every specialization); never read.
    const Image& noGeometry() const { return m_noGeometry; }
    // 1^3 RGBA8 image in SHADER_READ_ONLY_OPTIMAL layout standing in for the voxel grid.
    const Image& noVoxels() const { return m_noVoxels; }

private:
    Pipeline m_pipelines[2][2][2][3]; // [RGBA32F?][occlusion?][bounce?][accumulate]
    Image m_noGeometry;
    Image m_noVoxels;
    VkSampler m_voxelSampler = VK_NULL_HANDLE;
};

} // namespace vkgi::gi::lpv
