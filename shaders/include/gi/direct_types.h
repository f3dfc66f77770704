// Layouts shared by the direct-lighting passes (G-buffer, shadow/RSM, deferred, composite) in
// C++ and GLSL, plus the shadow-map tables that GI techniques read together with the RSM.
#ifndef VKGI_GI_DIRECT_TYPES_H
#define VKGI_GI_DIRECT_TYPES_H
#include "../shared/bridge.h"

// Bindings (set 1).
// Rasterising passes (raster.vert and rsm.vert through raster.h; gbuffer.frag and rsm.frag
// through surface.h). The shadow-only pipeline declares the first three.
#define DIRECT_RASTER_BINDING_VERTICES 0  // scene vertices (GpuVertex), pulled by gl_VertexIndex
#define DIRECT_RASTER_BINDING_INSTANCES 1 // scene instances (GpuInstance), indexed by RasterPush info.x
#define DIRECT_RASTER_BINDING_MATERIALS 2 // scene materials (GpuMaterial), read per vertex
#define DIRECT_RASTER_BINDING_TEXTURES 3  // base-colour textures (2D array, sampled by the fragment shaders)
#define DIRECT_RASTER_BINDING_LIGHTS 4    // scene lights (GpuLight), read by rsm.vert only
// Deferred direct lighting (deferred.comp).
#define DIRECT_DEFERRED_BINDING_POSITION 0      // G-buffer world position (RGBA32F, w = 1 where geometry)
#define DIRECT_DEFERRED_BINDING_NORMAL 1        // G-buffer normal + roughness (RGBA16F)
#define DIRECT_DEFERRED_BINDING_ALBEDO 2        // G-buffer albedo + metallic (RGBA16F)
#define DIRECT_DEFERRED_BINDING_EMISSION 3      // G-buffer emission (RGBA32F)
#define DIRECT_DEFERRED_BINDING_LIGHTS 4        // scene lights (GpuLight)
#define DIRECT_DEFERRED_BINDING_LIGHT_SHADOWS 5 // atlas layers of each light (GpuLightShadow)
#define DIRECT_DEFERRED_BINDING_SHADOW_VIEWS 6  // one GpuShadowView per atlas layer
#define DIRECT_DEFERRED_BINDING_SHADOW_ATLAS 7  // shadow atlas (2D-array depth) with a point sampler
#define DIRECT_DEFERRED_BINDING_OUTPUT 8        // direct radiance (RGBA32F)
// Composite (composite.comp).
#define DIRECT_COMPOSITE_BINDING_DIRECT 0   // direct radiance (RGBA32F)
#define DIRECT_COMPOSITE_BINDING_INDIRECT 1 // the technique's indirect radiance (RGBA32F)
#define DIRECT_COMPOSITE_BINDING_OUTPUT 2   // their sum (RGBA32F)
// Host G-buffer path (host_position.comp).
#define DIRECT_HOST_POSITION_BINDING_DEPTH 0  // the host's depth (D32) with a point sampler
#define DIRECT_HOST_POSITION_BINDING_OUTPUT 1 // reconstructed world position (RGBA32F)

GI_NAMESPACE_BEGIN

// Push constants of every rasterising pass (G-buffer, shadow map, RSM): one vertex shader.
GI_GPU_STRUCT(RasterPush) {
    mat4 viewProj; // world -> clip of the camera or of one shadow-map layer
    vec4 eye;      // xyz camera or light position; w = linear-depth far distance (0 = orthographic)
    vec4 axisArea; // xyz light axis of this layer (unit); w = texel area (see GpuShadowView)
    uvec4 info;    // x instance, y light index, z shadow layer, w 0
};
GI_CHECK_SIZE(RasterPush, 112);

// One layer of the shadow atlas (a 2D-array depth image shared by all lights; a cube is 6
// layers). Depth is stored linearly: perspective layers store distance(light, p) / eye.w,
// orthographic layers the clip z of `viewProj`, which is linear in the distance along the axis.
GI_GPU_STRUCT(GpuShadowView) {
    mat4 viewProj; // world -> clip
    vec4 eye;      // xyz light position (perspective) or the ortho box's near-plane centre; w = far (0 = ortho)
    vec4 axisArea; // xyz unit axis the layer looks along; w = texel area: on the plane at unit distance
                   // (perspective, steradians at the axis) or in world m^2 perpendicular to the light (ortho)
    vec4 texel;    // x world texel size per metre of distance (perspective) or in metres (ortho);
                   // y metres per unit of stored depth (far or ortho depth range); z resolution; w 0
};
GI_CHECK_SIZE(GpuShadowView, 112);

#define GI_SHADOW_NONE 0u
#define GI_SHADOW_SINGLE 1u // one perspective (spot) or orthographic (directional) layer
#define GI_SHADOW_CUBE 2u   // six layers in the order +X, -X, +Y, -Y, +Z, -Z

// Which atlas layers belong to a light: info x first layer, y layer count, z GI_SHADOW_* kind.
// Every consumer that samples the atlas at arbitrary points (voxel light, VPLs) reads `info`.
// `cascades` (directional lights; 0 for point and spot lights), all shadow-only layers with no
// RSM: x first cascade layer, y cascade count (0 = none), finest first, fitted to this frame's
// camera and read by the deferred pass only; z first shadow-window layer, w window count
// (0 = none): window k (TechniqueModule::shadowWindows, finest first) is layer z + k for k < w,
// fitted to that box (its x, y on whole texels, its depth from the scene's nearest point toward
// the light to the box's far side); a box k >= w reads the light's own layer (`info`).
GI_GPU_STRUCT(GpuLightShadow) {
    uvec4 info;
    uvec4 cascades;
};
GI_CHECK_SIZE(GpuLightShadow, 32);

// Deferred direct lighting (compute over the G-buffer).
GI_GPU_STRUCT(DeferredPush) {
    uvec4 size;   // x width, y height, z light count, w PCF radius in texels
    vec4 bias;    // x normal offset, y depth bias (both in shadow texels at the receiver), zw unused
};
GI_CHECK_SIZE(DeferredPush, 32);

// Composite: final = direct + indirect.
GI_GPU_STRUCT(CompositePush) {
    uvec4 size; // x width, y height
};
GI_CHECK_SIZE(CompositePush, 16);

// Host G-buffer path: world position reconstructed from the host's depth.
GI_GPU_STRUCT(HostPositionPush) {
    mat4 invViewProj; // clip -> world of the frame's camera
    uvec4 size;       // x width, y height
};
GI_CHECK_SIZE(HostPositionPush, 80);

// Cube face of a direction from the light: +X, -X, +Y, -Y, +Z, -Z = 0..5 (major axis).
GI_INLINE uint cubeFace(vec3 d) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z)
        return d.x >= 0.0 ? 0u : 1u;
    if (a.y >= a.z)
        return d.y >= 0.0 ? 2u : 3u;
    return d.z >= 0.0 ? 4u : 5u;
}

// Reflected flux of one RSM texel (see docs in gi/include/vkgi/frame_data.hpp):
// perspective: albedo * I * attenuation * dOmega, dOmega = texelArea * cos^3(angle to the axis);
// orthographic: albedo * E * texelArea (area perpendicular to the light).
GI_INLINE float rsmTexelSolidAngle(float planeTexelArea, float cosToAxis) {
    return planeTexelArea * cosToAxis * cosToAxis * cosToAxis;
}

GI_NAMESPACE_END
#endif
