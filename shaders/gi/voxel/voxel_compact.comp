#version 460
#extension GL_GOOGLE_include_directive : require
// Once per voxelization: appends every occupied voxel and every 2^3 block holding one to the
// occupied lists (headers = indirect dispatch arguments, voxel_passes.h). Level 0 of the
// directional volume is cleared by a transfer before, so the passes that then run over the
// list alone leave a complete level 0 behind.
// The list order depends on scheduling; its consumers write per voxel, so results do not.
#include "gi/voxel_passes.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 4) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, rgba8) uniform readonly image3D albedoVol; // a = occupancy
layout(set = 1, binding = 1, std430) buffer List { uint header[GI_VOXEL_LIST_HEADER]; uint entries[]; };

void main() {
    uvec3 c = gl_GlobalInvocationID;
    if (any(greaterThanEqual(c, uvec3(pc.grid.dims.x))))
        return;
    uint n = pc.grid.dims.x;
    if (c == uvec3(0u)) {
        header[1] = header[2] = 1u; // dispatch y, z (the clear pass zeroed the header)
        header[GI_VOXEL_LIST_BLOCKS + 1u] = header[GI_VOXEL_LIST_BLOCKS + 2u] = 1u;
    }
    if (all(equal(c & 1u, uvec3(0u)))) { // the block's first voxel lists the block
        bool any8 = false;
        for (int i = 0; i < 8; ++i)
            any8 = any8 || imageLoad(albedoVol, ivec3(c) + ivec3(i & 1, (i >> 1) & 1, i >> 2)).a > 0.0;
        if (any8) {
            uint slot = atomicAdd(header[GI_VOXEL_LIST_BLOCKS + 3u], 1u);
            entries[n * n * n + slot] = voxelListPack(c >> 1u);
            if (slot % GI_VOXEL_LIST_GROUP == 0u)
                atomicAdd(header[GI_VOXEL_LIST_BLOCKS], 1u);
        }
    }
    if (imageLoad(albedoVol, ivec3(c)).a == 0.0)
        return;
    uint slot = atomicAdd(header[3], 1u);
    entries[slot] = voxelListPack(c);
    // The first voxel of each group of GI_VOXEL_LIST_GROUP adds that group: x = ceil(count / group).
    if (slot % GI_VOXEL_LIST_GROUP == 0u)
        atomicAdd(header[0], 1u);
}
