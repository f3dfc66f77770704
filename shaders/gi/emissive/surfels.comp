#version 460
#extension GL_GOOGLE_include_directive : require
// Emissive surfels (gi/emissive.h): each invocation places one surfel on its triangle as the
// instance is transformed this frame (moving emitters are followed), with the flux
// pi * Le * area * weight of the side it stands for and its area (w). Texels past the surfel count
// are cleared.
#include "engine/scene_types.h"
#include "gi/emissive.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform Push { EmissiveSurfelPush pc; };

layout(set = 1, binding = EMISSIVE_BINDING_VERTICES, std430) readonly buffer Vertices { GpuVertex vertices[]; };
layout(set = 1, binding = EMISSIVE_BINDING_INDICES, std430) readonly buffer Indices { uint indices[]; };
layout(set = 1, binding = EMISSIVE_BINDING_INSTANCES, std430) readonly buffer Instances { GpuInstance instances[]; };
layout(set = 1, binding = EMISSIVE_BINDING_MATERIALS, std430) readonly buffer Materials { GpuMaterial materials[]; };
layout(set = 1, binding = EMISSIVE_BINDING_SURFELS, std430) readonly buffer Surfels { GpuEmissiveSurfel surfels[]; };
layout(set = 1, binding = EMISSIVE_BINDING_POSITION, rgba32f) uniform writeonly image2DArray outPosition;
layout(set = 1, binding = EMISSIVE_BINDING_NORMAL, rgba16f) uniform writeonly image2DArray outNormal;
layout(set = 1, binding = EMISSIVE_BINDING_FLUX, rgba32f) uniform writeonly image2DArray outFlux;

const float kPi = 3.14159265358979;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID.xy, 0);
    uint side = pc.info.y;
    if (texel.x >= int(side) || texel.y >= int(side))
        return;
    uint k = uint(texel.y) * side + uint(texel.x);
    vec4 position = vec4(0.0), normal = vec4(0.0), flux = vec4(0.0);
    if (k < pc.info.x) {
        GpuEmissiveSurfel s = surfels[k];
        GpuInstance inst = instances[s.triangle.x];
        uint first = inst.info.y + 3u * s.triangle.y;
        uint base = inst.info.w;
        vec3 v0 = (inst.model * vec4(vertices[base + indices[first]].positionU.xyz, 1.0)).xyz;
        vec3 v1 = (inst.model * vec4(vertices[base + indices[first + 1u]].positionU.xyz, 1.0)).xyz;
        vec3 v2 = (inst.model * vec4(vertices[base + indices[first + 2u]].positionU.xyz, 1.0)).xyz;
        vec3 c = cross(v1 - v0, v2 - v0);
        float twiceArea = length(c);
        // The front side is counter-clockwise in object space, as for the path tracer: a mirroring
        // transform turns the world-space winding around.
        float mirrored = determinant(mat3(inst.model)) < 0.0 ? -1.0 : 1.0;
        float facing = s.triangle.z == 0u ? mirrored : -mirrored;
        if (twiceArea > 0.0 && twiceArea < 1e30) {
            // Uniform on the triangle: b0 = 1 - sqrt(u), b1 = v sqrt(u).
            float su = sqrt(s.point.x);
            vec3 p = v0 * (1.0 - su) + v1 * (s.point.y * su) + v2 * (su - s.point.y * su);
            vec3 le = materials[inst.info.x].emission.rgb;
            position = vec4(p, 1.0);
            normal = vec4(c * (facing / twiceArea), 0.0);
            float area = 0.5 * twiceArea * s.point.z;
            flux = vec4(kPi * le * area, area);
        }
    }
    imageStore(outPosition, texel, position);
    imageStore(outNormal, texel, normal);
    imageStore(outFlux, texel, flux);
}
