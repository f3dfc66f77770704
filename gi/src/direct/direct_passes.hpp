#pragma once
// The shared passes every technique builds on: G-buffer, per-light shadow map (+ RSM),
// deferred direct lighting, composite and readback. One source file per pass; this header is
// private to gi/.
#include <string>
#include <vector>

#include "vkgi/gpu_scene.hpp"
#include "vkgi/pipeline.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "gi/direct_types.h"
#include "vkgi/frame_data.hpp"
#include "vkgi/gi.hpp"

namespace vkgi::gi {

struct DirectPipelines {
    Pipeline gbuffer;
    Pipeline shadow;
    Pipeline rsm;
    // The same two without the texture lookup, for scenes without textures (surface.h).
    Pipeline gbufferUntextured;
    Pipeline rsmUntextured;
    Pipeline deferred;
    Pipeline composite;
    Pipeline hostPosition; // host G-buffer path (host_gbuffer.cpp)
    VkSampler pointSampler = VK_NULL_HANDLE;  // texelFetch-only images still need a sampler
    VkSampler shadowSampler = VK_NULL_HANDLE; // depth compare, bilinear (PCF)
};
Result<DirectPipelines> createDirectPipelines(Context& ctx);
void destroyDirectPipelines(Context& ctx, DirectPipelines& p);

// G-buffer formats (documented in vkgi/frame_data.hpp).
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr VkFormat kPositionFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kNormalFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kAlbedoFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kEmissionFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kRadianceFormat = VK_FORMAT_R32G32B32A32_SFLOAT; // 32F: 1e9 cd stays finite
constexpr VkFormat kRsmFluxFormat = VK_FORMAT_R32G32B32A32_SFLOAT;  // per-texel flux ~1e-5 I: below half's normals

// Which lights get which atlas layers, and each layer's projection. Pure CPU.
struct LightShadowPlan {
    uint32_t light = 0;
    uint32_t kind = GI_SHADOW_NONE;
    uint32_t firstLayer = 0;
    uint32_t layerCount = 0;
    uint32_t faceMask = 0; // cube faces that can see the light's cone (others are only cleared)
    // Directional lights: shadow-only cascade layers fitted to the camera (cascades.hpp), which
    // the deferred pass reads instead of the whole-scene layer where they hold the receiver. They
    // follow the atlas's light layers (layerCount), so RSM arrays never include them.
    uint32_t cascadeFirst = 0;
    uint32_t cascadeCount = 0;
    // Directional lights: shadow-only window layers, one per leading box of planShadows'
    // `shadowWindows` (window k in layer windowFirst + k), after every light's cascades.
    uint32_t windowFirst = 0;
    uint32_t windowCount = 0;
    // Directional lights with an RSM window (planShadows' rsmWindow): the RSM layer is rendered
    // from this view, fitted to the window, in a pass of its own; the own atlas layer keeps the
    // whole scene for the shadow lookups. Without it the RSM shares the own layer's view.
    bool rsmWindowed = false;
    gpu::GpuShadowView rsmView{};
};
struct ShadowLayout {
    std::vector<LightShadowPlan> lights;   // one per scene light
    std::vector<gpu::GpuShadowView> views; // one per atlas layer: light, then cascade, then window layers
    std::vector<ShadowLayer> layers;       // one per light layer (the RSM's layers)
    uint32_t resolution = 0;
    uint32_t lightLayers() const { return uint32_t(layers.size()); }
};
// What the cascades of directional lights are fitted to; count 0 = no cascades.
struct CascadeRequest {
    uint32_t count = 0;
    Camera camera;
    float aspect = 1.0f;
    float marginTexels = 0.0f; // the deferred pass's PCF reach plus normal offset, in texels (also
                               // the shadow windows' margin, with or without cascades)
};
// Every light's own layers first (lights past `maxLayers` stay unshadowed, as without cascades);
// then cascades for directional lights while the atlas has room. A light keeps the leading
// cascades whose texels are finer than its whole-scene layer (all of them in a large world, the
// near slices where the camera sees most of the scene); receivers beyond them use that layer.
// `rsmWindow` (when valid): the region whose RSM texels the technique reads. A directional
// light's RSM is then rendered for that region alone (depth still spanning the scene toward
// the sun) when that makes its texels at least twice as fine: the LPV's cascades in a large
// world read a few tens of metres of a sun's RSM that otherwise covers hundreds.
// `shadowWindows` (TechniqueModule::shadowWindows, finest first): boxes whose points a technique
// looks up in the atlas. After all cascades, each directional light gets one depth-only layer per
// window (windowView of the window clipped to the bounds, margin cascades.marginTexels) while the
// atlas has room, up to kMaxShadowWindows; it keeps the leading windows whose texels are finer
// than its whole-scene layer, and the first one that is not ends the list (its points and those
// of every later window read the whole-scene layer).
ShadowLayout planShadows(const Scene& scene, const Aabb& bounds, uint32_t resolution, uint32_t maxLayers,
                         const CascadeRequest& cascades = {}, const Aabb& rsmWindow = {},
                         const std::vector<Aabb>& shadowWindows = {});
// Most shadow windows a light gets (the bits of addLightPasses' keep mask).
constexpr uint32_t kMaxShadowWindows = 32;

// The 6 cube-face views of a point light at `eye` reaching every corner of `bounds` (the views
// planShadows gives a point light without a range): +x, -x, +y, -y, +z, -z.
std::vector<gpu::GpuShadowView> cubeShadowViews(const glm::vec3& eye, const Aabb& bounds, uint32_t resolution);

// Transient images in the RSM's formats (kPositionFormat, kNormalFormat, kRsmFluxFormat: the
// layout of RsmData in vkgi/frame_data.hpp), storage and sampled, with at least 2 layers so
// that their readers' views are 2D arrays: the LPV's reduced RSM and the emissive surfels.
struct RsmImages {
    rg::ImageHandle position, normal, flux;
};
RsmImages createRsmImages(rg::RenderGraph& graph, const std::string& prefix, uint32_t resolution, uint32_t layers);

// Persistent shadow atlas and RSM arrays (recreated when the layer count or size changes),
// sampled through 2D-array views and rendered one layer at a time (PassContext::layerView).
struct ShadowTargets {
    rg::PersistentImage atlas;
    rg::PersistentImage rsmPosition;
    rg::PersistentImage rsmNormal;
    rg::PersistentImage rsmFlux;
    uint32_t layers = 0;
    uint32_t rsmLayers = 0;
    uint32_t resolution = 0;
    bool rsm = false;
    VkDeviceSize bytes() const;
};
// `layers` atlas layers; the RSM arrays get the first `rsmLayers` (the lights' own layers).
void ensureShadowTargets(Context& ctx, ShadowTargets& t, uint32_t layers, uint32_t rsmLayers, uint32_t resolution,
                         bool rsm);
void destroyShadowTargets(Context& ctx, ShadowTargets& t);

SceneHandles importScene(rg::RenderGraph& graph, const GpuScene& scene);

GBufferData addGBufferPass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                           const SceneHandles& scene);

