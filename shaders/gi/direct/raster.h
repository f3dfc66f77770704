// Vertex pulling shared by raster.vert and rsm.vert (GLSL only): rasterVertex() reads the
// vertex, instance and material, writes the interface below and gl_Position.
#ifndef VKGI_GI_DIRECT_RASTER_H
#define VKGI_GI_DIRECT_RASTER_H
#include "engine/scene_types.h"
#include "gi/direct_types.h"

layout(push_constant) uniform PushBlock { RasterPush pc; };
layout(set = 1, binding = DIRECT_RASTER_BINDING_VERTICES, std430) readonly buffer Vertices { GpuVertex vertices[]; };
layout(set = 1, binding = DIRECT_RASTER_BINDING_INSTANCES, std430) readonly buffer Instances { GpuInstance instances[]; };
layout(set = 1, binding = DIRECT_RASTER_BINDING_MATERIALS, std430) readonly buffer Materials { GpuMaterial materials[]; };

layout(location = 0) out vec3 outPosition;
layout(location = 1) out vec3 outNormal;
layout(location = 2) out vec2 outUv;
layout(location = 3) flat out uint outMaterial;
// The instance's material (surface.h), read per vertex: lavapipe loads a storage buffer
// separately for every lane, so a per-fragment read costs far more.
layout(location = 4) flat out vec4 outBaseColor;
layout(location = 5) flat out vec4 outEmission;
layout(location = 6) flat out vec4 outMaterialParams;

void rasterVertex() {
    GpuVertex v = vertices[gl_VertexIndex];
    GpuInstance inst = instances[pc.info.x];
    vec4 world = inst.model * vec4(v.positionU.xyz, 1.0);
    outPosition = world.xyz;
    outNormal = mat3(inst.normalModel) * v.normalV.xyz;
    outUv = vec2(v.positionU.w, v.normalV.w);
    outMaterial = inst.info.x;
    GpuMaterial m = materials[inst.info.x];
    outBaseColor = m.baseColor;
    outEmission = m.emission;
    outMaterialParams = m.params;
    gl_Position = pc.viewProj * world;
}
#endif
