#version 460
#extension GL_GOOGLE_include_directive : require
// Second bounce, job list: per 4^3 block, the classes of its voxels' normals (voxel_block.glsl)
// -> the block's class mask and one job per class, appended to that class's list, and the
// gathers' indirect dispatch (gi/voxel_passes.h). The order within a class's list follows the
// scheduling; each gather depends only on its block and class and stores its result at them,
// so the images do not.
#include "gi/voxel_passes.h"

layout(local_size_x = GI_VOXEL_LIST_GROUP) in; // one invocation per 4^3 block of the grid
layout(push_constant) uniform Push { VoxelGridPush pc; };
layout(set = 1, binding = 0, rgba8) uniform readonly image3D normalVol;
layout(set = 1, binding = 1, std430) readonly buffer List { uint listHeader[GI_VOXEL_LIST_HEADER]; uint entries[]; };
layout(set = 1, binding = 2, std430) buffer Jobs { uint header[GI_BOUNCE_HEADER]; uint words[]; };
#include "voxel_block.glsl"

void main() {
    uint n = pc.grid.dims.x, quarter = n / 4u;
    uint b = gl_GlobalInvocationID.x;
    if (b == 0u) { // dispatch y, z of both quads (the clear zeroed the header)
        header[1] = GI_BOUNCE_CLASSES;
        header[2] = header[GI_BOUNCE_MISFITS + 1u] = header[GI_BOUNCE_MISFITS + 2u] = 1u;
    }
    if (b >= bounceBlockCount(n))
        return;
    if ((entries[voxelListCoarseBitsOffset(n) + (b >> 5u)] & (1u << (b & 31u))) == 0u) {
        words[b] = 0u; // no classes (the apply reads the masks of neighbouring blocks)
        return;
    }
    uvec3 q = uvec3(b % quarter, (b / quarter) % quarter, b / (quarter * quarter));
    uint mask = 0u;
    for (int i = 0; i < 64; ++i) {
        vec3 normal;
        uint k;
        if (voxelNormalOf(4 * ivec3(q) + ivec3(i & 3, (i >> 2) & 3, i >> 4), normal, k))
            mask |= 1u << k;
    }
    words[b] = mask;
    while (mask != 0u) {
        uint k = uint(findLSB(mask));
        mask &= mask - 1u;
        uint slot = atomicAdd(header[GI_BOUNCE_COUNTS + k], 1u);
        if (slot % GI_VOXEL_LIST_GROUP == 0u) // x = ceil(largest count / group)
            atomicMax(header[0], slot / GI_VOXEL_LIST_GROUP + 1u);
        words[bounceJobOffset(n) + k * bounceBlockCount(n) + slot] = b;
    }
}
