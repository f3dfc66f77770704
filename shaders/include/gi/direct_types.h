// Layouts shared by the direct-lighting passes (G-buffer, shadow/RSM, deferred, composite) in
// C++ and GLSL, plus the shadow-map tables that GI techniques read together with the RSM.
#ifndef VKGI_GI_DIRECT_TYPES_H
#define VKGI_GI_DIRECT_TYPES_H
#include "../shared/bridge.h"

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

// Which atlas layers belong to a light: x first layer, y layer count, z GI_SHADOW_* kind.
GI_GPU_STRUCT(GpuLightShadow) {
    uvec4 info;
};
GI_CHECK_SIZE(GpuLightShadow, 16);

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

// Reflected flux of one RSM texel (see docs in gi/include/gi/frame_data.hpp):
// perspective: albedo * I * attenuation * dOmega, dOmega = texelArea * cos^3(angle to the axis);
// orthographic: albedo * E * texelArea (area perpendicular to the light).
GI_INLINE float rsmTexelSolidAngle(float planeTexelArea, float cosToAxis) {
    return planeTexelArea * cosToAxis * cosToAxis * cosToAxis;
}

GI_NAMESPACE_END
#endif
