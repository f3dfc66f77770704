#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, gather half: each occupied 2^3 block gathers the first-bounce radiance with
// the diffuse cones over the hemisphere of its mean normal, from its centre (so the first
// cone sample, 2 voxels out, clears the block's own surface voxels as it does a voxel's).
// Surface voxels come in 2D sheets, so blocks are about a quarter of them; the cones are 30
// degrees wide and their first sample is already 2 voxels across, so the gather changes little
// over a block. voxel_bounce_apply.comp adds it to the voxels (or gathers per voxel where the
// block's mean normal does not fit).
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per occupied block (indirect)
layout(push_constant) uniform Push { VoxelBouncePush pc; };
#include "voxel_cone.glsl"
layout(set = 1, binding = 2, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = 3, rgba16f) uniform writeonly image3D gatheredOut; // (N/2)^3: (1/n) sum L_i
layout(set = 1, binding = 4, std430) readonly buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };
#include "voxel_block.glsl"

void main() {
    if (gl_GlobalInvocationID.x >= header[GI_VOXEL_LIST_BLOCKS + 3u])
        return;
    uint n = pc.grid.dims.x;
    ivec3 b = ivec3(voxelListUnpack(entries[n * n * n + gl_GlobalInvocationID.x]));
    vec3 normal = blockNormal(b);
    if (normal == vec3(0.0)) {
        imageStore(gatheredOut, b, vec4(0.0));
        return;
    }
    float occlusion;
    vec3 gathered = diffuseGather(vec3(2 * b + 1) + normal, normal, pc.cones, float(n), occlusion);
    imageStore(gatheredOut, b, vec4(gathered, 1.0));
}