// "gi.light[i].spot|point|directional": the name of light i's shadow/RSM pass.
std::string lightPassName(uint32_t light, LightType type);

// One pass per shadowed light ("gi.light[i].spot|point|directional"), writing the atlas layers
// of that light and, when `rsm`, the RSM arrays. Adds ShadowData (and RsmData) to `blackboard`.
// Lights with `keep[i]` true get no pass: their persistent layers still hold this frame's content.
// Each cascade of a directional light is one more pass ("gi.light[i].directional.cascade[k]",
// depth only), left out when bit k of `keepCascades[i]` is set; so is an RSM window
// (rsmWindowPassName), left out when `keepWindows[i]` is true; and each shadow window layer
// (windowPassName, depth only), left out when bit k of `keepShadowWindows[i]` is set.
void addLightPasses(rg::RenderGraph& graph, rg::Blackboard& blackboard, const DirectPipelines& p,
                    const FrameData& frame, const SceneHandles& scene, const ShadowLayout& layout,
                    ShadowTargets& targets, bool rsm, const std::vector<bool>& keep = {},
                    const std::vector<uint32_t>& keepCascades = {}, const std::vector<bool>& keepWindows = {},
                    const std::vector<uint32_t>& keepShadowWindows = {});
std::string cascadePassName(uint32_t light, uint32_t cascade);
std::string windowPassName(uint32_t light, uint32_t window); // "gi.light[i].directional.window[k]"
std::string rsmWindowPassName(uint32_t light); // "gi.light[i].directional.rsm"

// The RSM of point sources that are not scene lights (the LPV's emitter proxies, docs/lpv.md):
// layer l rendered from views[l] with the GpuLight lights[l / 6] (cube faces, cubeShadowViews),
// by the RSM pipeline of the light passes, into transient RSM images `<name>.*` with a transient
// depth array of their own. One pass, `name`.
RsmImages addPointSourceRsmPass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                                const SceneHandles& scene, rg::BufferHandle lights,
                                const std::vector<gpu::GpuShadowView>& views, uint32_t resolution,
                                const std::string& name);

DirectData addDeferredPass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                           const SceneHandles& scene, const GBufferData& gbuffer, const ShadowData& shadow);

CompositeData addCompositePass(rg::RenderGraph& graph, const DirectPipelines& p, const FrameData& frame,
                               rg::ImageHandle direct, rg::ImageHandle indirect);

// Copies an RGBA32F image into `dst` (host-visible, width*height*16 bytes) after the frame.
void addReadbackPass(rg::RenderGraph& graph, const std::string& name, rg::ImageHandle image, const Buffer& dst);
// Converts a readback buffer to an HdrImage (RGB of the RGBA32F texels).
enum class ReadbackChannels { Rgb, AlphaToRgb }; // AlphaToRgb: r = g = b = the texel's alpha (AO)
HdrImage readbackToImage(const Buffer& src, uint32_t width, uint32_t height,
                         ReadbackChannels channels = ReadbackChannels::Rgb);

// One indexed draw per instance of `scene` with `push` (info.x set per draw); pipeline and set 1
// must be bound.
void drawScene(VkCommandBuffer cmd, const Pipeline& pipeline, const GpuScene& scene, VkBuffer indices,
               gpu::RasterPush push);

// Begins dynamic rendering of a full-extent area with cleared attachments (colour 0, depth 1).
void beginRendering(VkCommandBuffer cmd, VkExtent2D extent, const std::vector<VkImageView>& colors,
                    VkImageView depth);

} // namespace vkgi::gi
