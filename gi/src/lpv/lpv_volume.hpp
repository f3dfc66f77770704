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

// The compute pipelines of one propagation step, for both SH formats.
class Propagator {
public:
    static Result<Propagator> create(Context& ctx);
    void destroy(Context& ctx);

    // One gather step dst = propagate(src), acc += dst, over a grid of `cells`. Every image
    // must be in GENERAL layout with earlier writes visible. `geometryVolume` has cells + 1
    // texels per axis and is only read when `occlusion` is set (any RGBA16F 3D view otherwise).
    void record(const Context& ctx, VkCommandBuffer cmd, VkFormat format, glm::ivec3 cells, const ShViews& src,
                const ShViews& dst, const ShViews& acc, VkImageView geometryVolume, bool occlusion) const;

    // 1^3 RGBA16F image in GENERAL layout, bound as the geometry volume when occlusion is off
    // (the binding exists in both specializations); never read.
    const Image& noGeometry() const { return m_noGeometry; }

private:
    Pipeline m_pipelines[2][2]; // [RGBA32F?][occlusion?]
    Image m_noGeometry;
};

} // namespace vkgi::gi::lpv
