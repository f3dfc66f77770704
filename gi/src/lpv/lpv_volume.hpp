#pragma once
// GPU side of the light propagation volume: SH volumes (one 3D image per colour channel, 4
// coefficients per texel) and the propagation step recorder. Recording functions only bind,
// push and dispatch: layouts and barriers come from the render graph, never from here.
#include <array>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "engine/pipeline.hpp"
#include "engine/resources.hpp"
#include "engine/result.hpp"
#include "gi/lpv.h"

namespace vkgi::gi::lpv {

// Storage formats of SH volumes: RGBA16F halves bandwidth, RGBA32F is the reference.
bool isSupportedShFormat(VkFormat format);

// Three images (R, G, B) of `cells` texels in `format`; storage + sampled (trilinear lookup).
struct ShImages {
    std::array<Image, 3> channel;
};
ShImages createShImages(Context& ctx, glm::ivec3 cells, VkFormat format, const char* name);
void destroyShImages(Context& ctx, ShImages& images);

// Views of the three channel images of one volume, as a pass sees them.
struct ShViews {
    std::array<VkImageView, 3> channel{};
};
inline ShViews viewsOf(const ShImages& images) {
    return {{images.channel[0].view, images.channel[1].view, images.channel[2].view}};
}

// Geometry-volume storage format (blocking potential SH in [0, 1] per coefficient magnitude).
constexpr VkFormat kGeometryVolumeFormat = VK_FORMAT_R16G16B16A16_SFLOAT;

// What one propagation step binds (views in GENERAL layout, voxel views in
// SHADER_READ_ONLY_OPTIMAL) besides the three SH volumes.
struct PropagateStep {
    glm::ivec3 cells{0};
    VkFormat format = VK_FORMAT_R16G16B16A16_SFLOAT;
    bool occlusion = false;  // read the geometry volume (cells + 1 texels per axis, RGBA16F)
    bool bounce = false;     // reflect at occupied voxels of the shared voxel grid
    uint32_t accumulate = LPV_ACCUMULATE_OWN; // what the step adds to acc (LPV_ACCUMULATE_*, gi/lpv.h)
    glm::vec4 lpvOrigin{0};  // xyz world min corner, w cell size (bounce only)
    glm::vec4 voxelOrigin{0}; // xyz world min corner, w 1 / (voxel size * N) (bounce only)
    VkImageView geometryVolume = VK_NULL_HANDLE; // noGeometry() when !occlusion
    VkImageView voxelAlbedo = VK_NULL_HANDLE;    // noVoxels() when !bounce
    VkImageView voxelNormal = VK_NULL_HANDLE;
};

// The compute pipelines of one propagation step, for both SH formats and every combination of
// occlusion and bounce (specialization constants, so the free-space step carries no dead code).
class Propagator {
public:
    static Result<Propagator> create(Context& ctx);
    void destroy(Context& ctx);

    // One gather step dst = propagate(src); acc += dst, src + dst or nothing (step.accumulate).
    // Earlier writes must be visible.
    void record(const Context& ctx, VkCommandBuffer cmd, const PropagateStep& step, const ShViews& src,
                const ShViews& dst, const ShViews& acc) const;

    // 1^3 RGBA16F image in GENERAL layout, bound as the geometry volume when occlusion is off
    // (the binding exists in every specialization); never read.
    const Image& noGeometry() const { return m_noGeometry; }
    // 1^3 RGBA8 image in SHADER_READ_ONLY_OPTIMAL layout standing in for the voxel grid.
    const Image& noVoxels() const { return m_noVoxels; }

private:
    Pipeline m_pipelines[2][2][2][3]; // [RGBA32F?][occlusion?][bounce?][accumulate]
    Image m_noGeometry;
    Image m_noVoxels;
    VkSampler m_linear = VK_NULL_HANDLE;
};

} // namespace vkgi::gi::lpv
