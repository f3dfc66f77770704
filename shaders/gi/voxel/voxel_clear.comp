#version 460
#extension GL_GOOGLE_include_directive : require
// Zeroes the fixed-point accumulation image (N x N x N*channels) before a voxelization.
#include "gi/voxel_passes.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 4) in;
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, r32ui) uniform writeonly uimage3D accum;

void main() {
    uvec3 p = gl_GlobalInvocationID;
    uint n = pc.grid.dims.x;
    if (any(greaterThanEqual(p, uvec3(n, n, n * GI_VOXEL_ACC_CHANNELS))))
        return;
    imageStore(accum, ivec3(p), uvec4(0u));
}
