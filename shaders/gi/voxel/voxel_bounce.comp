#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce in the voxels: each occupied voxel with a normal gathers the first-bounce
// radiance with the diffuse cones over its hemisphere and adds albedo * E / pi to its own
// radiance (so the per-pixel gather then sees emission + one bounce + two bounces).
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per occupied voxel (indirect)
layout(push_constant) uniform Push { VoxelBouncePush pc; };
#include "voxel_cone.glsl"
layout(set = 1, binding = 2, rgba8) uniform readonly image3D albedoVol;
layout(set = 1, binding = 3, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = 4, rgba16f) uniform writeonly image3D radianceOut;
layout(set = 1, binding = 5, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint voxels[]; };

void main() {
    if (gl_GlobalInvocationID.x >= header[3])
        return;
    ivec3 c = ivec3(voxelListUnpack(voxels[gl_GlobalInvocationID.x]));
    float n = float(pc.grid.dims.x);
    vec4 own = texelFetch(radianceVol, c, 0);
    vec4 albedo = imageLoad(albedoVol, c);
    vec3 normal = voxelNormalDecode(imageLoad(normalVol, c).xyz);
    if (dot(normal, normal) < 0.25) {
        // Normals that cancel: no hemisphere to gather over (kept as is).
        imageStore(radianceOut, c, own);
        return;
    }
    normal = normalize(normal);
    float occlusion;
    vec3 gathered = diffuseGather(vec3(c) + 0.5 + normal, normal, pc.cones, n, occlusion);
    imageStore(radianceOut, c, vec4(min(own.rgb + albedo.rgb * gathered, vec3(65000.0)), own.a));
}
