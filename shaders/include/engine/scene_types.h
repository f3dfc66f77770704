// GPU scene layouts shared by C++ (engine/gpu_scene) and GLSL (rasteriser, voxelizer, RSM).
// std430 in storage buffers; vec4-only fields so both sides agree without padding rules.
#ifndef VKGI_ENGINE_SCENE_TYPES_H
#define VKGI_ENGINE_SCENE_TYPES_H
#include "../shared/bridge.h"
// Light types: GI_LIGHT_* in lights.h (= vkgi::LightType).

GI_NAMESPACE_BEGIN

// Object-space vertex; uv packed into the w components.
GI_GPU_STRUCT(GpuVertex) {
    vec4 positionU; // xyz position, w = u
    vec4 normalV;   // xyz normal (unit), w = v
};
GI_CHECK_SIZE(GpuVertex, 32);

// Material: Lambertian albedo = baseColor (x texture), emission in nits.
GI_GPU_STRUCT(GpuMaterial) {
    vec4 baseColor; // linear RGBA factor
    vec4 emission;  // rgb nits (emissiveFactor * emissiveStrength), w = 0
    vec4 params;    // x metallic, y roughness, z texture layer in the base-colour array (-1 = none), w doubleSided
};
GI_CHECK_SIZE(GpuMaterial, 48);

// One placed mesh: transforms plus where its triangles live in the shared buffers.
GI_GPU_STRUCT(GpuInstance) {
    mat4 model;       // object -> world
    mat4 normalModel; // inverse-transpose of model (for normals)
    uvec4 info;       // x material, y first index, z index count, w vertex offset
};
GI_CHECK_SIZE(GpuInstance, 144);
GI_CHECK_OFFSET(GpuInstance, info, 128);

// Punctual light in KHR_lights_punctual units (cd for point/spot, lux for directional).
GI_GPU_STRUCT(GpuLight) {
    vec4 positionType;   // xyz world position, w = GI_LIGHT_* type
    vec4 directionRange; // xyz unit direction the light shines along, w = range (0 = infinite)
    vec4 colorIntensity; // rgb linear colour, w = intensity
    vec4 cone;           // x cos(inner), y cos(outer) (spot only), z = w = 0
};
GI_CHECK_SIZE(GpuLight, 64);

#define GI_SCENE_TEXTURE_SIZE 256u

GI_NAMESPACE_END
#endif
