#version 460
#extension GL_GOOGLE_include_directive : require
// Once per voxelization: appends every occupied voxel to the occupied-voxel list (header =
// indirect dispatch arguments, voxel_passes.h) and zeroes both radiance volumes at the empty
// voxels, so the passes that then run over the list alone leave complete volumes behind.
// The list order depends on scheduling; its consumers write per voxel, so results do not.
#include "gi/voxel_passes.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 4) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, rgba8) uniform readonly image3D albedoVol; // a = occupancy
layout(set = 1, binding = 1, std430) buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint voxels[]; };
layout(set = 1, binding = 2, rgba16f) uniform writeonly image3D radianceVol;
layout(set = 1, binding = 3, rgba16f) uniform writeonly image3D bouncedVol;

void main() {
    uvec3 c = gl_GlobalInvocationID;
    if (any(greaterThanEqual(c, uvec3(pc.grid.dims.x))))
        return;
    if (c == uvec3(0u)) {
        header[1] = 1u; // dispatch y, z (the clear pass zeroed the header)
        header[2] = 1u;
    }
    if (imageLoad(albedoVol, ivec3(c)).a == 0.0) {
        imageStore(radianceVol, ivec3(c), vec4(0.0));
        imageStore(bouncedVol, ivec3(c), vec4(0.0));
        return;
    }
    uint slot = atomicAdd(header[3], 1u);
    voxels[slot] = voxelListPack(c);
    // The first voxel of each group of GI_VOXEL_LIST_GROUP adds that group: x = ceil(count / group).
    if (slot % GI_VOXEL_LIST_GROUP == 0u)
        atomicAdd(header[0], 1u);
}
