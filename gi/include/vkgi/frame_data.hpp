#pragma once
// Render-graph handles the shared GI passes publish on the blackboard (rg::Blackboard, typed):
// a technique's passes read them and add IndirectData. Layouts of the images:
//
// G-buffer (camera resolution, pixel centres, no jitter):
//   depth    D32_SFLOAT          camera clip depth (Camera::projection)
//   position RGBA32F             xyz world position, w = 1 where geometry was drawn, 0 = background.
//                                Stored rather than reconstructed from depth: every technique needs
//                                it and 32-bit floats keep shadow lookups exact at any depth range.
//   normal   RGBA16F             xyz unit shading normal turned towards the camera (for every
//                                surface: reflection is two-sided, as in the path tracer), w = roughness
//   albedo   RGBA16F             rgb Lambertian albedo = baseColor x texture clamped to [0,1], w = metallic
//   emission RGBA32F             rgb nits (front faces, or both sides when doubleSided); 32-bit so
//                                1e-6 and 1e9 nit emitters keep their value (float16 would flush/clamp)
//
// Shadow atlas: one D32 2D array for all lights (ShadowData::layers says whose layer is whose);
// depth is linear (see GpuShadowView in shaders/include/gi/direct_types.h). Spots with an outer
// cone up to kMaxSpotFrustumHalfAngle use one perspective layer covering the cone, wider spots
// and point lights a cube (6 layers, +X,-X,+Y,-Y,+Z,-Z), directional lights one orthographic
// layer fitted around the scene bounds. After all lights' own layers (ShadowData::layers) the
// atlas may hold shadow-only cascade layers of directional lights, fitted to this frame's camera
// (GiSettings::shadowCascades, docs/direct.md); only the deferred direct pass reads them, through
// GpuLightShadow::cascades. Passes that sample the atlas at arbitrary scene points use the
// light's own layer (GpuLightShadow::info), which covers the whole scene.
//
// Reflective shadow map (only when a technique needs it): arrays with the atlas's layers and size,
//   position RGBA32F  xyz world position, w = 1 (0 = no geometry in this texel)
//   normal   RGBA16F  xyz unit normal turned towards the light
//   flux     RGBA32F  rgb flux the texel's surface reflects (Lambertian, into the hemisphere):
//     point/spot:   albedo x I x spot(angle) x rangeWindow(d) x dOmega,
//                   dOmega = a cos^3(theta) the texel's solid angle seen from the light, with
//                   a = (2 tan(fov/2) / N)^2 and theta the angle to the layer's axis; this is the
//                   texel's world area A times the irradiance I cos/d^2 on it, since A = dOmega d^2/cos.
//     directional:  albedo x E x (ortho width / N) x (ortho height / N), the texel's area
//                   perpendicular to the light times the illuminance E (lux).
//   Summed over all texels this is albedo x the light's power reaching the surfaces it sees.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "vkgi/camera.hpp"
#include "vkgi/rg/render_graph.hpp"
#include "vkgi/scene.hpp"

namespace vkgi {
struct GpuScene;
}

namespace vkgi::gi {

struct GiSettings;

// Spots up to this outer half angle get one perspective layer (fov 120 degrees); beyond, the
// texels at the rim would stretch by 1/cos^3 = 8x or more, so wider spots use a cube.
constexpr float kMaxSpotFrustumHalfAngle = 1.0471976f; // 60 degrees

// This frame's camera and scene (always present).
struct FrameData {
    Camera camera;
    uint32_t width = 0;
    uint32_t height = 0;
    glm::mat4 view{1.0f};
    glm::mat4 proj{1.0f};
    glm::mat4 viewProj{1.0f};
    glm::mat4 invViewProj{1.0f};
    VkDescriptorSet frameSet = VK_NULL_HANDLE; // set 0 (FrameConstants) of this frame
    const Scene* scene = nullptr;              // CPU scene as last given to setScene/updateScene
    const GpuScene* gpuScene = nullptr;
    const GiSettings* settings = nullptr;
};

// The scene's device buffers imported into this graph (read-only for every pass).
struct SceneHandles {
    rg::BufferHandle vertices;  // GpuVertex[]
    rg::BufferHandle indices;   // uint32[]
    rg::BufferHandle instances; // GpuInstance[]
    rg::BufferHandle materials; // GpuMaterial[]
    rg::BufferHandle lights;    // GpuLight[]
    rg::ImageHandle textures;   // base-colour texture array (sampled)
};

struct GBufferData {
    rg::ImageHandle depth;
    rg::ImageHandle position;
    rg::ImageHandle normal;
    rg::ImageHandle albedo;
    rg::ImageHandle emission;
};

// Owner of one atlas layer.
struct ShadowLayer {
    uint32_t light = 0; // index into Scene::lights
    uint32_t face = 0;  // cube face (0 for single layers)
    glm::mat4 viewProj{1.0f};
};

struct ShadowData {
    rg::ImageHandle atlas;         // D32 2D array (sampled with compare: ShadowData::compareSampler)
    rg::BufferHandle views;        // GpuShadowView[layer]
    rg::BufferHandle lightShadows; // GpuLightShadow[light]
    uint32_t resolution = 0;
    std::vector<ShadowLayer> layers; // the lights' own layers (cascade and window layers follow them)
    VkSampler compareSampler = VK_NULL_HANDLE; // linear, depth compare LESS_OR_EQUAL, clamp to edge
    VkSampler pointSampler = VK_NULL_HANDLE;   // nearest, no compare: the stored depths themselves
};

// Present only when the technique asked for it (or GiSettings::forceRsm).
struct RsmData {
    rg::ImageHandle position;
    rg::ImageHandle normal;
    rg::ImageHandle flux;
    uint32_t resolution = 0;
    std::vector<ShadowLayer> layers; // same as ShadowData::layers: never a cascade layer, so each
                                     // light's flux is in the RSM once
};

struct DirectData {
    rg::ImageHandle direct; // RGBA32F radiance: emission + punctual direct light
};

// Written by the technique's passes.
struct IndirectData {
    rg::ImageHandle indirect; // RGBA32F indirect radiance (nits), camera resolution
    rg::ImageHandle ao;       // image whose alpha is the AO visibility in [0, 1] (invalid when not produced)
    rg::ImageHandle glossy;   // RGBA32F glossy cone radiance, nits (invalid when not produced)
};

struct CompositeData {
    rg::ImageHandle final; // RGBA32F direct + indirect
};

} // namespace vkgi::gi
